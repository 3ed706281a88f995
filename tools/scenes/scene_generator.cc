// Scene generator: a tiny deterministic ray caster (see scene_generator.h for the contract).
//
// World frame: metres, z up, the table is the plane z = 0, optional back wall x = wall_x.
// Camera: x_cam ~ K (R X + t), R's rows are the camera's right, down and forward axes in world
// coordinates, t = -R pos. The ray of image point (u, v) is pos + s D with
// D = forward + right (u - pcx) / f + down (v - pcy) / f (not normalised: s = 1 at depth 1).
#include "tools/scenes/scene_generator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <initializer_list>
#include <functional>
#include <string>
#include <utility>
#include <limits>
#include <system_error>

#include <opencv2/imgcodecs.hpp>

#include "tools/scenes/conic.h"
#include "tools/scenes/rng.h"

namespace ellipsekit::scenes {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();

// ---------------------------------------------------------------- small vector maths
struct V3 {
  double x = 0, y = 0, z = 0;
};
inline V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline V3 operator*(V3 a, double k) { return {a.x * k, a.y * k, a.z * k}; }
inline double Dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline V3 Cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline V3 Normalize(V3 a) { return a * (1.0 / std::sqrt(Dot(a, a))); }
inline double Clamp(double v, double lo, double hi) { return v < lo ? lo : (v > hi ? hi : v); }
inline double Smoothstep(double e0, double e1, double x) {
  const double t = Clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

struct IRect {  // inclusive pixel rectangle
  int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
  bool Contains(int x, int y) const { return x >= x0 && x <= x1 && y >= y0 && y <= y1; }
};

struct Camera {
  double f = 600, pcx = 0, pcy = 0;
  V3 pos, right, down, fwd;

  V3 Ray(double u, double v) const { return fwd + right * ((u - pcx) / f) + down * ((v - pcy) / f); }
  bool Project(V3 p, double* u, double* v) const {
    const V3 d = p - pos;
    const double zc = Dot(d, fwd);
    if (zc <= 1e-3) return false;
    *u = pcx + f * Dot(d, right) / zc;
    *v = pcy + f * Dot(d, down) / zc;
    return true;
  }
  cv::Matx33d K() const { return cv::Matx33d(f, 0, pcx, 0, f, pcy, 0, 0, 1); }
  cv::Matx33d R() const {
    return cv::Matx33d(right.x, right.y, right.z, down.x, down.y, down.z, fwd.x, fwd.y, fwd.z);
  }
  cv::Vec3d T() const { return -(R() * cv::Vec3d(pos.x, pos.y, pos.z)); }
  // T_world_camera: camera coordinates to world coordinates.
  cv::Matx44d WorldFromCamera() const {
    return cv::Matx44d(right.x, down.x, fwd.x, pos.x,  //
                       right.y, down.y, fwd.y, pos.y,  //
                       right.z, down.z, fwd.z, pos.z,  //
                       0, 0, 0, 1);
  }
};

// Image bounding rectangle (expanded by `pad` px, clipped to the image) of a set of world points;
// the whole image when a point is behind the camera.
IRect ProjectBounds(const Camera& cam, const V3* pts, int n, int width, int height, int pad = 2) {
  double u0 = kInf, v0 = kInf, u1 = -kInf, v1 = -kInf;
  for (int i = 0; i < n; ++i) {
    double u, v;
    if (!cam.Project(pts[i], &u, &v)) return IRect{0, 0, width - 1, height - 1};
    u0 = std::min(u0, u);
    v0 = std::min(v0, v);
    u1 = std::max(u1, u);
    v1 = std::max(v1, v);
  }
  IRect r;
  r.x0 = static_cast<int>(std::floor(Clamp(u0, -1e6, 1e6))) - pad;
  r.y0 = static_cast<int>(std::floor(Clamp(v0, -1e6, 1e6))) - pad;
  r.x1 = static_cast<int>(std::ceil(Clamp(u1, -1e6, 1e6))) + pad;
  r.y1 = static_cast<int>(std::ceil(Clamp(v1, -1e6, 1e6))) + pad;
  r.x0 = std::max(r.x0, 0);
  r.y0 = std::max(r.y0, 0);
  r.x1 = std::min(r.x1, width - 1);
  r.y1 = std::min(r.y1, height - 1);
  return r;
}

// Axis-aligned rectangle on the table (world x, y).
struct TRect {
  double x0 = kInf, y0 = kInf, x1 = -kInf, y1 = -kInf;
  void Add(double x, double y) {
    x0 = std::min(x0, x);
    y0 = std::min(y0, y);
    x1 = std::max(x1, x);
    y1 = std::max(y1, y);
  }
  void Grow(double d) {
    x0 -= d;
    y0 -= d;
    x1 += d;
    y1 += d;
  }
  bool Contains(double x, double y) const { return x >= x0 && x <= x1 && y >= y0 && y <= y1; }
};

IRect ProjectTableRect(const Camera& cam, const TRect& t, int width, int height) {
  const V3 pts[4] = {{t.x0, t.y0, 0}, {t.x1, t.y0, 0}, {t.x0, t.y1, 0}, {t.x1, t.y1, 0}};
  return ProjectBounds(cam, pts, 4, width, height);
}

// ---------------------------------------------------------------- scene contents
enum class CylKind { kCan, kCup, kJar };

struct Cylinder {
  CylKind kind = CylKind::kCan;
  double x = 0, y = 0, r = 0.03, h = 0.1, r2 = 0;
  double r_in = 0, r_in2 = 0, z_floor = 0;  // cup: inner radius, inner floor height
  double side_albedo = 0.5;
  double top_albedo = 0.5;    // lid (can, jar) or lip (cup)
  bool has_rim = false;       // a ring of rim_albedo on the top, rim_width wide
  double rim_albedo = 0.5, rim_width = 0.003;
  double inner_albedo = 0.4;  // cup interior
  bool has_label = false;
  double label_z0 = 0, label_z1 = 0, label_albedo = 0.5;
  bool has_print = false;
  V3 print_dir;
  double print_cos = 1, print_albedo = 0.5;
  bool has_neck = false;
  double neck_width = 0, neck_albedo = 0.5;
  double spec = 0, shininess = 10;
  double top_scale = 1;  // contrast fix: multiplies every top-related albedo
  IRect bbox;
  TRect shadow;
  IRect shadow_bbox;
  ellipsekit::Ellipse truth;
};

// The sequence cans' derived shape from r: r^2, the inner radius 3 mm in, the inner floor height.
void SetCanShape(Cylinder* c) {
  c->r2 = c->r * c->r;
  c->r_in = c->r - 0.003;
  c->r_in2 = c->r_in * c->r_in;
  c->z_floor = 0.01;
}

// What a moving cylinder changes in a frame: its bounding box and its shadow's (when not empty).
IRect RedrawRect(const Cylinder& c) {
  IRect r = c.bbox;
  if (c.shadow_bbox.x1 >= c.shadow_bbox.x0 && c.shadow_bbox.y1 >= c.shadow_bbox.y0) {
    r.x0 = std::min(r.x0, c.shadow_bbox.x0);
    r.y0 = std::min(r.y0, c.shadow_bbox.y0);
    r.x1 = std::max(r.x1, c.shadow_bbox.x1);
    r.y1 = std::max(r.y1, c.shadow_bbox.y1);
  }
  return r;
}

struct Box {
  double x = 0, y = 0, c = 1, s = 0, hx = 0.05, hy = 0.05, hz = 0.05, bound_r = 0;
  double albedo = 0.5;
  bool has_print = false;
  double print_hx = 0, print_hy = 0, print_albedo = 0.5;
  IRect bbox;
  TRect shadow;
  IRect shadow_bbox;
};

enum class ShapeKind { kPolygon, kRect, kStripes, kBlob, kLine };

struct Shape {
  ShapeKind kind = ShapeKind::kRect;
  double albedo = 0.5;
  TRect area;
  double cx = 0, cy = 0, c = 1, s = 0, hx = 0, hy = 0;  // rect, stripes, blob centre
  double period = 0.01, duty = 0.5;                     // stripes
  std::vector<double> px, py;                           // polygon
  std::array<double, 256> blob_r{};                     // blob radius per angle
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0, half_w = 0;    // line

  bool Inside(double X, double Y) const {
    switch (kind) {
      case ShapeKind::kRect:
      case ShapeKind::kStripes: {
        const double dx = X - cx, dy = Y - cy;
        const double lx = dx * c + dy * s, ly = -dx * s + dy * c;
        if (std::abs(lx) > hx || std::abs(ly) > hy) return false;
        if (kind == ShapeKind::kRect) return true;
        const double w = (lx + hx) / period;
        return w - std::floor(w) < duty;
      }
      case ShapeKind::kPolygon: {
        bool in = false;
        const size_t n = px.size();
        for (size_t i = 0, j = n - 1; i < n; j = i++) {
          if ((py[i] > Y) != (py[j] > Y) && X < (px[j] - px[i]) * (Y - py[i]) / (py[j] - py[i]) + px[i]) in = !in;
        }
        return in;
      }
      case ShapeKind::kBlob: {
        const double dx = X - cx, dy = Y - cy;
        const double t = (std::atan2(dy, dx) + kPi) * (256.0 / (2 * kPi));
        int i0 = static_cast<int>(t);
        const double w = t - i0;
        i0 &= 255;
        const double r = blob_r[i0] * (1 - w) + blob_r[(i0 + 1) & 255] * w;
        return dx * dx + dy * dy <= r * r;
      }
      case ShapeKind::kLine: {
        const double vx = x1 - x0, vy = y1 - y0;
        const double t = Clamp(((X - x0) * vx + (Y - y0) * vy) / (vx * vx + vy * vy), 0.0, 1.0);
        const double ex = X - (x0 + t * vx), ey = Y - (y0 + t * vy);
        return ex * ex + ey * ey <= half_w * half_w;
      }
    }
    return false;
  }
};

enum class TableKind { kWood, kMottled, kPlain };

enum Part : int { kBackground, kTable, kWall, kSide, kTop, kInner, kFloor, kBoxFace };

struct Hit {
  double s = kInf;
  int part = kBackground;
  int obj = -1;
  V3 p;
  V3 n;
  double rho2 = 0;  // top: squared distance from the axis
};

// Per-pixel cache of the (smooth) table/wall texture, evaluated once at the pixel's centre ray.
struct TexCache {
  bool table_ok = false, wall_ok = false;
  double table = 0, wall = 0;
};

class World {
 public:
  World(const SceneOptions& o, std::uint64_t seed) : opt_(o), rng_(seed), W_(o.width), H_(o.height) {}

  Scene Build();
  // A conveyor sequence in this world (see scene_generator.h).
  ellipsekit::Status BuildConveyor(const ConveyorSceneOptions& co, std::uint64_t seed, ConveyorSequence* info,
                                   const std::function<ellipsekit::Status(const ConveyorFrame&)>& sink);
  // Two cans, static or crossing (see scene_generator.h, CanSceneOptions).
  ellipsekit::Status BuildCans(const CanSceneOptions& co, std::uint64_t seed, CanSequence* info,
                               const std::function<ellipsekit::Status(const CanFrame&)>& sink);

 private:
  // setup
  void SetupCamera();
  void SetupLightAndSurfaces();
  bool TablePointAt(double u, double v, double z, V3* p) const;
  void PlaceClutter();
  bool PlaceBox();
  bool PlaceShape(ShapeKind kind);
  void PlaceCylinders();
  void ColorCylinder(Cylinder* c);
  bool ComputeTruth(Cylinder* c) const;
  void FinishCylinderBounds(Cylinder* c) const;
  bool TopFitsAt(Cylinder c, double x, double y) const;
  bool MoveTopTo(const cv::Vec3d& top, Cylinder* c) const;
  V3 RandomRowDirection(double max_deg);
  double RimVisibleFraction(int i, bool stop_early_below, double thr) const;
  void FixContrast();
  double ContrastPassFraction(int i) const;

  // ray casting
  bool IntersectCylinder(const Cylinder& c, V3 D, double s_max, Hit* h) const;
  bool IntersectBox(const Box& b, V3 O, V3 D, double s_max, Hit* h) const;
  void Trace(V3 D, int px, int py, Hit* h) const;
  bool OccludedBefore(V3 D, double s_max, int px, int py, int skip_cyl) const;
  double Shade(const Hit& h, V3 D, V3 D_centre, TexCache* tc) const;
  double ShadeAt(double u, double v) const;
  double TableTexture(double X, double Y, double footprint) const;
  double WallTexture(double Y, double Z) const;
  double TableLit(V3 P) const;
  double CupLit(const Cylinder& c, V3 P) const;
  double Noise(double x, double y) const;
  double Vignette(double u, double v) const;

  float RenderPixel(int x, int y) const;
  void Render(std::vector<float>* img) const;
  void RenderRect(const IRect& r, std::vector<float>* img) const;  // img already W_ x H_
  void RenderDepth(const IRect& r, std::vector<double>* z) const;   // z of the first hit, 0 = none
  void Finish(const std::vector<float>& img, cv::Mat* gray);

  SceneOptions opt_;
  Rng rng_;
  int W_, H_;
  Camera cam_;
  V3 light_;
  double ambient_ = 0.3, diffuse_ = 0.7, gain_ = 1, vignette_ = 0.1;
  bool has_wall_ = false;
  double wall_x_ = kInf, wall_albedo_ = 0.5, background_ = 80;
  TableKind table_kind_ = TableKind::kWood;
  double table_base_ = 0.5, grain_contrast_ = 0.2, noise_contrast_ = 0.1, grain_period_ = 0.02, grain_warp_ = 1;
  double grain_c_ = 1, grain_s_ = 0, speck_ = 0.05, illum_var_ = 0.1;
  double penumbra_ = 0.02;
  std::vector<float> lattice_;
  std::vector<Cylinder> cyl_;
  std::vector<Box> box_;
  std::vector<Shape> shape_;
  bool no_boxes_ = false;  // conveyor worlds: flat clutter only
};

// ---------------------------------------------------------------- setup
void World::SetupCamera() {
  const double tilt = rng_.Uniform(opt_.min_tilt_deg, opt_.max_tilt_deg) * kPi / 180;
  const double yaw = rng_.Uniform(-10, 10) * kPi / 180;
  const double roll = rng_.Uniform(-4, 4) * kPi / 180;
  cam_.f = rng_.Uniform(500, 700) * W_ / 640.0;
  cam_.pcx = (W_ - 1) / 2.0;
  cam_.pcy = (H_ - 1) / 2.0;
  cam_.pos = {rng_.Uniform(-0.2, 0.2), rng_.Uniform(-0.2, 0.2), rng_.Uniform(0.35, 0.8)};
  const V3 fwd{std::cos(tilt) * std::cos(yaw), std::cos(tilt) * std::sin(yaw), -std::sin(tilt)};
  const V3 right0{std::sin(yaw), -std::cos(yaw), 0};  // horizontal, perpendicular to fwd
  const V3 down0 = Cross(fwd, right0);                // right x down = fwd (right-handed camera)
  cam_.fwd = fwd;
  cam_.right = right0 * std::cos(roll) + down0 * std::sin(roll);
  cam_.down = down0 * std::cos(roll) - right0 * std::sin(roll);
}

void World::SetupLightAndSurfaces() {
  const double elev = rng_.Uniform(35, 72) * kPi / 180;
  const double az = rng_.Uniform(0, 2 * kPi);
  light_ = {std::cos(elev) * std::cos(az), std::cos(elev) * std::sin(az), std::sin(elev)};
  ambient_ = rng_.Uniform(0.25, 0.42);
  diffuse_ = rng_.Uniform(1.0, 1.1) - ambient_;
  gain_ = rng_.Uniform(0.85, 1.05);
  vignette_ = rng_.Uniform(0.05, 0.3);
  penumbra_ = rng_.Uniform(0.01, 0.04);
  illum_var_ = rng_.Uniform(0.0, 0.25);

  lattice_.resize(256 * 256);
  for (float& v : lattice_) v = static_cast<float>(rng_.Uniform());

  const double pick = rng_.Uniform();
  table_kind_ = pick < 0.5 ? TableKind::kWood : (pick < 0.8 ? TableKind::kMottled : TableKind::kPlain);
  table_base_ = rng_.Uniform(0.22, 0.75);
  grain_contrast_ = rng_.Uniform(0.1, 0.35);
  noise_contrast_ = table_kind_ == TableKind::kPlain ? rng_.Uniform(0.03, 0.08) : rng_.Uniform(0.1, 0.3);
  grain_period_ = rng_.Uniform(0.008, 0.03);
  grain_warp_ = rng_.Uniform(0.5, 2.5);
  const double ga = rng_.Uniform(0, kPi);
  grain_c_ = std::cos(ga);
  grain_s_ = std::sin(ga);
  speck_ = rng_.Uniform(0.0, 0.12);

  // Back wall where the table ends: sometimes in view (its foot at an image row near the top).
  has_wall_ = false;
  wall_x_ = kInf;
  if (rng_.Chance(0.45)) {
    const double row = rng_.Uniform(0.03, 0.3) * H_;
    V3 p;
    if (TablePointAt(cam_.pcx, row, 0, &p) && p.x > cam_.pos.x + 0.3) {
      has_wall_ = true;
      wall_x_ = p.x;
    }
  }
  wall_albedo_ = rng_.Uniform(0.3, 0.85);
  background_ = rng_.Uniform(40, 120);
}

// Where the ray of image point (u, v) meets the horizontal plane at height z (in front of the camera).
bool World::TablePointAt(double u, double v, double z, V3* p) const {
  const V3 D = cam_.Ray(u, v);
  if (D.z >= -1e-9) return false;
  const double s = (z - cam_.pos.z) / D.z;
  if (s <= 0) return false;
  *p = cam_.pos + D * s;
  return true;
}

bool World::PlaceBox() {
  for (int tries = 0; tries < 30; ++tries) {
    Box b;
    V3 p;
    if (!TablePointAt(rng_.Uniform(-0.05, 1.05) * W_, rng_.Uniform(0.0, 1.05) * H_, 0, &p)) continue;
    b.x = p.x;
    b.y = p.y;
    b.hx = rng_.Uniform(0.02, 0.1);
    b.hy = rng_.Uniform(0.02, 0.1);
    b.hz = rng_.Uniform(0.015, 0.1);
    const double a = rng_.Uniform(0, kPi);
    b.c = std::cos(a);
    b.s = std::sin(a);
    b.bound_r = std::hypot(b.hx, b.hy);
    b.albedo = rng_.Uniform(0.1, 0.9);
    b.has_print = rng_.Chance(0.5);
    b.print_hx = b.hx * rng_.Uniform(0.3, 0.8);
    b.print_hy = b.hy * rng_.Uniform(0.3, 0.8);
    b.print_albedo = rng_.Uniform(0.05, 0.95);
    if (has_wall_ && b.x + b.bound_r > wall_x_ - 0.01) continue;
    bool clash = false;
    for (const Box& o : box_) clash |= std::hypot(o.x - b.x, o.y - b.y) < o.bound_r + b.bound_r + 0.01;
    if (clash) continue;
    V3 corners[8];
    for (int k = 0; k < 8; ++k) {
      const double lx = (k & 1) ? b.hx : -b.hx, ly = (k & 2) ? b.hy : -b.hy;
      corners[k] = {b.x + lx * b.c - ly * b.s, b.y + lx * b.s + ly * b.c, (k & 4) ? b.hz : 0.0};
    }
    b.bbox = ProjectBounds(cam_, corners, 8, W_, H_);
    const double area = double(b.bbox.x1 - b.bbox.x0 + 1) * (b.bbox.y1 - b.bbox.y0 + 1);
    if (b.bbox.x1 < b.bbox.x0 || b.bbox.y1 < b.bbox.y0 || area > 0.2 * W_ * H_) continue;
    // Shadow region: footprint and the footprint moved by the top's shadow offset.
    const double ox = -b.hz * light_.x / light_.z, oy = -b.hz * light_.y / light_.z;
    for (int k = 0; k < 4; ++k) {
      b.shadow.Add(corners[k].x, corners[k].y);
      b.shadow.Add(corners[k].x + ox, corners[k].y + oy);
    }
    b.shadow.Grow(0.02);
    b.shadow_bbox = ProjectTableRect(cam_, b.shadow, W_, H_);
    box_.push_back(b);
    return true;
  }
  return false;
}

bool World::PlaceShape(ShapeKind kind) {
  for (int tries = 0; tries < 20; ++tries) {
    V3 p;
    if (!TablePointAt(rng_.Uniform(-0.05, 1.05) * W_, rng_.Uniform(0.0, 1.05) * H_, 0, &p)) continue;
    if (p.x > wall_x_) continue;
    Shape sh;
    sh.kind = kind;
    do {
      sh.albedo = rng_.Uniform(0.05, 0.95);
    } while (std::abs(sh.albedo - table_base_) < 0.12);
    sh.cx = p.x;
    sh.cy = p.y;
    const double size = rng_.Uniform(0.02, 0.12);
    const double ang = rng_.Uniform(0, 2 * kPi);
    sh.c = std::cos(ang);
    sh.s = std::sin(ang);
    switch (kind) {
      case ShapeKind::kRect:
      case ShapeKind::kStripes: {
        sh.hx = size * rng_.Uniform(0.4, 1.2);
        sh.hy = size * rng_.Uniform(0.3, 1.0);
        sh.period = rng_.Uniform(0.006, 0.03);
        sh.duty = rng_.Uniform(0.3, 0.7);
        const double R = std::hypot(sh.hx, sh.hy);
        sh.area.Add(sh.cx - R, sh.cy - R);
        sh.area.Add(sh.cx + R, sh.cy + R);
        break;
      }
      case ShapeKind::kPolygon: {
        const int n = rng_.Int(3, 7);
        std::vector<double> angles(n);
        for (double& a : angles) a = rng_.Uniform(0, 2 * kPi);
        std::sort(angles.begin(), angles.end());
        for (int i = 0; i < n; ++i) {
          const double r = size * rng_.Uniform(0.45, 1.0);
          sh.px.push_back(sh.cx + r * std::cos(angles[i]));
          sh.py.push_back(sh.cy + r * std::sin(angles[i]));
          sh.area.Add(sh.px.back(), sh.py.back());
        }
        break;
      }
      case ShapeKind::kBlob: {
        // Star-shaped blob with 3rd..5th harmonics: curved, but never an ellipse.
        const double a2 = rng_.Uniform(0, 0.12), a3 = rng_.Uniform(0.12, 0.25), a4 = rng_.Uniform(0, 0.12);
        const double a5 = rng_.Uniform(0, 0.08);
        const double p2 = rng_.Uniform(0, 2 * kPi), p3 = rng_.Uniform(0, 2 * kPi), p4 = rng_.Uniform(0, 2 * kPi);
        const double p5 = rng_.Uniform(0, 2 * kPi);
        double rmax = 0;
        for (int i = 0; i < 256; ++i) {
          const double t = -kPi + 2 * kPi * i / 256.0;
          const double r = size * (1 + a2 * std::cos(2 * t + p2) + a3 * std::cos(3 * t + p3) +
                                   a4 * std::cos(4 * t + p4) + a5 * std::cos(5 * t + p5));
          sh.blob_r[i] = r;
          rmax = std::max(rmax, r);
        }
        sh.area.Add(sh.cx - rmax, sh.cy - rmax);
        sh.area.Add(sh.cx + rmax, sh.cy + rmax);
        break;
      }
      case ShapeKind::kLine: {
        const double len = rng_.Uniform(0.08, 0.5);
        sh.x0 = sh.cx - 0.5 * len * sh.c;
        sh.y0 = sh.cy - 0.5 * len * sh.s;
        sh.x1 = sh.cx + 0.5 * len * sh.c;
        sh.y1 = sh.cy + 0.5 * len * sh.s;
        sh.half_w = rng_.Uniform(0.001, 0.003);
        sh.area.Add(sh.x0, sh.y0);
        sh.area.Add(sh.x1, sh.y1);
        sh.area.Grow(sh.half_w);
        break;
      }
    }
    shape_.push_back(std::move(sh));
    return true;
  }
  return false;
}

void World::PlaceClutter() {
  int boxes = 0;
  for (int i = 0; i < opt_.clutter_shapes; ++i) {
    const double pick = rng_.Uniform();
    if (pick < 0.2 && boxes < 3 && !no_boxes_) {
      if (PlaceBox()) ++boxes;
    } else if (pick < 0.45) {
      PlaceShape(ShapeKind::kLine);
    } else {
      static constexpr ShapeKind kKinds[4] = {ShapeKind::kPolygon, ShapeKind::kRect, ShapeKind::kStripes,
                                              ShapeKind::kBlob};
      PlaceShape(kKinds[rng_.Int(0, 3)]);
    }
  }
}

void World::ColorCylinder(Cylinder* c) {
  c->side_albedo = rng_.Uniform(0.08, 0.9);
  c->spec = 0;
  c->shininess = 10;
  switch (c->kind) {
    case CylKind::kCan:
      c->top_albedo = rng_.Uniform(0.3, 0.8);  // metal lid
      c->has_rim = true;
      c->rim_albedo = Clamp(c->top_albedo + (rng_.Chance(0.5) ? 1 : -1) * rng_.Uniform(0.08, 0.2), 0.05, 0.95);
      c->rim_width = rng_.Uniform(0.002, 0.005);
      c->spec = rng_.Uniform(0.1, 0.45);
      c->shininess = rng_.Uniform(8, 40);
      c->has_label = rng_.Chance(0.7);
      c->has_neck = rng_.Chance(0.6);
      c->neck_width = rng_.Uniform(0.003, 0.01);
      c->neck_albedo = Clamp(c->top_albedo * rng_.Uniform(0.8, 1.1), 0.05, 0.95);
      break;
    case CylKind::kCup:
      c->top_albedo = Clamp(c->side_albedo * rng_.Uniform(1.0, 1.25), 0.05, 0.95);  // lip
      c->inner_albedo = Clamp(c->side_albedo * rng_.Uniform(0.8, 1.0), 0.05, 0.95);
      c->spec = rng_.Uniform(0.0, 0.15);
      c->has_label = rng_.Chance(0.3);
      break;
    case CylKind::kJar:
      do {
        c->top_albedo = rng_.Uniform(0.05, 0.95);
      } while (std::abs(c->top_albedo - c->side_albedo) < 0.15);
      c->has_rim = rng_.Chance(0.5);
      c->rim_albedo = rng_.Uniform(0.05, 0.95);
      c->rim_width = rng_.Uniform(0.002, 0.004);
      c->has_neck = rng_.Chance(0.5);  // the lid's side band, same paint as the lid
      c->neck_width = rng_.Uniform(0.008, 0.02);
      c->neck_albedo = c->top_albedo;
      c->spec = rng_.Uniform(0.0, 0.2);
      break;
  }
  c->label_z0 = c->h * rng_.Uniform(0.1, 0.3);
  c->label_z1 = c->h * rng_.Uniform(0.65, 0.92);
  c->label_albedo = rng_.Uniform(0.05, 0.95);
  c->has_print = c->has_label && rng_.Chance(0.6);
  const double pa = rng_.Uniform(0, 2 * kPi);
  c->print_dir = {std::cos(pa), std::sin(pa), 0};
  c->print_cos = std::cos(rng_.Uniform(0.3, 1.0));
  c->print_albedo = rng_.Uniform(0.05, 0.95);
}

bool World::ComputeTruth(Cylinder* c) const {
  const cv::Matx33d q = ProjectCircleConic(cam_.K(), cam_.R(), cam_.T(), cv::Vec3d(c->x, c->y, c->h),
                                           cv::Vec3d(1, 0, 0), cv::Vec3d(0, 1, 0), c->r);
  return ConicToEllipse(q, &c->truth);
}

void World::FinishCylinderBounds(Cylinder* c) const {
  V3 corners[8];
  for (int k = 0; k < 8; ++k)
    corners[k] = {c->x + ((k & 1) ? c->r : -c->r), c->y + ((k & 2) ? c->r : -c->r), (k & 4) ? c->h : 0.0};
  c->bbox = ProjectBounds(cam_, corners, 8, W_, H_);
  const double ox = -c->h * light_.x / light_.z, oy = -c->h * light_.y / light_.z;
  c->shadow = TRect();
  c->shadow.Add(c->x, c->y);
  c->shadow.Add(c->x + ox, c->y + oy);
  c->shadow.Grow(c->r + 0.035 + penumbra_ * c->h / light_.z);  // + penumbra and contact darkening
  c->shadow_bbox = ProjectTableRect(cam_, c->shadow, W_, H_);
}

// Whether c, moved to (x, y), stays clear of the wall and shows a top ellipse with b >= 4 px whose
// bounding box lies at least 12 px inside the image.
bool World::TopFitsAt(Cylinder c, double x, double y) const {
  c.x = x;
  c.y = y;
  if (has_wall_ && c.x + c.r > wall_x_ - 0.01) return false;
  if (!ComputeTruth(&c)) return false;
  const ellipsekit::Ellipse& e = c.truth;
  const double ct = std::cos(e.theta), st = std::sin(e.theta);
  const double ex = std::sqrt(e.a * e.a * ct * ct + e.b * e.b * st * st);
  const double ey = std::sqrt(e.a * e.a * st * st + e.b * e.b * ct * ct);
  const double m = 12;
  return e.b >= 4 && e.cx - ex >= m && e.cx + ex <= W_ - 1 - m && e.cy - ey >= m && e.cy + ey <= H_ - 1 - m;
}

// Moves c so its top centre is above (top[0], top[1]); recomputes its ellipse and bounds. False
// when the top ellipse is degenerate.
bool World::MoveTopTo(const cv::Vec3d& top, Cylinder* c) const {
  c->x = top[0];
  c->y = top[1];
  if (!ComputeTruth(c)) return false;
  FinishCylinderBounds(c);
  return true;
}

// A horizontal unit vector within max_deg of the image rows (one draw from rng_).
V3 World::RandomRowDirection(double max_deg) {
  const double ang = rng_.Uniform(-max_deg, max_deg) * kPi / 180;
  const V3 h0 = Normalize(V3{cam_.right.x, cam_.right.y, 0});
  return V3{h0.x * std::cos(ang) - h0.y * std::sin(ang), h0.x * std::sin(ang) + h0.y * std::cos(ang), 0};
}

double World::RimVisibleFraction(int i, bool stop_early_below, double thr) const {
  const Cylinder& c = cyl_[i];
  int visible = 0;
  for (int k = 0; k < 360; ++k) {
    const double phi = 2 * kPi * k / 360.0;
    const V3 P{c.x + c.r * std::cos(phi), c.y + c.r * std::sin(phi), c.h};
    double u, v;
    if (!cam_.Project(P, &u, &v)) continue;
    const V3 D = P - cam_.pos;  // s = 1 at the rim point
    if (!OccludedBefore(D, 1 - 1e-9, static_cast<int>(std::lround(u)), static_cast<int>(std::lround(v)), i))
      ++visible;
    else if (stop_early_below && (k + 1 - visible) > (1 - thr) * 360 + 1e-9)
      return 0;
  }
  return visible / 360.0;
}

void World::PlaceCylinders() {
  const int wanted = rng_.Int(opt_.min_objects, opt_.max_objects);
  const double thr = opt_.occlusion ? 0.5 : 1.0;
  const double margin = 3.0;
  for (int n = 0; n < wanted; ++n) {
    for (int tries = 0; tries < 80; ++tries) {
      Cylinder c;
      const double pk = rng_.Uniform();
      c.kind = pk < 0.45 ? CylKind::kCan : (pk < 0.75 ? CylKind::kCup : CylKind::kJar);
      c.r = rng_.Uniform(0.025, 0.06);
      c.h = rng_.Uniform(0.03, 0.15);
      c.r2 = c.r * c.r;
      c.r_in = c.r - rng_.Uniform(0.002, 0.005);
      c.r_in2 = c.r_in * c.r_in;
      c.z_floor = std::min(c.h * 0.5, rng_.Uniform(0.006, 0.015));
      ColorCylinder(&c);
      V3 top;
      if (!TablePointAt(rng_.Uniform(0.04, 0.96) * W_, rng_.Uniform(0.04, 0.96) * H_, c.h, &top)) continue;
      c.x = top.x;
      c.y = top.y;
      if (has_wall_ && c.x + c.r > wall_x_ - 0.01) continue;
      if (!ComputeTruth(&c)) continue;
      const ellipsekit::Ellipse& e = c.truth;
      const double ct = std::cos(e.theta), st = std::sin(e.theta);
      const double ex = std::sqrt(e.a * e.a * ct * ct + e.b * e.b * st * st);
      const double ey = std::sqrt(e.a * e.a * st * st + e.b * e.b * ct * ct);
      if (e.cx - ex < margin || e.cx + ex > W_ - 1 - margin || e.cy - ey < margin || e.cy + ey > H_ - 1 - margin)
        continue;
      if (e.a < 6 || e.b < 3.5 || e.a > 0.4 * std::min(W_, H_)) continue;
      bool clash = false;
      for (const Cylinder& o : cyl_) clash |= std::hypot(o.x - c.x, o.y - c.y) < o.r + c.r + 0.004;
      for (const Box& b : box_) {
        const double dx = c.x - b.x, dy = c.y - b.y;
        const double lx = dx * b.c + dy * b.s, ly = -dx * b.s + dy * b.c;
        const double qx = lx - Clamp(lx, -b.hx, b.hx), qy = ly - Clamp(ly, -b.hy, b.hy);
        clash |= std::hypot(qx, qy) < c.r + 0.004;
      }
      if (clash) continue;
      FinishCylinderBounds(&c);
      cyl_.push_back(c);
      bool ok = true;
      for (int i = 0; i < static_cast<int>(cyl_.size()) && ok; ++i) ok = RimVisibleFraction(i, true, thr) >= thr;
      if (ok) break;
      cyl_.pop_back();
    }
  }
}

// Share of the (unoccluded) rim samples where the image 2 px inside the top differs from 2 px
// outside by at least 18 gray levels (before blur and noise).
double World::ContrastPassFraction(int i) const {
  const Cylinder& c = cyl_[i];
  double cu, cv;
  if (!cam_.Project(V3{c.x, c.y, c.h}, &cu, &cv)) return 0;
  int seen = 0, pass = 0;
  for (int k = 0; k < 72; ++k) {
    const double phi = 2 * kPi * k / 72.0;
    const V3 P{c.x + c.r * std::cos(phi), c.y + c.r * std::sin(phi), c.h};
    double u, v;
    if (!cam_.Project(P, &u, &v)) continue;
    if (OccludedBefore(P - cam_.pos, 1 - 1e-9, static_cast<int>(std::lround(u)), static_cast<int>(std::lround(v)),
                       i))
      continue;
    const double du = u - cu, dv = v - cv, len = std::hypot(du, dv);
    if (len < 1e-9) continue;
    const double nu = du / len, nv = dv / len;
    const double in = ShadeAt(u - 2 * nu, v - 2 * nv), out = ShadeAt(u + 2 * nu, v + 2 * nv);
    ++seen;
    if (std::abs(in - out) >= 18) ++pass;
  }
  return seen ? static_cast<double>(pass) / seen : 0;
}

void World::FixContrast() {
  static constexpr double kScales[] = {1.0, 1.6, 0.55, 2.2, 0.35, 3.0, 0.2};
  for (int i = 0; i < static_cast<int>(cyl_.size()); ++i) {
    Cylinder& c = cyl_[i];
    double best = -1, best_scale = 1;
    for (double s : kScales) {
      // Albedos stay below 1: skip scales that would saturate the brightest top part.
      const double brightest = std::max({c.top_albedo, c.has_rim ? c.rim_albedo : 0.0,
                                         c.kind == CylKind::kCup ? c.inner_albedo : 0.0});
      if (brightest * s > 0.98) continue;
      c.top_scale = s;
      const double f = ContrastPassFraction(i);
      if (f > best) {
        best = f;
        best_scale = s;
      }
      if (f >= 0.7) break;
    }
    c.top_scale = best_scale;
  }
}

// ---------------------------------------------------------------- ray casting
bool World::IntersectCylinder(const Cylinder& c, V3 D, double s_max, Hit* h) const {
  const V3 O = cam_.pos;
  const double ox = O.x - c.x, oy = O.y - c.y;
  if (D.z < 0) {  // the top plane, seen from above
    const double st = (c.h - O.z) / D.z;
    if (st > 0 && st < s_max) {
      const double qx = ox + st * D.x, qy = oy + st * D.y;
      const double rr = qx * qx + qy * qy;
      if (rr <= c.r2) {
        if (c.kind == CylKind::kCup && rr < c.r_in2) {
          // Into the cup: the inner wall (far side) or the floor.
          const double A = D.x * D.x + D.y * D.y;
          double s_hit = kInf;
          int part = kFloor;
          if (A > 1e-18) {
            const double B = ox * D.x + oy * D.y, C = ox * ox + oy * oy - c.r_in2;
            const double disc = std::max(0.0, B * B - A * C);
            const double s2 = (-B + std::sqrt(disc)) / A;
            if (O.z + s2 * D.z >= c.z_floor) {
              s_hit = s2;
              part = kInner;
            }
          }
          if (part == kFloor) s_hit = (c.z_floor - O.z) / D.z;
          if (s_hit >= s_max) return false;
          h->s = s_hit;
          h->part = part;
          h->p = O + D * s_hit;
          h->rho2 = rr;
          return true;
        }
        h->s = st;
        h->part = kTop;
        h->p = O + D * st;
        h->rho2 = rr;
        return true;
      }
    }
  }
  const double A = D.x * D.x + D.y * D.y;
  if (A < 1e-18) return false;
  const double B = ox * D.x + oy * D.y, C = ox * ox + oy * oy - c.r2;
  const double disc = B * B - A * C;
  if (disc < 0) return false;
  const double s1 = (-B - std::sqrt(disc)) / A;
  if (s1 <= 0 || s1 >= s_max) return false;
  const double z = O.z + s1 * D.z;
  if (z < 0 || z > c.h) return false;
  h->s = s1;
  h->part = kSide;
  h->p = O + D * s1;
  return true;
}

bool World::IntersectBox(const Box& b, V3 O, V3 D, double s_max, Hit* h) const {
  const double rx = O.x - b.x, ry = O.y - b.y;
  const double o[3] = {rx * b.c + ry * b.s, -rx * b.s + ry * b.c, O.z};
  const double d[3] = {D.x * b.c + D.y * b.s, -D.x * b.s + D.y * b.c, D.z};
  const double lo[3] = {-b.hx, -b.hy, 0}, hi[3] = {b.hx, b.hy, b.hz};
  double t0 = 0, t1 = s_max;
  int face = -1;
  double sign = 0;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) < 1e-15) {
      if (o[k] < lo[k] || o[k] > hi[k]) return false;
      continue;
    }
    const double inv = 1.0 / d[k];
    double ta = (lo[k] - o[k]) * inv, tb = (hi[k] - o[k]) * inv;
    double sg = -1;  // entering through the low face: outward normal points to -k
    if (ta > tb) {
      std::swap(ta, tb);
      sg = 1;
    }
    if (ta > t0) {
      t0 = ta;
      face = k;
      sign = sg;
    }
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  if (face < 0 || t0 >= s_max) return false;  // starts inside, or beyond the current nearest hit
  if (h != nullptr) {
    h->s = t0;
    h->part = kBoxFace;
    h->p = O + D * t0;
    V3 n;
    if (face == 0) n = {sign * b.c, sign * b.s, 0};
    if (face == 1) n = {-sign * b.s, sign * b.c, 0};
    if (face == 2) n = {0, 0, sign};
    h->n = n;
  }
  return true;
}

void World::Trace(V3 D, int px, int py, Hit* h) const {
  const V3 O = cam_.pos;
  *h = Hit();
  if (D.z < 0) {
    const double s = -O.z / D.z;
    const V3 P = O + D * s;
    if (P.x < wall_x_) {
      h->s = s;
      h->part = kTable;
      h->p = P;
    }
  }
  if (h->part == kBackground && has_wall_ && D.x > 0) {
    const double s = (wall_x_ - O.x) / D.x;
    h->s = s;
    h->part = kWall;
    h->p = O + D * s;
  }
  for (int i = 0; i < static_cast<int>(cyl_.size()); ++i) {
    if (!cyl_[i].bbox.Contains(px, py)) continue;
    if (IntersectCylinder(cyl_[i], D, h->s, h)) h->obj = i;
  }
  for (int i = 0; i < static_cast<int>(box_.size()); ++i) {
    if (!box_[i].bbox.Contains(px, py)) continue;
    if (IntersectBox(box_[i], O, D, h->s, h)) h->obj = i;
  }
}

bool World::OccludedBefore(V3 D, double s_max, int px, int py, int skip_cyl) const {
  Hit h;
  for (int i = 0; i < static_cast<int>(cyl_.size()); ++i) {
    if (i == skip_cyl || !cyl_[i].bbox.Contains(px, py)) continue;
    if (IntersectCylinder(cyl_[i], D, s_max, &h)) return true;
  }
  for (const Box& b : box_) {
    if (b.bbox.Contains(px, py) && IntersectBox(b, cam_.pos, D, s_max, &h)) return true;
  }
  return false;
}

double World::Noise(double x, double y) const {
  const double fx = std::floor(x), fy = std::floor(y);
  const long long ix = static_cast<long long>(fx), iy = static_cast<long long>(fy);
  double tx = x - fx, ty = y - fy;
  tx = tx * tx * (3 - 2 * tx);
  ty = ty * ty * (3 - 2 * ty);
  const int x0 = static_cast<int>(ix & 255), x1 = static_cast<int>((ix + 1) & 255);
  const int y0 = static_cast<int>(iy & 255), y1 = static_cast<int>((iy + 1) & 255);
  const double a = lattice_[y0 * 256 + x0], b = lattice_[y0 * 256 + x1];
  const double c = lattice_[y1 * 256 + x0], d = lattice_[y1 * 256 + x1];
  return (a + (b - a) * tx) * (1 - ty) + (c + (d - c) * tx) * ty;
}

// Contrast kept for a feature of size `lambda` metres when a pixel covers `fp` metres (cheap mip-mapping).
inline double Keep(double fp, double lambda) {
  const double q = 3 * fp / lambda;
  return 1.0 / (1.0 + q * q);
}

double World::TableTexture(double X, double Y, double fp) const {
  double t = 0;
  switch (table_kind_) {
    case TableKind::kWood: {
      const double along = X * grain_c_ + Y * grain_s_, across = -X * grain_s_ + Y * grain_c_;
      const double w = across / grain_period_ + grain_warp_ * Noise(along * 1.5 + 17.3, across * 1.5 + 5.1);
      const double ring = w - std::floor(w);
      const double tri = std::abs(2 * ring - 1);
      const double profile = tri * tri * (3 - 2 * tri);
      const double streak = Noise(along * 4 + 91.7, across * 150 + 33.3);
      t = grain_contrast_ * (profile - 0.5) * Keep(fp, grain_period_) +
          0.15 * (streak - 0.5) * Keep(fp, 1.0 / 150) + 0.12 * (Noise(X * 3 + 50.5, Y * 3 + 7.7) - 0.5);
      break;
    }
    case TableKind::kMottled:
      t = noise_contrast_ * (0.6 * Noise(X * 8 + 3.3, Y * 8 + 9.9) +
                             0.4 * (Noise(X * 30 + 71.1, Y * 30 + 2.2) - 0.5) * Keep(fp, 1.0 / 30) - 0.3) +
          speck_ * (Noise(X * 300 + 11.1, Y * 300 + 61.6) - 0.5) * Keep(fp, 1.0 / 300);
      break;
    case TableKind::kPlain:
      t = noise_contrast_ * (Noise(X * 5 + 123.4, Y * 5 + 43.2) - 0.5) +
          speck_ * 0.5 * (Noise(X * 200 + 1.1, Y * 200 + 8.8) - 0.5) * Keep(fp, 1.0 / 200);
      break;
  }
  const double illum = 1 + illum_var_ * (Noise(X * 0.8 + 200.5, Y * 0.8 + 100.5) - 0.5);
  return table_base_ * (1 + t) * illum;
}

double World::WallTexture(double Y, double Z) const {
  return wall_albedo_ * (1 + 0.08 * (Noise(Y * 4 + 140.0, Z * 4 + 20.0) - 0.5));
}

// Direct light reaching table point P (0..1): soft cylinder shadows, hard box shadows, contact darkening.
double World::TableLit(V3 P) const {
  double lit = 1;
  const double lx = light_.x, ly = light_.y, lz = light_.z, ll = lx * lx + ly * ly;
  for (const Cylinder& c : cyl_) {
    if (!c.shadow.Contains(P.x, P.y)) continue;
    const double px = P.x - c.x, py = P.y - c.y;
    // Closest horizontal approach of the shadow ray to the axis while it is below the top.
    const double s_top = c.h / lz;
    const double s = ll > 1e-12 ? Clamp(-(px * lx + py * ly) / ll, 0.0, s_top) : 0.0;
    const double d = std::hypot(px + s * lx, py + s * ly);
    const double w = 0.002 + penumbra_ * s;
    lit *= Smoothstep(c.r - w, c.r + w, d);
    const double gap = std::hypot(px, py) - c.r;  // contact darkening near the base
    if (gap < 0.03) {
      const double g = 1 - Clamp(gap / 0.03, 0.0, 1.0);
      lit *= 1 - 0.45 * g * g;
    }
  }
  for (const Box& b : box_) {
    if (!b.shadow.Contains(P.x, P.y)) continue;
    if (IntersectBox(b, V3{P.x, P.y, 1e-9}, light_, kInf, nullptr)) lit *= 0.0;
    // contact darkening
    const double dx = P.x - b.x, dy = P.y - b.y;
    const double qx = std::abs(dx * b.c + dy * b.s) - b.hx, qy = std::abs(-dx * b.s + dy * b.c) - b.hy;
    const double gap = std::hypot(std::max(qx, 0.0), std::max(qy, 0.0));
    if (gap < 0.02) {
      const double g = 1 - gap / 0.02;
      lit *= 1 - 0.4 * g * g;
    }
  }
  return lit;
}

// Direct light on a point inside a cup: shadowed where the way to the light leaves through the wall.
double World::CupLit(const Cylinder& c, V3 P) const {
  const double px = P.x - c.x, py = P.y - c.y;
  const double lx = light_.x, ly = light_.y, ll = lx * lx + ly * ly;
  if (ll < 1e-12) return 1;
  const double pl = px * lx + py * ly;
  const double disc = std::max(0.0, pl * pl - ll * (px * px + py * py - c.r_in2));
  const double u = (-pl + std::sqrt(disc)) / ll;
  const double z_exit = P.z + u * light_.z;
  return Smoothstep(c.h - 0.004, c.h + 0.004, z_exit);
}

double World::Vignette(double u, double v) const {
  const double du = (u - cam_.pcx) / (cam_.pcx + 1), dv = (v - cam_.pcy) / (cam_.pcx + 1);
  return 1 - vignette_ * (du * du + dv * dv);
}

double World::Shade(const Hit& h, V3 D, V3 D_centre, TexCache* tc) const {
  double albedo = 0, lit = 0;  // lit: ambient + diffuse, spec added separately
  double spec = 0;
  const V3 P = h.p;
  switch (h.part) {
    case kBackground:
      return background_;
    case kTable: {
      if (!tc->table_ok) {
        // Texture at the pixel centre's table point (smooth: one evaluation per pixel).
        V3 Q = P;
        double s = h.s;
        V3 Dq = D;
        if (D_centre.z < 0) {
          const double sc = -cam_.pos.z / D_centre.z;
          const V3 Pc = cam_.pos + D_centre * sc;
          if (Pc.x < wall_x_) {
            Q = Pc;
            s = sc;
            Dq = D_centre;
          }
        }
        const double fp = s * Dot(Dq, Dq) / (cam_.f * std::abs(Dq.z));
        tc->table = TableTexture(Q.x, Q.y, fp);
        tc->table_ok = true;
      }
      albedo = tc->table;
      for (const Shape& sh : shape_) {  // printed shapes (later ones on top), sharp: per sample
        if (sh.area.Contains(P.x, P.y) && sh.Inside(P.x, P.y)) albedo = sh.albedo;
      }
      const double l = TableLit(P);
      lit = ambient_ * (0.75 + 0.25 * l) + diffuse_ * light_.z * l;
      break;
    }
    case kWall: {
      if (!tc->wall_ok) {
        tc->wall = WallTexture(P.y, P.z);
        tc->wall_ok = true;
      }
      albedo = tc->wall;
      lit = ambient_ + diffuse_ * std::max(0.0, -light_.x) * 0.9;
      break;
    }
    case kSide: {
      const Cylinder& c = cyl_[h.obj];
      const V3 n{(P.x - c.x) / c.r, (P.y - c.y) / c.r, 0};
      albedo = c.side_albedo;
      if (c.has_label && P.z >= c.label_z0 && P.z <= c.label_z1) {
        albedo = c.label_albedo;
        if (c.has_print && Dot(n, c.print_dir) > c.print_cos && P.z < 0.5 * (c.label_z0 + c.label_z1))
          albedo = c.print_albedo;
      }
      if (c.has_neck && P.z > c.h - c.neck_width) albedo = c.neck_albedo;
      const double ao = 1 - 0.35 * std::max(0.0, 1 - P.z / 0.012);
      lit = ambient_ * ao + diffuse_ * std::max(0.0, Dot(n, light_));
      if (c.spec > 0) {
        const V3 Hh = Normalize(light_ + Normalize(cam_.pos - P));
        spec = c.spec * std::pow(std::max(0.0, Dot(n, Hh)), c.shininess);
      }
      break;
    }
    case kTop: {
      const Cylinder& c = cyl_[h.obj];
      albedo = c.top_albedo;
      if (c.has_rim) {
        const double rho = std::sqrt(h.rho2);
        if (rho > c.r - c.rim_width)
          albedo = c.rim_albedo;
        else if (c.kind == CylKind::kCan && rho > c.r - c.rim_width - 0.002)
          albedo = c.top_albedo * 0.8;  // the lid's countersink groove
      }
      albedo = std::min(albedo * c.top_scale, 1.0);
      lit = ambient_ + diffuse_ * light_.z;
      if (c.spec > 0) {
        const V3 Hh = Normalize(light_ + Normalize(cam_.pos - P));
        spec = 0.5 * c.spec * std::pow(std::max(0.0, Hh.z), 4 * c.shininess);
      }
      break;
    }
    case kInner: {
      const Cylinder& c = cyl_[h.obj];
      const V3 n{-(P.x - c.x) / c.r_in, -(P.y - c.y) / c.r_in, 0};
      albedo = std::min(c.inner_albedo * c.top_scale, 1.0);
      const double depth = Clamp((P.z - c.z_floor) / std::max(1e-6, c.h - c.z_floor), 0.0, 1.0);
      lit = ambient_ * (0.4 + 0.6 * depth) + diffuse_ * std::max(0.0, Dot(n, light_)) * CupLit(c, P);
      break;
    }
    case kFloor: {
      const Cylinder& c = cyl_[h.obj];
      albedo = std::min(c.inner_albedo * c.top_scale, 1.0);
      lit = ambient_ * 0.4 + diffuse_ * light_.z * CupLit(c, P);
      break;
    }
    case kBoxFace: {
      const Box& b = box_[h.obj];
      albedo = b.albedo;
      if (b.has_print && h.n.z > 0.5) {
        const double dx = P.x - b.x, dy = P.y - b.y;
        if (std::abs(dx * b.c + dy * b.s) < b.print_hx && std::abs(-dx * b.s + dy * b.c) < b.print_hy)
          albedo = b.print_albedo;
      }
      const double ao = 1 - 0.3 * std::max(0.0, 1 - P.z / 0.01);
      lit = ambient_ * ao + diffuse_ * std::max(0.0, Dot(h.n, light_));
      break;
    }
  }
  return 255.0 * gain_ * (albedo * lit + spec);
}

double World::ShadeAt(double u, double v) const {
  const V3 D = cam_.Ray(u, v);
  Hit h;
  Trace(D, static_cast<int>(std::lround(u)), static_cast<int>(std::lround(v)), &h);
  TexCache tc;
  return Shade(h, D, D, &tc) * Vignette(u, v);
}

// One pixel: the mean of 2x2 sub-samples at (x +- 0.25, y +- 0.25), times the vignette.
float World::RenderPixel(int x, int y) const {
  static constexpr double kSub[4][2] = {{-0.25, -0.25}, {0.25, -0.25}, {-0.25, 0.25}, {0.25, 0.25}};
  const V3 Dc = cam_.Ray(x, y);
  TexCache tc;
  double sum = 0;
  for (const auto& sub : kSub) {
    const V3 D = cam_.Ray(x + sub[0], y + sub[1]);
    Hit h;
    Trace(D, x, y, &h);
    sum += Shade(h, D, Dc, &tc);
  }
  return static_cast<float>(0.25 * sum * Vignette(x, y));
}

void World::Render(std::vector<float>* img) const {
  img->assign(static_cast<size_t>(W_) * H_, 0.f);
  RenderRect(IRect{0, 0, W_ - 1, H_ - 1}, img);
}

void World::RenderRect(const IRect& r, std::vector<float>* img) const {
  const int x0 = std::max(r.x0, 0), y0 = std::max(r.y0, 0);
  const int x1 = std::min(r.x1, W_ - 1), y1 = std::min(r.y1, H_ - 1);
  for (int y = y0; y <= y1; ++y) {
    float* row = img->data() + static_cast<size_t>(y) * W_;
    for (int x = x0; x <= x1; ++x) row[x] = RenderPixel(x, y);
  }
}

// Camera-axis depth of the first hit of each pixel's centre ray: D . forward = 1, so the ray
// parameter s is that depth. 0 where the ray sees no surface.
void World::RenderDepth(const IRect& r, std::vector<double>* z) const {
  const int x0 = std::max(r.x0, 0), y0 = std::max(r.y0, 0);
  const int x1 = std::min(r.x1, W_ - 1), y1 = std::min(r.y1, H_ - 1);
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      Hit h;
      Trace(cam_.Ray(x, y), x, y, &h);
      (*z)[static_cast<size_t>(y) * W_ + x] = (h.part == kBackground || !std::isfinite(h.s)) ? 0.0 : h.s;
    }
  }
}

// Separable Gaussian blur (reflect-101 border), then additive Gaussian noise, round and clamp.
void World::Finish(const std::vector<float>& img, cv::Mat* gray) {
  std::vector<float> a = img;
  if (opt_.blur_sigma > 0) {
    const int rad = std::max(1, static_cast<int>(std::ceil(3 * opt_.blur_sigma)));
    std::vector<double> k(2 * rad + 1);
    double ksum = 0;
    for (int i = -rad; i <= rad; ++i) ksum += k[i + rad] = std::exp(-0.5 * i * i / (opt_.blur_sigma * opt_.blur_sigma));
    for (double& v : k) v /= ksum;
    auto reflect = [](int i, int n) {
      if (n == 1) return 0;
      while (i < 0 || i >= n) i = i < 0 ? -i : 2 * n - 2 - i;
      return i;
    };
    std::vector<float> b(a.size());
    for (int y = 0; y < H_; ++y) {
      const float* src = a.data() + static_cast<size_t>(y) * W_;
      float* dst = b.data() + static_cast<size_t>(y) * W_;
      for (int x = 0; x < W_; ++x) {
        double s = 0;
        if (x >= rad && x < W_ - rad) {
          for (int i = -rad; i <= rad; ++i) s += k[i + rad] * src[x + i];
        } else {
          for (int i = -rad; i <= rad; ++i) s += k[i + rad] * src[reflect(x + i, W_)];
        }
        dst[x] = static_cast<float>(s);
      }
    }
    std::vector<double> acc(W_);
    for (int y = 0; y < H_; ++y) {
      std::fill(acc.begin(), acc.end(), 0.0);
      for (int i = -rad; i <= rad; ++i) {
        const float* src = b.data() + static_cast<size_t>(reflect(y + i, H_)) * W_;
        const double w = k[i + rad];
        for (int x = 0; x < W_; ++x) acc[x] += w * src[x];
      }
      float* dst = a.data() + static_cast<size_t>(y) * W_;
      for (int x = 0; x < W_; ++x) dst[x] = static_cast<float>(acc[x]);
    }
  }
  gray->create(H_, W_, CV_8UC1);
  for (int y = 0; y < H_; ++y) {
    const float* src = a.data() + static_cast<size_t>(y) * W_;
    std::uint8_t* dst = gray->ptr<std::uint8_t>(y);
    for (int x = 0; x < W_; ++x) {
      double v = src[x];
      if (opt_.noise_sigma > 0) v += opt_.noise_sigma * rng_.Normal();
      dst[x] = static_cast<std::uint8_t>(Clamp(std::floor(v + 0.5), 0.0, 255.0));
    }
  }
}

Scene World::Build() {
  SetupCamera();
  SetupLightAndSurfaces();
  PlaceClutter();
  PlaceCylinders();
  FixContrast();
  std::vector<float> img;
  Render(&img);
  Scene scene;
  Finish(img, &scene.gray);
  for (const Cylinder& c : cyl_) scene.truth.push_back(c.truth);
  return scene;
}

// Depth as a sensor reads it (see ConveyorSceneOptions): Gaussian noise growing with z^2, 1 mm
// steps, a share of dropped pixels and about half of the pixels at depth jumps > 2 cm dropped.
// Draws the same random numbers for every pixel, so the noise does not depend on the content.
void DegradeDepth(const std::vector<double>& z, int W, int H, double noise_mm, double invalid_fraction, Rng* rng,
                  cv::Mat* out) {
  out->create(H, W, CV_16UC1);
  for (int y = 0; y < H; ++y) {
    std::uint16_t* dst = out->ptr<std::uint16_t>(y);
    for (int x = 0; x < W; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * W + x;
      const double zz = z[i];
      const double n = rng->Normal(), drop = rng->Uniform(), edge_drop = rng->Uniform();
      if (!(zz > 0)) {
        dst[x] = 0;
        continue;
      }
      double jump = 0;
      if (x > 0) jump = std::max(jump, std::abs(zz - z[i - 1]));
      if (x + 1 < W) jump = std::max(jump, std::abs(zz - z[i + 1]));
      if (y > 0) jump = std::max(jump, std::abs(zz - z[i - W]));
      if (y + 1 < H) jump = std::max(jump, std::abs(zz - z[i + W]));
      if (drop < invalid_fraction || (jump > 0.02 && edge_drop < 0.5)) {
        dst[x] = 0;
        continue;
      }
      const double mm = zz * 1000 + noise_mm * (1 + zz * zz) * n;
      dst[x] = static_cast<std::uint16_t>(Clamp(std::floor(mm + 0.5), 1.0, 65535.0));
    }
  }
}

ellipsekit::Status World::BuildConveyor(const ConveyorSceneOptions& co, std::uint64_t seed, ConveyorSequence* info,
                                        const std::function<ellipsekit::Status(const ConveyorFrame&)>& sink) {
  using ellipsekit::Status;
  using ellipsekit::StatusCode;
  no_boxes_ = true;
  SetupCamera();
  SetupLightAndSurfaces();

  Cylinder can;
  can.kind = CylKind::kCan;
  can.r = rng_.Uniform(0.03, 0.04);
  can.h = rng_.Uniform(0.08, 0.12);
  SetCanShape(&can);
  ColorCylinder(&can);

  // The guide: through the table point below the image centre, roughly along the image rows.
  V3 mid;
  if (!TablePointAt(cam_.pcx, cam_.pcy, can.h, &mid))
    return Status(StatusCode::kInternal, "conveyor: the camera does not see the table");
  const V3 dir = RandomRowDirection(25);
  auto fits = [&](double s) { return TopFitsAt(can, mid.x + dir.x * s, mid.y + dir.y * s); };
  double L = co.guide_length_m;
  for (int k = 0; k < 60 && !(fits(-0.5 * L) && fits(0.5 * L)); ++k) L *= 0.93;
  if (!(fits(-0.5 * L) && fits(0.5 * L)))
    return Status(StatusCode::kInternal, "conveyor: the can does not fit in the image (image too small?)");
  const V3 start{mid.x - dir.x * 0.5 * L, mid.y - dir.y * 0.5 * L, can.h};
  const V3 end{mid.x + dir.x * 0.5 * L, mid.y + dir.y * 0.5 * L, can.h};

  PlaceClutter();
  can.x = start.x;
  can.y = start.y;
  ComputeTruth(&can);
  FinishCylinderBounds(&can);
  cyl_.push_back(can);
  FixContrast();
  can = cyl_[0];

  // The static world (everything but the can) once; each frame re-renders only the can's region
  // (its bounding box and its shadow's), which the can does not affect outside.
  cyl_.clear();
  std::vector<float> bg;
  Render(&bg);
  std::vector<double> bgz(static_cast<size_t>(W_) * H_, 0.0);
  RenderDepth(IRect{0, 0, W_ - 1, H_ - 1}, &bgz);
  cyl_.push_back(can);

  ConveyorSequence seq;
  seq.width = W_;
  seq.height = H_;
  seq.K = cam_.K();
  seq.T_world_camera = cam_.WorldFromCamera();
  seq.start_point = cv::Vec3d(start.x, start.y, start.z);
  seq.end_point = cv::Vec3d(end.x, end.y, end.z);
  double u, v;
  cam_.Project(start, &u, &v);
  seq.start_pixel = cv::Vec2d(u, v);
  cam_.Project(end, &u, &v);
  seq.end_pixel = cv::Vec2d(u, v);
  seq.speed_m_s = co.speed_m_s;
  seq.length_m = L;
  seq.radius_m = can.r;
  seq.height_m = can.h;
  seq.fps = co.fps;
  seq.frames = co.frames;
  if (info != nullptr) *info = seq;

  Rng drng(Mix64(seed ^ 0x6A09E667F3BCC909ull));
  std::vector<float> img;
  std::vector<double> z;
  for (int i = 0; i < co.frames; ++i) {
    ConveyorFrame fr;
    fr.index = i;
    fr.t = i / co.fps;
    const cv::Vec3d p = seq.TopCentreAt(fr.t);
    Cylinder& c = cyl_[0];
    if (!MoveTopTo(p, &c)) return Status(StatusCode::kInternal, "conveyor: degenerate top ellipse");
    const IRect r = RedrawRect(c);
    img = bg;
    RenderRect(r, &img);
    z = bgz;
    RenderDepth(r, &z);
    Finish(img, &fr.gray);
    DegradeDepth(z, W_, H_, co.depth_noise_mm, co.depth_invalid_fraction, &drng, &fr.depth_mm);
    fr.top_centre = p;
    cam_.Project(V3{p[0], p[1], p[2]}, &u, &v);
    fr.top_pixel = cv::Vec2d(u, v);
    fr.truth = c.truth;
    if (ellipsekit::Status st = sink(fr); !st.ok()) return st;
  }
  return Status::Ok();
}

ellipsekit::Status World::BuildCans(const CanSceneOptions& co, std::uint64_t seed, CanSequence* info,
                                    const std::function<ellipsekit::Status(const CanFrame&)>& sink) {
  using ellipsekit::Status;
  using ellipsekit::StatusCode;
  no_boxes_ = true;
  SetupCamera();
  const bool crossing = co.speed_m_s > 0;
  Cylinder cans[2];
  for (Cylinder& c : cans) {
    c.kind = CylKind::kCan;
    c.r = rng_.Uniform(co.min_radius_m, co.max_radius_m);
    c.h = rng_.Uniform(co.min_height_m, co.max_height_m);
    ColorCylinder(&c);
  }
  if (crossing) cans[0].h = cans[1].h + co.crossing_height_difference_m;
  for (Cylinder& c : cans) SetCanShape(&c);
  // The camera height from the distance to the tops along the optical axis.
  const double d = rng_.Uniform(co.min_distance_m, co.max_distance_m);
  const double h_ref = crossing ? cans[1].h : 0.5 * (cans[0].h + cans[1].h);
  cam_.pos.z = h_ref + d * -cam_.fwd.z;
  SetupLightAndSurfaces();

  CanSequence seq;
  seq.width = W_;
  seq.height = H_;
  seq.K = cam_.K();
  seq.T_world_camera = cam_.WorldFromCamera();
  seq.fps = co.fps;
  seq.frames = co.frames;
  if (!crossing) {
    // Can 0 on the feed side (right half), can 1 on the stack side (left half).
    bool placed = false;
    for (int tries = 0; tries < 100 && !placed; ++tries) {
      V3 p[2];
      bool ok = true;
      for (int k = 0; k < 2 && ok; ++k) {
        const double u = (k == 0 ? 0.7 : 0.3) * W_ + rng_.Uniform(-0.08, 0.08) * W_;
        const double v = rng_.Uniform(0.35, 0.65) * H_;
        ok = TablePointAt(u, v, cans[k].h, &p[k]) && TopFitsAt(cans[k], p[k].x, p[k].y);
      }
      if (!ok || std::hypot(p[0].x - p[1].x, p[0].y - p[1].y) < cans[0].r + cans[1].r + 0.01) continue;
      for (int k = 0; k < 2; ++k) {
        cans[k].x = p[k].x;
        cans[k].y = p[k].y;
        ComputeTruth(&cans[k]);
      }
      placed = cans[0].truth.cx > 0.5 * W_ && cans[1].truth.cx < 0.5 * W_;
    }
    if (!placed) return Status(StatusCode::kInternal, "can scene: the cans do not fit in the image");
    for (int k = 0; k < 2; ++k) {
      seq.start_point.push_back(cv::Vec3d(cans[k].x, cans[k].y, cans[k].h));
      seq.velocity_m_s.push_back(cv::Vec3d(0, 0, 0));
    }
  } else {
    // Two lanes roughly along the image rows through the table point below the image centre; can 0
    // on the lane nearer the camera, moving along +dir, can 1 on the far lane along -dir; they pass
    // each other at mid-sequence, below the image centre.
    V3 mid;
    if (!TablePointAt(cam_.pcx, cam_.pcy, cans[1].h, &mid))
      return Status(StatusCode::kInternal, "can scene: the camera does not see the table");
    const V3 dir = RandomRowDirection(15);
    V3 nrm{-dir.y, dir.x, 0};
    if (Dot(nrm, V3{cam_.fwd.x, cam_.fwd.y, 0}) > 0) nrm = nrm * -1.0;  // towards the camera
    const double off = 0.5 * (cans[0].r + cans[1].r + co.lane_gap_m);
    const double L = co.speed_m_s * (co.frames - 1) / co.fps;
    const V3 s0 = mid + nrm * off - dir * (0.5 * L), s1 = mid - nrm * off + dir * (0.5 * L);
    const V3 e0 = s0 + dir * L, e1 = s1 - dir * L;
    if (!(TopFitsAt(cans[0], s0.x, s0.y) && TopFitsAt(cans[0], e0.x, e0.y) && TopFitsAt(cans[1], s1.x, s1.y) &&
          TopFitsAt(cans[1], e1.x, e1.y)))
      return Status(StatusCode::kInternal,
                    "can scene: the crossing does not fit in the image (lower speed_m_s or frames)");
    seq.start_point.push_back(cv::Vec3d(s0.x, s0.y, cans[0].h));
    seq.start_point.push_back(cv::Vec3d(s1.x, s1.y, cans[1].h));
    seq.velocity_m_s.push_back(cv::Vec3d(dir.x, dir.y, 0) * co.speed_m_s);
    seq.velocity_m_s.push_back(cv::Vec3d(dir.x, dir.y, 0) * -co.speed_m_s);
    for (int k = 0; k < 2; ++k) {
      cans[k].x = seq.start_point[k][0];
      cans[k].y = seq.start_point[k][1];
      ComputeTruth(&cans[k]);
    }
  }
  for (int k = 0; k < 2; ++k) {
    seq.radius_m.push_back(cans[k].r);
    seq.height_m.push_back(cans[k].h);
    seq.rim_width_m.push_back(cans[k].has_rim ? cans[k].rim_width : 0.0);
  }

  PlaceClutter();
  cyl_.clear();
  for (Cylinder& c : cans) {
    FinishCylinderBounds(&c);
    cyl_.push_back(c);
  }
  FixContrast();
  if (info != nullptr) *info = seq;

  // Static: render once, then only noise differs per frame. Crossing: the world without the cans
  // once, then each frame re-renders each can's bounding box and shadow.
  std::vector<float> bg;
  std::vector<double> bgz(static_cast<size_t>(W_) * H_, 0.0);
  const std::vector<Cylinder> placed = cyl_;
  if (crossing) cyl_.clear();
  Render(&bg);
  RenderDepth(IRect{0, 0, W_ - 1, H_ - 1}, &bgz);
  cyl_ = placed;

  Rng drng(Mix64(seed ^ 0xBB67AE8584CAA73Bull));
  std::vector<float> img;
  std::vector<double> z;
  for (int i = 0; i < co.frames; ++i) {
    CanFrame fr;
    fr.index = i;
    fr.t = i / co.fps;
    if (crossing) {
      img = bg;
      z = bgz;
      for (int k = 0; k < 2; ++k) {
        if (!MoveTopTo(seq.TopCentreAt(k, fr.t), &cyl_[k]))
          return Status(StatusCode::kInternal, "can scene: degenerate top ellipse");
      }
      for (int k = 0; k < 2; ++k) {
        const IRect r = RedrawRect(cyl_[k]);
        RenderRect(r, &img);
        RenderDepth(r, &z);
      }
      Finish(img, &fr.gray);
      DegradeDepth(z, W_, H_, co.depth_noise_mm, co.depth_invalid_fraction, &drng, &fr.depth_mm);
    } else {
      Finish(bg, &fr.gray);
      DegradeDepth(bgz, W_, H_, co.depth_noise_mm, co.depth_invalid_fraction, &drng, &fr.depth_mm);
    }
    for (int k = 0; k < 2; ++k) {
      const cv::Vec3d p = seq.TopCentreAt(k, fr.t);
      double u = 0, v = 0;
      cam_.Project(V3{p[0], p[1], p[2]}, &u, &v);
      fr.top_centre.push_back(p);
      fr.top_pixel.push_back(cv::Vec2d(u, v));
      fr.truth.push_back(cyl_[k].truth);
      fr.rim_visible.push_back(RimVisibleFraction(k, false, 0));
    }
    if (ellipsekit::Status st = sink(fr); !st.ok()) return st;
  }
  return Status::Ok();
}

std::string JoinPath(const std::filesystem::path& dir, const std::string& name) { return (dir / name).string(); }

}  // namespace

// ---------------------------------------------------------------- public API
ellipsekit::Status ValidateSceneOptions(const SceneOptions& o) {
  auto bad = [](const std::string& m) { return ellipsekit::Status(ellipsekit::StatusCode::kInvalidArgument, m); };
  if (o.width < 16 || o.width > 8192 || o.height < 16 || o.height > 8192)
    return bad("scene size must be 16..8192 px, got " + std::to_string(o.width) + "x" + std::to_string(o.height));
  if (!(o.min_tilt_deg > 0 && o.min_tilt_deg <= o.max_tilt_deg && o.max_tilt_deg <= 90))
    return bad("tilt range must satisfy 0 < min_tilt_deg <= max_tilt_deg <= 90");
  if (o.min_objects < 0 || o.max_objects < o.min_objects || o.max_objects > 100)
    return bad("object counts must satisfy 0 <= min_objects <= max_objects <= 100");
  if (o.clutter_shapes < 0 || o.clutter_shapes > 1000) return bad("clutter_shapes must be 0..1000");
  if (!(o.noise_sigma >= 0 && o.noise_sigma <= 1000)) return bad("noise_sigma must be finite and >= 0");
  if (!(o.blur_sigma >= 0 && o.blur_sigma <= 50)) return bad("blur_sigma must be 0..50");
  return ellipsekit::Status::Ok();
}

Scene RenderScene(std::uint64_t seed, const SceneOptions& options) {
  if (!ValidateSceneOptions(options).ok()) return Scene();
  World world(options, seed);
  return world.Build();
}

std::uint64_t MixSeed(std::uint64_t seed, std::uint64_t index) {
  const std::uint64_t a = Mix64(seed + 0x9E3779B97F4A7C15ull);
  return Mix64(a ^ Mix64(index * 0xD1B54A32D192ED03ull + 0x8CB92BA72F3D8DD7ull));
}

std::string FormatTruthLine(const ellipsekit::Ellipse& e) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%.4f %.4f %.4f %.4f %.6f", e.cx, e.cy, e.a, e.b, e.theta);
  return buf;
}

ellipsekit::Status WriteSceneDataset(const std::string& dir, int count, std::uint64_t seed,
                                     const SceneOptions& options) {
  if (ellipsekit::Status st = ValidateSceneOptions(options); !st.ok()) return st;
  return WriteDataset(dir, count, seed, [&options](std::uint64_t s) { return RenderScene(s, options); });
}

ellipsekit::Status WriteDataset(const std::string& dir, int count, std::uint64_t seed,
                                const std::function<Scene(std::uint64_t)>& render) {
  using ellipsekit::Status;
  using ellipsekit::StatusCode;
  if (dir.empty()) return Status(StatusCode::kInvalidArgument, "dataset directory is empty");
  if (count < 0) return Status(StatusCode::kInvalidArgument, "scene count must be >= 0, got " + std::to_string(count));
  if (count > 10000) return Status(StatusCode::kInvalidArgument, "scene count must be <= 10000 (4-digit names)");
  const std::filesystem::path root(dir);
  const std::filesystem::path images = root / "images", gt = root / "gt";
  for (const auto& d : {images, gt}) {
    std::error_code ec;
    std::filesystem::create_directories(d, ec);
    if (ec || !std::filesystem::is_directory(d, ec))
      return Status(StatusCode::kInternal, "cannot create directory " + d.string() + ": " + ec.message());
  }
  for (int i = 0; i < count; ++i) {
    const Scene scene = render(MixSeed(seed, static_cast<std::uint64_t>(i)));
    char stem[32];
    std::snprintf(stem, sizeof stem, "scene_%04d", i);
    // Image: imwrite picks the format from the extension, so the temporary name ends in .png too.
    const std::string png = JoinPath(images, std::string(stem) + ".png");
    const std::string png_tmp = JoinPath(images, std::string(".") + stem + ".tmp.png");
    bool written = false;
    try {
      written = cv::imwrite(png_tmp, scene.gray);
    } catch (const cv::Exception& e) {
      written = false;
    }
    std::error_code ec;
    if (!written) {
      std::filesystem::remove(png_tmp, ec);
      return Status(StatusCode::kInternal, "cannot write image " + png_tmp);
    }
    std::filesystem::rename(png_tmp, png, ec);
    if (ec) return Status(StatusCode::kInternal, "cannot rename " + png_tmp + " to " + png + ": " + ec.message());
    // Ground truth.
    const std::string txt = JoinPath(gt, std::string(stem) + ".txt");
    const std::string txt_tmp = JoinPath(gt, std::string(".") + stem + ".tmp.txt");
    std::FILE* f = std::fopen(txt_tmp.c_str(), "wb");
    if (f == nullptr) return Status(StatusCode::kInternal, "cannot open " + txt_tmp + " for writing");
    bool ok = true;
    for (const ellipsekit::Ellipse& e : scene.truth) {
      const std::string line = FormatTruthLine(e) + "\n";
      ok &= std::fwrite(line.data(), 1, line.size(), f) == line.size();
    }
    ok &= std::fclose(f) == 0;
    if (!ok) {
      std::filesystem::remove(txt_tmp, ec);
      return Status(StatusCode::kInternal, "cannot write ground truth " + txt_tmp);
    }
    std::filesystem::rename(txt_tmp, txt, ec);
    if (ec) return Status(StatusCode::kInternal, "cannot rename " + txt_tmp + " to " + txt + ": " + ec.message());
  }
  return Status::Ok();
}

// ---------------------------------------------------------------- conveyor sequences
double ConveyorSequence::PositionAt(double t) const {
  if (!(length_m > 0) || !(speed_m_s > 0)) return 0;
  const double p = std::fmod(std::max(0.0, speed_m_s * t), 2 * length_m);
  return p <= length_m ? p : 2 * length_m - p;
}

cv::Vec3d ConveyorSequence::TopCentreAt(double t) const {
  const double s = PositionAt(t);
  const cv::Vec3d d = end_point - start_point;
  const double n = std::sqrt(d.dot(d));
  return n > 0 ? start_point + d * (s / n) : start_point;
}

ellipsekit::Status ValidateConveyorOptions(const ConveyorSceneOptions& o) {
  auto bad = [](const std::string& m) { return ellipsekit::Status(ellipsekit::StatusCode::kInvalidArgument, m); };
  if (o.width < 64 || o.width > 8192 || o.height < 64 || o.height > 8192)
    return bad("conveyor image size must be 64..8192 px, got " + std::to_string(o.width) + "x" +
               std::to_string(o.height));
  if (!(o.speed_m_s > 0 && o.speed_m_s <= 10)) return bad("conveyor speed must be in (0, 10] m/s");
  if (!(o.fps > 0 && o.fps <= 10000)) return bad("conveyor fps must be in (0, 10000]");
  if (o.frames < 1 || o.frames > 1000000) return bad("conveyor frames must be 1..999999");
  if (!(o.guide_length_m > 0.01 && o.guide_length_m <= 10)) return bad("guide_length_m must be in (0.01, 10]");
  if (o.clutter_shapes < 0 || o.clutter_shapes > 1000) return bad("clutter_shapes must be 0..1000");
  if (!(o.noise_sigma >= 0 && o.noise_sigma <= 1000)) return bad("noise_sigma must be finite and >= 0");
  if (!(o.blur_sigma >= 0 && o.blur_sigma <= 50)) return bad("blur_sigma must be 0..50");
  if (!(o.depth_noise_mm >= 0 && o.depth_noise_mm <= 1000)) return bad("depth_noise_mm must be finite and >= 0");
  if (!(o.depth_invalid_fraction >= 0 && o.depth_invalid_fraction <= 1))
    return bad("depth_invalid_fraction must be in [0, 1]");
  return ellipsekit::Status::Ok();
}

ellipsekit::Status RenderConveyorSequence(std::uint64_t seed, const ConveyorSceneOptions& options,
                                          ConveyorSequence* info,
                                          const std::function<ellipsekit::Status(const ConveyorFrame&)>& sink) {
  if (ellipsekit::Status st = ValidateConveyorOptions(options); !st.ok()) return st;
  SceneOptions so;
  so.width = options.width;
  so.height = options.height;
  so.min_tilt_deg = 45;
  so.max_tilt_deg = 65;
  so.min_objects = so.max_objects = 1;
  so.occlusion = false;
  so.clutter_shapes = options.clutter_shapes;
  so.noise_sigma = options.noise_sigma;
  so.blur_sigma = options.blur_sigma;
  World world(so, seed);
  return world.BuildConveyor(options, seed, info, sink);
}

// ---------------------------------------------------------------- stacking and crossing sequences
cv::Vec3d CanSequence::TopCentreAt(int can, double t) const {
  if (can < 0 || can >= static_cast<int>(start_point.size())) return cv::Vec3d(0, 0, 0);
  const std::size_t k = static_cast<std::size_t>(can);
  return start_point[k] + velocity_m_s[k] * t;
}

ellipsekit::Status ValidateCanSceneOptions(const CanSceneOptions& o) {
  auto bad = [](const std::string& m) { return ellipsekit::Status(ellipsekit::StatusCode::kInvalidArgument, m); };
  if (o.width < 64 || o.width > 8192 || o.height < 64 || o.height > 8192)
    return bad("can scene image size must be 64..8192 px, got " + std::to_string(o.width) + "x" +
               std::to_string(o.height));
  if (!(o.fps > 0 && o.fps <= 10000)) return bad("can scene fps must be in (0, 10000]");
  if (o.frames < 1 || o.frames > 999999) return bad("can scene frames must be 1..999999");
  if (!(o.speed_m_s >= 0 && o.speed_m_s <= 10)) return bad("can scene speed_m_s must be in [0, 10]");
  if (!(o.lane_gap_m >= 0 && o.lane_gap_m <= 1)) return bad("lane_gap_m must be in [0, 1]");
  if (!(o.crossing_height_difference_m >= 0 && o.crossing_height_difference_m <= 0.5))
    return bad("crossing_height_difference_m must be in [0, 0.5]");
  if (!(o.min_radius_m >= 0.005 && o.min_radius_m <= o.max_radius_m && o.max_radius_m <= 0.5))
    return bad("radius range must satisfy 0.005 <= min_radius_m <= max_radius_m <= 0.5");
  if (!(o.min_height_m >= 0.02 && o.min_height_m <= o.max_height_m && o.max_height_m <= 1))
    return bad("height range must satisfy 0.02 <= min_height_m <= max_height_m <= 1");
  if (!(o.min_distance_m >= 0.1 && o.min_distance_m <= o.max_distance_m && o.max_distance_m <= 10))
    return bad("distance range must satisfy 0.1 <= min_distance_m <= max_distance_m <= 10");
  if (!(o.min_tilt_deg >= 10 && o.min_tilt_deg <= o.max_tilt_deg && o.max_tilt_deg <= 90))
    return bad("tilt range must satisfy 10 <= min_tilt_deg <= max_tilt_deg <= 90");
  if (o.clutter_shapes < 0 || o.clutter_shapes > 1000) return bad("clutter_shapes must be 0..1000");
  if (!(o.noise_sigma >= 0 && o.noise_sigma <= 1000)) return bad("noise_sigma must be finite and >= 0");
  if (!(o.blur_sigma >= 0 && o.blur_sigma <= 50)) return bad("blur_sigma must be 0..50");
  if (!(o.depth_noise_mm >= 0 && o.depth_noise_mm <= 1000)) return bad("depth_noise_mm must be finite and >= 0");
  if (!(o.depth_invalid_fraction >= 0 && o.depth_invalid_fraction <= 1))
    return bad("depth_invalid_fraction must be in [0, 1]");
  return ellipsekit::Status::Ok();
}

ellipsekit::Status RenderCanSequence(std::uint64_t seed, const CanSceneOptions& options, CanSequence* info,
                                     const std::function<ellipsekit::Status(const CanFrame&)>& sink) {
  if (ellipsekit::Status st = ValidateCanSceneOptions(options); !st.ok()) return st;
  SceneOptions so;
  so.width = options.width;
  so.height = options.height;
  so.min_tilt_deg = options.min_tilt_deg;
  so.max_tilt_deg = options.max_tilt_deg;
  so.min_objects = so.max_objects = 2;
  so.occlusion = false;
  so.clutter_shapes = options.clutter_shapes;
  so.noise_sigma = options.noise_sigma;
  so.blur_sigma = options.blur_sigma;
  World world(so, seed);
  return world.BuildCans(options, seed, info, sink);
}

namespace {

ellipsekit::Status WriteTextFile(const std::filesystem::path& path, const std::string& text) {
  using ellipsekit::Status;
  using ellipsekit::StatusCode;
  std::string tmp_name(".");  // (appends: GCC 12 warns falsely on "literal" + string)
  tmp_name += path.filename().string();
  tmp_name += ".tmp";
  const std::filesystem::path tmp = path.parent_path() / tmp_name;
  std::FILE* f = std::fopen(tmp.string().c_str(), "wb");
  if (f == nullptr) return Status(StatusCode::kInternal, "cannot open " + tmp.string() + " for writing");
  bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  ok &= std::fclose(f) == 0;
  std::error_code ec;
  if (!ok) {
    std::filesystem::remove(tmp, ec);
    return Status(StatusCode::kInternal, "cannot write " + tmp.string());
  }
  std::filesystem::rename(tmp, path, ec);
  if (ec) return Status(StatusCode::kInternal, "cannot rename " + tmp.string() + " to " + path.string() + ": " + ec.message());
  return Status::Ok();
}

ellipsekit::Status WritePng(const std::filesystem::path& path, const cv::Mat& m) {
  using ellipsekit::Status;
  using ellipsekit::StatusCode;
  std::string tmp_name(".");
  tmp_name += path.stem().string();
  tmp_name += ".tmp.png";
  const std::filesystem::path tmp = path.parent_path() / tmp_name;
  bool written = false;
  try {
    written = cv::imwrite(tmp.string(), m);
  } catch (const cv::Exception&) {
    written = false;
  }
  std::error_code ec;
  if (!written) {
    std::filesystem::remove(tmp, ec);
    return Status(StatusCode::kInternal, "cannot write image " + tmp.string());
  }
  std::filesystem::rename(tmp, path, ec);
  if (ec) return Status(StatusCode::kInternal, "cannot rename " + tmp.string() + " to " + path.string() + ": " + ec.message());
  return Status::Ok();
}

std::string Fmt(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

template <class It>
std::string JsonList(It begin, It end, const char* fmt) {
  std::string s = "[";
  for (It it = begin; it != end; ++it) s += (it == begin ? "" : ", ") + Fmt(fmt, *it);
  return s + "]";
}

}  // namespace

namespace {

// The folders of a sequence directory (frames/, depth/), created with their parents.
ellipsekit::Status CreateDirectories(std::initializer_list<std::filesystem::path> dirs) {
  for (const auto& d : dirs) {
    std::error_code ec;
    std::filesystem::create_directories(d, ec);
    if (ec || !std::filesystem::is_directory(d, ec))
      return ellipsekit::Status(ellipsekit::StatusCode::kInternal,
                                "cannot create directory " + d.string() + ": " + ec.message());
  }
  return ellipsekit::Status::Ok();
}

// frames/NNNNNN.png (8-bit gray) and depth/NNNNNN.png (uint16 mm) of frame `index`.
ellipsekit::Status WriteFrameImages(const std::filesystem::path& frames, const std::filesystem::path& depth,
                                    int index, const cv::Mat& gray, const cv::Mat& depth_mm) {
  char name[32];
  std::snprintf(name, sizeof name, "%06d.png", index);
  if (ellipsekit::Status s = WritePng(frames / name, gray); !s.ok()) return s;
  return WritePng(depth / name, depth_mm);
}

// camera.json of a sequence (README "Sequences"): rendered frames have no lens distortion.
std::string CameraJson(int width, int height, const cv::Matx33d& K, const cv::Matx44d& T_world_camera) {
  const double D[5] = {0, 0, 0, 0, 0};
  return "{\"width\": " + std::to_string(width) + ", \"height\": " + std::to_string(height) +
         ", \"K\": " + JsonList(K.val, K.val + 9, "%.17g") + ", \"D\": " + JsonList(D, D + 5, "%.17g") +
         ", \"T_world_camera\": " + JsonList(T_world_camera.val, T_world_camera.val + 16, "%.17g") + "}\n";
}

}  // namespace

ellipsekit::Status WriteConveyorSequence(const std::string& dir, std::uint64_t seed,
                                         const ConveyorSceneOptions& options, ConveyorSequence* info) {
  using ellipsekit::Status;
  using ellipsekit::StatusCode;
  if (dir.empty()) return Status(StatusCode::kInvalidArgument, "sequence directory is empty");
  if (Status st = ValidateConveyorOptions(options); !st.ok()) return st;
  if (options.frames > 999999) return Status(StatusCode::kInvalidArgument, "at most 999999 frames (6-digit names)");
  const std::filesystem::path root(dir), frames = root / "frames", depth = root / "depth";
  if (Status st = CreateDirectories({frames, depth}); !st.ok()) return st;
  std::string times, truth;
  ConveyorSequence seq;
  Status st = RenderConveyorSequence(seed, options, &seq, [&](const ConveyorFrame& fr) {
    if (Status s = WriteFrameImages(frames, depth, fr.index, fr.gray, fr.depth_mm); !s.ok()) return s;
    times += Fmt("%.9g", fr.t) + "\n";
    const double el[5] = {fr.truth.cx, fr.truth.cy, fr.truth.a, fr.truth.b, fr.truth.theta};
    truth += "{\"t\": " + Fmt("%.9g", fr.t) + ", \"tops\": [{\"centre\": " +
             JsonList(fr.top_centre.val, fr.top_centre.val + 3, "%.6f") +
             ", \"pixel\": " + JsonList(fr.top_pixel.val, fr.top_pixel.val + 2, "%.4f") +
             ", \"ellipse\": " + JsonList(el, el + 5, "%.6f") + "}]}\n";
    return Status::Ok();
  });
  if (!st.ok()) return st;
  const std::string camera = CameraJson(seq.width, seq.height, seq.K, seq.T_world_camera);
  const std::string conveyor =
      "{\"references\": [{\"point\": " + JsonList(seq.start_point.val, seq.start_point.val + 3, "%.17g") +
      ", \"pixel\": " + JsonList(seq.start_pixel.val, seq.start_pixel.val + 2, "%.17g") + "}, {\"point\": " +
      JsonList(seq.end_point.val, seq.end_point.val + 3, "%.17g") +
      ", \"pixel\": " + JsonList(seq.end_pixel.val, seq.end_pixel.val + 2, "%.17g") + "}]}\n";
  for (const auto& [name, text] : {std::pair<const char*, const std::string*>{"timestamps.txt", &times},
                                   {"camera.json", &camera}, {"conveyor.json", &conveyor}, {"truth.jsonl", &truth}}) {
    if (Status s = WriteTextFile(root / name, *text); !s.ok()) return s;
  }
  if (info != nullptr) *info = seq;
  return Status::Ok();
}

ellipsekit::Status WriteCanSequence(const std::string& dir, std::uint64_t seed, const CanSceneOptions& options,
                                    CanSequence* info) {
  using ellipsekit::Status;
  using ellipsekit::StatusCode;
  if (dir.empty()) return Status(StatusCode::kInvalidArgument, "sequence directory is empty");
  if (Status st = ValidateCanSceneOptions(options); !st.ok()) return st;
  const std::filesystem::path root(dir), frames = root / "frames", depth = root / "depth";
  if (Status st = CreateDirectories({frames, depth}); !st.ok()) return st;
  std::string times, truth;
  CanSequence seq;
  Status st = RenderCanSequence(seed, options, &seq, [&](const CanFrame& fr) {
    if (Status s = WriteFrameImages(frames, depth, fr.index, fr.gray, fr.depth_mm); !s.ok()) return s;
    times += Fmt("%.9g", fr.t) + "\n";
    truth += "{\"t\": " + Fmt("%.9g", fr.t) + ", \"tops\": [";
    for (std::size_t k = 0; k < fr.truth.size(); ++k) {
      const ellipsekit::Ellipse& e = fr.truth[k];
      const double el[5] = {e.cx, e.cy, e.a, e.b, e.theta};
      if (k > 0) truth += ", ";
      truth += "{\"centre\": " + JsonList(fr.top_centre[k].val, fr.top_centre[k].val + 3, "%.6f") +
               ", \"pixel\": " + JsonList(fr.top_pixel[k].val, fr.top_pixel[k].val + 2, "%.4f") +
               ", \"ellipse\": " + JsonList(el, el + 5, "%.6f") + ", \"rim_visible\": " +
               Fmt("%.4f", fr.rim_visible[k]) + "}";
    }
    truth += "]}\n";
    return Status::Ok();
  });
  if (!st.ok()) return st;
  const std::string camera = CameraJson(seq.width, seq.height, seq.K, seq.T_world_camera);
  for (const auto& [name, text] : {std::pair<const char*, const std::string*>{"timestamps.txt", &times},
                                   {"camera.json", &camera}, {"truth.jsonl", &truth}}) {
    if (Status s = WriteTextFile(root / name, *text); !s.ok()) return s;
  }
  if (info != nullptr) *info = seq;
  return Status::Ok();
}

}  // namespace ellipsekit::scenes

// The scene generator's world: a tiny deterministic ray caster (scene_generator.h gives the
// contract). Private to tools/scenes/: world_setup.cc places the camera, light and objects,
// world_render.cc casts and shades the rays, world_sequences.cc renders the sequences.
//
// World frame: metres, z up, the table is the plane z = 0, optional back wall x = wall_x.
// Camera: x_cam ~ K (R X + t), R's rows are the camera's right, down and forward axes in world
// coordinates, t = -R pos. The ray of image point (u, v) is pos + s D with
// D = forward + right (u - pcx) / f + down (v - pcy) / f (not normalised: s = 1 at depth 1).
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include <opencv2/core.hpp>

#include "tools/scenes/rng.h"
#include "tools/scenes/scene_generator.h"

namespace ellipsekit::scenes::detail {

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
inline IRect ProjectBounds(const Camera& cam, const V3* pts, int n, int width, int height, int pad = 2) {
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

inline IRect ProjectTableRect(const Camera& cam, const TRect& t, int width, int height) {
  const V3 pts[4] = {{t.x0, t.y0, 0}, {t.x1, t.y0, 0}, {t.x0, t.y1, 0}, {t.x1, t.y1, 0}};
  return ProjectBounds(cam, pts, 4, width, height);
}

// ---------------------------------------------------------------- scene contents
enum class CylKind { kCan, kCup, kJar };

// Plain cylinders of the hard tabletop set (tabletop_scenes.h): a textured top and side in nearly
// one colour. kNone (the default) leaves every other scene's shading untouched.
enum class PlainMaterial { kNone, kWood, kCardboard };

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
  // Real container geometry (scene_generator.h, Container); all zero for the original shapes.
  double recess = 0;          // can: the lid's floor lies this far below the rolled rim (r_in..r)
  double floor_albedo = -1;   // cup: the contents' surface at z_floor (>= 0: filled)
  double lid_r = 0;           // jar: a lid narrower than the body, from shoulder_h up to h
  double shoulder_h = 0;
  // Bottle (bottle(): a jar with neck_h > shoulder_h): the shoulder narrows as a cone from
  // radius r at shoulder_h to lid_r at neck_h, shaded as a rounded shoulder (no crease at either
  // end); the neck runs on up to h in the body's colour but for its top cap_h, the cap (top_albedo).
  double neck_h = 0, cap_h = 0;
  bool metal_top = false;     // strong specular lid (and lid floor)
  PlainMaterial material = PlainMaterial::kNone;  // plain cylinder: texture (World::PlainTexture)
  double grain_contrast = 0, grain_period = 0.004, pith_x = 0, pith_y = 0;
  double rim_r() const { return lid_r > 0 ? lid_r : r; }  // radius of the top rim circle
  bool bottle() const { return neck_h > shoulder_h; }     // see neck_h
  IRect bbox;
  TRect shadow;
  IRect shadow_bbox;
  ellipsekit::Ellipse truth;
};

// The sequence cans' derived shape from r: r^2, the inner radius 3 mm in, the inner floor height.
inline void SetCanShape(Cylinder* c) {
  c->r2 = c->r * c->r;
  c->r_in = c->r - 0.003;
  c->r_in2 = c->r_in * c->r_in;
  c->z_floor = 0.01;
}

// What a moving cylinder changes in a frame: its bounding box and its shadow's (when not empty).
inline IRect RedrawRect(const Cylinder& c) {
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

enum class TableKind { kWood, kMottled, kPlain, kCloth };  // kCloth: the hard tabletop set only

enum Part : int { kBackground, kTable, kWall, kSide, kTop, kInner, kFloor, kBoxFace, kLidSide, kShoulder };

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

class TabletopBuilder;  // tabletop_scenes.cc: the hard tabletop set, built on this world

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
  bool FinishBoxBounds(Box* b) const;  // bbox (false when empty or > 20 % of the frame), shadow
  bool PlaceShape(ShapeKind kind);
  void PlaceCylinders();
  void ColorCylinder(Cylinder* c);
  // Turns a sequence can (ColorCylinder'd, SetCanShape'd) into `kind`; draws only from `rng`.
  static void ShapeContainer(Container kind, bool metal_top, Rng* rng, Cylinder* c);
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
  bool IntersectJar(const Cylinder& c, V3 D, double s_max, Hit* h) const;
  bool IntersectBox(const Box& b, V3 O, V3 D, double s_max, Hit* h) const;
  void Trace(V3 D, int px, int py, Hit* h) const;
  bool OccludedBefore(V3 D, double s_max, int px, int py, int skip_cyl) const;
  double Shade(const Hit& h, V3 D, V3 D_centre, TexCache* tc) const;
  double ShadeAt(double u, double v) const;
  double TableTexture(double X, double Y, double footprint) const;
  double PlainTexture(const Cylinder& c, V3 P, bool top) const;  // albedo factor; tabletop_scenes.cc
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

  friend class TabletopBuilder;
};

}  // namespace ellipsekit::scenes::detail

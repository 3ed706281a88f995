#include "tools/scenes/crowded_scenes.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "tools/scenes/conic.h"
#include "tools/scenes/rng.h"

namespace ellipsekit::scenes {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kMinPitchPx = 48;  // smallest object pitch in the image at a frontal view
constexpr int kMinObjects = 50, kMaxObjects = 300;
constexpr int kCameraTries = 30;

// One circle of the layout, in plane units (the layout's pitch is 1).
struct Object {
  double x, y, r;
  double inner;   // rings: inner radius; other kinds: unused
  double tone;    // gray level of the object's main surface
  double phase;   // caps: knurl phase; cups: direction of the light inside
};

// A region id changes across every edge the pattern draws, so pixels whose neighbours differ are
// the ones to supersample. -1: outside the layout's board; 0: board; 1 + 8 k + part: object k.
struct Sample {
  double value;
  int region;
};

class Layout {
 public:
  Layout(CrowdedLayout kind, Rng* rng, double min_ring_ratio, double max_ring_ratio)
      : kind_(kind), rng_(*rng), min_ring_ratio_(min_ring_ratio), max_ring_ratio_(max_ring_ratio) {}

  // Places rows x cols objects (hexagonal rows when `hex`), pitch 1, and the board around them.
  void Place(int rows, int cols, bool hex) {
    const double row_step = hex ? std::sqrt(3.0) / 2 : 1.0;
    double fill = 0;  // object radius / half the pitch
    switch (kind_) {
      case CrowdedLayout::kDotGrid: fill = rng_.Uniform(0.5, 0.76); break;
      case CrowdedLayout::kRingGrid: fill = rng_.Uniform(0.6, 0.84); break;
      case CrowdedLayout::kCanCrate: fill = rng_.Chance(0.5) ? 1.0 : rng_.Uniform(0.9, 1.0); break;
      case CrowdedLayout::kCapTray: fill = rng_.Uniform(0.7, 0.95); break;
      default: fill = rng_.Uniform(0.85, 1.0); break;
    }
    const double inner = rng_.Uniform(min_ring_ratio_, max_ring_ratio_);
    board_tone_ = kind_ == CrowdedLayout::kDotGrid || kind_ == CrowdedLayout::kRingGrid ? rng_.Uniform(185, 240)
                  : kind_ == CrowdedLayout::kCanCrate                                     ? rng_.Uniform(25, 60)
                                                                                          : rng_.Uniform(70, 150);
    const double print_tone = rng_.Uniform(15, 70);
    for (int i = 0; i < rows; ++i) {
      for (int j = 0; j < cols; ++j) {
        Object o;
        o.x = j + (hex && (i % 2) ? 0.5 : 0.0);
        o.y = i * row_step;
        o.r = 0.5 * fill;
        o.inner = o.r * inner;
        o.phase = rng_.Uniform(0, 2 * kPi);
        switch (kind_) {
          case CrowdedLayout::kCanCrate: o.tone = rng_.Uniform(140, 215); break;
          case CrowdedLayout::kCapTray: {
            // Each cap its own colour, at least 45 gray levels from the tray.
            do o.tone = rng_.Uniform(20, 235); while (std::abs(o.tone - board_tone_) < 45);
            break;
          }
          case CrowdedLayout::kCupTray: o.tone = rng_.Uniform(195, 240); break;
          default: o.tone = print_tone; break;
        }
        objects_.push_back(o);
      }
    }
    min_x_ = -0.5 - 0.6;
    min_y_ = -0.5 - 0.6;
    max_x_ = cols - 1 + (hex && rows > 1 ? 0.5 : 0.0) + 0.5 + 0.6;
    max_y_ = (rows - 1) * row_step + 0.5 + 0.6;
    // Buckets of unit cells over the board: an object is found in the 3x3 cells around a point.
    bx_ = static_cast<int>(std::ceil(max_x_ - min_x_)) + 1;
    by_ = static_cast<int>(std::ceil(max_y_ - min_y_)) + 1;
    buckets_.assign(static_cast<std::size_t>(bx_) * by_, {});
    for (int k = 0; k < static_cast<int>(objects_.size()); ++k) {
      const int cx = static_cast<int>(objects_[k].x - min_x_), cy = static_cast<int>(objects_[k].y - min_y_);
      buckets_[static_cast<std::size_t>(cy) * bx_ + cx].push_back(k);
    }
  }

  Sample At(double x, double y) const {
    if (x < min_x_ || y < min_y_ || x > max_x_ || y > max_y_) return {-1, -1};
    const int cx = static_cast<int>(x - min_x_), cy = static_cast<int>(y - min_y_);
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const int bx = cx + dx, by = cy + dy;
        if (bx < 0 || by < 0 || bx >= bx_ || by >= by_) continue;
        for (int k : buckets_[static_cast<std::size_t>(by) * bx_ + bx]) {
          const Object& o = objects_[k];
          const double d = std::hypot(x - o.x, y - o.y);
          if (d < o.r) return ObjectAt(k, x - o.x, y - o.y, d);
        }
      }
    }
    return {board_tone_, 0};
  }

  const std::vector<Object>& objects() const { return objects_; }
  double min_x() const { return min_x_; }
  double min_y() const { return min_y_; }
  double max_x() const { return max_x_; }
  double max_y() const { return max_y_; }

 private:
  Sample ObjectAt(int k, double dx, double dy, double d) const {
    const Object& o = objects_[k];
    const int id = 1 + 8 * k;
    const double t = d / o.r;  // 0 at the centre, 1 on the outer edge
    switch (kind_) {
      case CrowdedLayout::kDotGrid: return {o.tone, id};
      case CrowdedLayout::kRingGrid: return d < o.inner ? Sample{board_tone_, id + 1} : Sample{o.tone, id};
      case CrowdedLayout::kCanCrate:
        // Rolled rim (bright, shaded across its width), the lid's raised ring, the groove, the lid.
        if (t > 0.9) return {o.tone * (0.9 + 0.1 * std::sin((t - 0.9) * 10 * kPi)), id};
        if (t > 0.84) return {o.tone * 0.78, id + 1};
        if (t > 0.8) return {o.tone * 0.55, id + 2};
        return {o.tone * (0.72 + 0.08 * (dx * std::cos(o.phase) + dy * std::sin(o.phase)) / o.r), id + 3};
      case CrowdedLayout::kCapTray: {
        if (t < 0.86) return {o.tone, id};
        // Knurled edge: 24 ridges round the cap.
        const double a = std::atan2(dy, dx) + o.phase;
        const int ridge = static_cast<int>(std::floor((a / (2 * kPi) + 1) * 24)) % 2;
        return {o.tone * (ridge ? 0.88 : 1.0), id + 1 + ridge};
      }
      default: {
        if (t > 0.9) return {o.tone, id};  // the lip
        // Inside: the far inner wall lit, the near one in shade, the bottom darkest.
        const double lit = (dx * std::cos(o.phase) + dy * std::sin(o.phase)) / o.r;
        return {45 + 55 * std::max(0.0, lit) * t + 20 * t, id + 1};
      }
    }
  }

  CrowdedLayout kind_;
  Rng& rng_;
  double min_ring_ratio_, max_ring_ratio_;
  std::vector<Object> objects_;
  std::vector<std::vector<int>> buckets_;
  int bx_ = 0, by_ = 0;
  double board_tone_ = 128;
  double min_x_ = 0, min_y_ = 0, max_x_ = 0, max_y_ = 0;
};

// The plane-to-image homography of a camera tilted `tilt` off the plane's normal at azimuth `azimuth`,
// rolled by `roll`, `distance` (plane units) from the point (cx, cy); focal length 1 (scaled later).
cv::Matx33d PlaneToImage(double cx, double cy, double tilt, double azimuth, double roll, double distance) {
  const cv::Vec3d target(cx, cy, 0);
  const cv::Vec3d eye = target + distance * cv::Vec3d(std::sin(tilt) * std::cos(azimuth),
                                                      std::sin(tilt) * std::sin(azimuth), std::cos(tilt));
  const cv::Vec3d f = cv::normalize(target - eye);
  const cv::Vec3d side(-std::sin(azimuth), std::cos(azimuth), 0);
  const cv::Vec3d x0 = cv::normalize(side - side.dot(f) * f);
  const cv::Vec3d y0 = f.cross(x0);
  const cv::Vec3d x = std::cos(roll) * x0 + std::sin(roll) * y0;
  const cv::Vec3d y = -std::sin(roll) * x0 + std::cos(roll) * y0;
  const cv::Matx33d R(x[0], x[1], x[2], y[0], y[1], y[2], f[0], f[1], f[2]);
  const cv::Vec3d t = -(R * eye);
  // Columns r1, r2 (the plane's axes) and t.
  return cv::Matx33d(R(0, 0), R(0, 1), t[0], R(1, 0), R(1, 1), t[1], R(2, 0), R(2, 1), t[2]);
}

cv::Point2d Apply(const cv::Matx33d& h, double x, double y) {
  const cv::Vec3d p = h * cv::Vec3d(x, y, 1);
  return {p[0] / p[2], p[1] / p[2]};
}

class Renderer {
 public:
  Renderer(std::uint64_t seed, const CrowdedSceneOptions& o) : rng_(seed), opt_(o) {}

  Scene Build() {
    static const int kSizes[3][2] = {{640, 480}, {1280, 720}, {1920, 1080}};
    const int size = rng_.Int(0, 2);
    W_ = opt_.width > 0 ? opt_.width : kSizes[size][0];
    H_ = opt_.height > 0 ? opt_.height : kSizes[size][1];
    CrowdedLayout kind = opt_.layout;
    if (kind == CrowdedLayout::kAny) kind = static_cast<CrowdedLayout>(rng_.Int(1, 5));
    const bool grid = kind == CrowdedLayout::kDotGrid || kind == CrowdedLayout::kRingGrid;

    // Rows x columns: the frame's aspect, objects limited by the smallest pitch the frame can show.
    const double aspect = static_cast<double>(W_) / H_;
    const int frame_max = std::max(12, static_cast<int>(W_ * H_ / (kMinPitchPx * kMinPitchPx) * 0.5));
    int n = opt_.objects > 0 ? opt_.objects
                             : rng_.Int(std::min(kMinObjects, frame_max), std::min(kMaxObjects, frame_max));
    int rows = std::max(1, static_cast<int>(std::lround(std::sqrt(n / aspect))));
    int cols = std::max(1, (n + rows / 2) / rows);
    if (opt_.objects > 0) {  // exactly the number asked for: the factorisation nearest the aspect
      double best = HUGE_VAL;
      for (int r = 1; r <= n; ++r) {
        if (n % r != 0) continue;
        const double miss = std::abs(std::log(static_cast<double>(n / r) / r / aspect));
        if (miss < best) { best = miss; rows = r; cols = n / r; }
      }
    }
    const bool hex = !grid && rng_.Chance(0.5);
    Layout layout(kind, &rng_, opt_.min_ring_ratio, opt_.max_ring_ratio);
    layout.Place(rows, cols, hex);

    // Camera: tilt, azimuth, roll, distance (perspective strength), fitted into the frame; drawn
    // again (up to kCameraTries times, then the closest to the size floor is kept) while the
    // smallest object's image would be smaller than min_semi_minor_px.
    Scene scene;
    cv::Matx33d best_plane;
    double best_min_b = -1;
    for (int attempt = 0; attempt < kCameraTries; ++attempt) {
      DrawCamera(layout);
      scene.truth.clear();
      for (const Object& o : layout.objects()) {
        AddTruth(o.x, o.y, o.r, &scene);
        if (kind == CrowdedLayout::kRingGrid) AddTruth(o.x, o.y, o.inner, &scene);
      }
      double min_b = 1e300;
      for (const ellipsekit::Ellipse& e : scene.truth) min_b = std::min(min_b, e.b);
      if (min_b > best_min_b) {
        best_min_b = min_b;
        best_plane = H_plane_;
      }
      if (min_b >= opt_.min_semi_minor_px) break;
    }
    H_plane_ = best_plane;
    H_image_ = H_plane_.inv();
    scene.truth.clear();
    for (const Object& o : layout.objects()) {
      AddTruth(o.x, o.y, o.r, &scene);
      if (kind == CrowdedLayout::kRingGrid) AddTruth(o.x, o.y, o.inner, &scene);
    }
    if (opt_.clutter) {
      DrawClutter();
      std::erase_if(scene.truth, [&](const ellipsekit::Ellipse& e) { return VisibleShare(e) < kClutterMinVisible; });
    }
    Render(layout, kind, &scene.gray);
    return scene;
  }

 private:
  // A bar (rotated rectangle) or a cable (a quadratic Bezier curve as a 32-segment polyline) above
  // the layout, or a mark printed on the table (a short thin bar, drawn only where the table shows).
  struct Shape {
    bool cable = false, mark = false;
    double cx = 0, cy = 0, ux = 1, uy = 0, half_length = 0, half_width = 0;  // a bar or a mark
    std::vector<cv::Point2d> path;                                          // a cable
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;                                  // its bounding box
    double tone = 0;
    // A bar's or a mark's frame: (u, v) along and across its axis, from its centre.
    double Along(double u, double v) const { return (u - cx) * ux + (v - cy) * uy; }
    double Across(double u, double v) const { return -(u - cx) * uy + (v - cy) * ux; }
  };

  void DrawClutter() {
    const double diag = std::hypot(W_, H_), side = std::min(W_, H_);
    auto bar = [&](double length, double width, bool mark) {
      Shape b;
      b.mark = mark;
      const double angle = rng_.Uniform(0, kPi);
      b.cx = rng_.Uniform(0, W_);
      b.cy = rng_.Uniform(0, H_);
      b.ux = std::cos(angle);
      b.uy = std::sin(angle);
      b.half_length = 0.5 * length;
      b.half_width = 0.5 * width;
      b.tone = rng_.Uniform(15, 240);
      shapes_.push_back(b);
    };
    for (int i = rng_.Int(1, 3); i > 0; --i) bar(rng_.Uniform(0.3, 0.8) * diag, rng_.Uniform(0.03, 0.1) * side, false);
    for (int i = rng_.Int(0, 2); i > 0; --i) {
      Shape c;
      c.cable = true;
      const cv::Point2d p0(rng_.Uniform(0, W_), rng_.Uniform(0, H_)), p1(rng_.Uniform(0, W_), rng_.Uniform(0, H_)),
          p2(rng_.Uniform(0, W_), rng_.Uniform(0, H_));
      for (int k = 0; k <= 32; ++k) {
        const double t = k / 32.0;
        c.path.push_back((1 - t) * (1 - t) * p0 + 2 * t * (1 - t) * p1 + t * t * p2);
      }
      c.half_width = 0.5 * rng_.Uniform(3, 10);
      c.x0 = c.y0 = 1e300;
      c.x1 = c.y1 = -1e300;
      for (const cv::Point2d& q : c.path) {
        c.x0 = std::min(c.x0, q.x - c.half_width);
        c.y0 = std::min(c.y0, q.y - c.half_width);
        c.x1 = std::max(c.x1, q.x + c.half_width);
        c.y1 = std::max(c.y1, q.y + c.half_width);
      }
      c.tone = rng_.Uniform(10, 200);
      shapes_.push_back(c);
    }
    for (int i = rng_.Int(6, 20); i > 0; --i) bar(rng_.Uniform(0.01, 0.08) * diag, rng_.Uniform(1.5, 6), true);
  }

  // The shape covering image point (u, v), topmost first (bars and cables over marks); -1: none.
  // Marks count only where the table shows (`table`).
  int ShapeAt(double u, double v, bool table) const {
    for (int k = static_cast<int>(shapes_.size()) - 1; k >= 0; --k) {
      const Shape& s = shapes_[k];
      if (s.mark && !table) continue;
      if (!s.cable) {
        if (std::abs(s.Along(u, v)) <= s.half_length && std::abs(s.Across(u, v)) <= s.half_width) return k;
        continue;
      }
      if (u < s.x0 || v < s.y0 || u > s.x1 || v > s.y1) continue;
      for (std::size_t i = 1; i < s.path.size(); ++i) {
        const cv::Point2d a = s.path[i - 1], d = s.path[i] - a, p(u - a.x, v - a.y);
        const double len2 = d.dot(d);
        const double t = len2 > 0 ? std::clamp(p.dot(d) / len2, 0.0, 1.0) : 0.0;
        if (std::hypot(p.x - t * d.x, p.y - t * d.y) <= s.half_width) return k;
      }
    }
    return -1;
  }

  // The share of 360 points on e's outline that no bar or cable hides.
  double VisibleShare(const ellipsekit::Ellipse& e) const {
    const double c = std::cos(e.theta), s = std::sin(e.theta);
    int visible = 0;
    for (int i = 0; i < 360; ++i) {
      const double t = i * kPi / 180, x = e.a * std::cos(t), y = e.b * std::sin(t);
      visible += ShapeAt(e.cx + c * x - s * y, e.cy + s * x + c * y, false) < 0;
    }
    return visible / 360.0;
  }

  void DrawCamera(const Layout& layout) {
    const double tilt = rng_.Uniform(0, opt_.max_tilt_deg) * kPi / 180;
    const double extent = std::hypot(layout.max_x() - layout.min_x(), layout.max_y() - layout.min_y());
    const double cx = 0.5 * (layout.min_x() + layout.max_x()), cy = 0.5 * (layout.min_y() + layout.max_y());
    const cv::Matx33d P = PlaneToImage(cx, cy, tilt, rng_.Uniform(0, 2 * kPi), rng_.Uniform(-kPi, kPi),
                                       extent * rng_.Uniform(0.9, 2.5));
    double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
    const double corners[4][2] = {{layout.min_x(), layout.min_y()}, {layout.max_x(), layout.min_y()},
                                  {layout.min_x(), layout.max_y()}, {layout.max_x(), layout.max_y()}};
    for (const auto& c : corners) {
      const cv::Point2d p = Apply(P, c[0], c[1]);
      x0 = std::min(x0, p.x); y0 = std::min(y0, p.y); x1 = std::max(x1, p.x); y1 = std::max(y1, p.y);
    }
    const double margin = 4;
    const double s = std::min((W_ - 1 - 2 * margin) / (x1 - x0), (H_ - 1 - 2 * margin) / (y1 - y0)) *
                     rng_.Uniform(0.85, 1.0);
    const double ox = margin + rng_.Uniform(0, std::max(0.0, W_ - 1 - 2 * margin - s * (x1 - x0))) - s * x0;
    const double oy = margin + rng_.Uniform(0, std::max(0.0, H_ - 1 - 2 * margin - s * (y1 - y0))) - s * y0;
    H_plane_ = cv::Matx33d(s, 0, ox, 0, s, oy, 0, 0, 1) * P;
    H_image_ = H_plane_.inv();
  }

  void AddTruth(double x, double y, double r, Scene* scene) const {
    const cv::Matx33d circle(1, 0, -x, 0, 1, -y, -x, -y, x * x + y * y - r * r);
    ellipsekit::Ellipse e;
    if (ConicToEllipse(H_image_.t() * circle * H_image_, &e)) scene->truth.push_back(e);
  }

  void Render(const Layout& layout, CrowdedLayout kind, cv::Mat* gray) {
    // Light: a gradient across the frame and, on metal and ceramic, glare spots.
    const double gx = rng_.Uniform(-0.3, 0.3) / W_, gy = rng_.Uniform(-0.3, 0.3) / H_;
    struct Spot { double x, y, radius, gain; };
    std::vector<Spot> spots;
    const int n_spots = kind == CrowdedLayout::kCanCrate || kind == CrowdedLayout::kCupTray ? rng_.Int(0, 3)
                        : kind == CrowdedLayout::kCapTray                                   ? rng_.Int(0, 1)
                                                                                            : 0;
    for (int i = 0; i < n_spots; ++i)
      spots.push_back({rng_.Uniform(0, W_), rng_.Uniform(0, H_), rng_.Uniform(0.03, 0.12) * W_, rng_.Uniform(40, 110)});
    const double table = rng_.Uniform(60, 200), wave = rng_.Uniform(0.01, 0.04), wave_phase = rng_.Uniform(0, 6);

    auto shade = [&](double u, double v) {
      const cv::Point2d p = Apply(H_image_, u, v);
      Sample s = layout.At(p.x, p.y);
      if (const int k = shapes_.empty() ? -1 : ShapeAt(u, v, s.region < 0); k >= 0) {
        const Shape& sh = shapes_[k];
        double value = sh.tone;
        if (!sh.cable && !sh.mark) {  // a bar is rounded: brightest along its middle
          const double across = sh.Across(u, v) / sh.half_width;
          value *= 0.75 + 0.25 * std::sqrt(std::max(0.0, 1 - across * across));
        }
        return Sample{value, kShapeRegion + k};
      }
      if (s.region < 0) s.value = table * (1 + 0.12 * std::sin(wave * (u + 0.7 * v) + wave_phase));
      double value = s.value * (1 + gx * (u - 0.5 * W_) + gy * (v - 0.5 * H_));
      for (const Spot& g : spots) {
        const double d2 = ((u - g.x) * (u - g.x) + (v - g.y) * (v - g.y)) / (g.radius * g.radius);
        if (d2 < 9 && s.region > 0) value += g.gain * std::exp(-0.5 * d2);
      }
      return Sample{value, s.region};
    };

    // Pixel centres first; then 4x4 samples where a neighbour lies in another region (an edge).
    cv::Mat1f img(H_, W_);
    cv::Mat1i region(H_, W_);
    for (int y = 0; y < H_; ++y) {
      for (int x = 0; x < W_; ++x) {
        const Sample s = shade(x, y);
        img(y, x) = static_cast<float>(s.value);
        region(y, x) = s.region;
      }
    }
    for (int y = 0; y < H_; ++y) {
      for (int x = 0; x < W_; ++x) {
        const int r = region(y, x);
        const bool edge = (x > 0 && region(y, x - 1) != r) || (x + 1 < W_ && region(y, x + 1) != r) ||
                          (y > 0 && region(y - 1, x) != r) || (y + 1 < H_ && region(y + 1, x) != r);
        if (!edge) continue;
        double sum = 0;
        for (int i = 0; i < 4; ++i)
          for (int j = 0; j < 4; ++j) sum += shade(x + (j + 0.5) / 4 - 0.5, y + (i + 0.5) / 4 - 0.5).value;
        img(y, x) = static_cast<float>(sum / 16);
      }
    }
    const double blur = rng_.Uniform(0.5, 1.5), noise = rng_.Uniform(1.5, 5);
    cv::GaussianBlur(img, img, cv::Size(0, 0), blur, blur, cv::BORDER_REFLECT_101);
    gray->create(H_, W_, CV_8UC1);
    for (int y = 0; y < H_; ++y) {
      for (int x = 0; x < W_; ++x) {
        const double v = img(y, x) + noise * rng_.Normal();
        gray->at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(std::clamp(std::floor(v + 0.5), 0.0, 255.0));
      }
    }
  }

  static constexpr int kShapeRegion = 1 << 28;  // region ids of shapes: above every object's
  Rng rng_;
  CrowdedSceneOptions opt_;
  std::vector<Shape> shapes_;  // CrowdedSceneOptions::clutter, in drawing order
  int W_ = 0, H_ = 0;
  cv::Matx33d H_plane_, H_image_;  // plane -> image, image -> plane
};

}  // namespace

ellipsekit::Status ValidateCrowdedSceneOptions(const CrowdedSceneOptions& o) {
  auto bad = [](const std::string& m) { return ellipsekit::Status(ellipsekit::StatusCode::kInvalidArgument, m); };
  const bool drawn = o.width == 0 && o.height == 0;
  if (!drawn && (o.width < 64 || o.width > 8192 || o.height < 64 || o.height > 8192))
    return bad("crowded scene size must be 64..8192 px (or 0x0: drawn per scene), got " + std::to_string(o.width) +
               "x" + std::to_string(o.height));
  if (o.objects < 0 || o.objects > 2000) return bad("objects must be 0..2000, got " + std::to_string(o.objects));
  if (!(o.max_tilt_deg >= 0 && o.max_tilt_deg <= 70)) return bad("max_tilt_deg must be in [0, 70]");
  if (!(o.min_semi_minor_px >= 0 && o.min_semi_minor_px <= 100)) return bad("min_semi_minor_px must be in [0, 100]");
  if (!(o.min_ring_ratio >= 0.1 && o.min_ring_ratio <= o.max_ring_ratio && o.max_ring_ratio <= 0.9))
    return bad("ring ratios must satisfy 0.1 <= min_ring_ratio <= max_ring_ratio <= 0.9");
  switch (o.layout) {
    case CrowdedLayout::kAny: case CrowdedLayout::kDotGrid: case CrowdedLayout::kRingGrid:
    case CrowdedLayout::kCanCrate: case CrowdedLayout::kCapTray: case CrowdedLayout::kCupTray: break;
    default: return bad("layout is not one of any, dots, rings, cans, caps, cups");
  }
  return ellipsekit::Status::Ok();
}

Scene RenderCrowdedScene(std::uint64_t seed, const CrowdedSceneOptions& options) {
  if (!ValidateCrowdedSceneOptions(options).ok()) return Scene();
  return Renderer(seed, options).Build();
}

ellipsekit::Status WriteCrowdedDataset(const std::string& dir, int count, std::uint64_t seed,
                                       const CrowdedSceneOptions& options) {
  if (ellipsekit::Status st = ValidateCrowdedSceneOptions(options); !st.ok()) return st;
  return WriteDataset(dir, count, seed, [&options](std::uint64_t s) { return RenderCrowdedScene(s, options); });
}

const char* CrowdedLayoutName(CrowdedLayout layout) {
  switch (layout) {
    case CrowdedLayout::kAny: return "any";
    case CrowdedLayout::kDotGrid: return "dots";
    case CrowdedLayout::kRingGrid: return "rings";
    case CrowdedLayout::kCanCrate: return "cans";
    case CrowdedLayout::kCapTray: return "caps";
    case CrowdedLayout::kCupTray: return "cups";
  }
  return "?";
}

bool ParseCrowdedLayout(const std::string& name, CrowdedLayout* layout) {
  for (CrowdedLayout l : {CrowdedLayout::kAny, CrowdedLayout::kDotGrid, CrowdedLayout::kRingGrid,
                          CrowdedLayout::kCanCrate, CrowdedLayout::kCapTray, CrowdedLayout::kCupTray}) {
    if (name == CrowdedLayoutName(l)) {
      *layout = l;
      return true;
    }
  }
  return false;
}

}  // namespace ellipsekit::scenes

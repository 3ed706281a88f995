// The hard tabletop set (tabletop_scenes.h), built on the scene generator's world (world.h): its
// camera is placed by distance, its containers reuse World::ShapeContainer's real geometry, and
// every top's visible fraction comes from the world's own ray caster.
#include "tools/scenes/tabletop_scenes.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include "tools/scenes/rng.h"
#include "tools/scenes/world.h"

namespace ellipsekit::scenes {
namespace detail {

// ---------------------------------------------------------------- plain cylinders' texture
// An albedo factor around 1. Wood: end grain (growth rings round an off-centre pith) on the top,
// long grain on the side; cardboard: a fine mottle and, on the side, the tube's spiral seam.
double World::PlainTexture(const Cylinder& c, V3 P, bool top) const {
  const double dx = P.x - c.x, dy = P.y - c.y;
  const double fine = Noise(dx * 400 + 13.7, (top ? dy : P.z) * 400 + 71.3) - 0.5;
  if (c.material == PlainMaterial::kWood) {
    double w;
    if (top) {
      const double rho = std::hypot(dx - c.pith_x, dy - c.pith_y);
      w = rho / c.grain_period + 0.8 * Noise(std::atan2(dy, dx) * 2 + 40.5, rho * 60 + 9.1);
    } else {
      const double s = std::atan2(dy, dx) * c.r;  // arc length round the side
      w = s / (1.5 * c.grain_period) + 2.0 * Noise(s * 30 + 3.3, P.z * 6 + 1.7);
    }
    const double tri = std::abs(2 * (w - std::floor(w)) - 1);
    return 1 + c.grain_contrast * (tri * tri * (3 - 2 * tri) - 0.5) + 0.08 * fine;
  }
  if (top) return 1 + c.grain_contrast * fine + 0.05 * (Noise(dx * 60 + 5.5, dy * 60 + 2.5) - 0.5);
  const double q = std::atan2(dy, dx) / (2 * kPi) + P.z / 0.06;  // a seam climbing 6 cm a turn
  const double seam = std::abs(q - std::floor(q + 0.5)) * 2 * kPi * c.r < 0.0006 ? 0.85 : 1.0;
  return seam * (1 + c.grain_contrast * fine);
}

class TabletopBuilder {
 public:
  TabletopBuilder(const TabletopSceneOptions& o, std::uint64_t seed) : o_(o), w_(WorldOptions(o), seed) {}
  TabletopScene Build();

 private:
  static SceneOptions WorldOptions(const TabletopSceneOptions& o) {
    SceneOptions so;
    so.width = o.width;
    so.height = o.height;
    so.noise_sigma = o.noise_sigma;
    so.blur_sigma = o.blur_sigma;
    return so;
  }
  void SetupCamera();
  void SetupTable();
  TabletopKind DrawKind();
  Cylinder MakeContainer(TabletopKind kind);
  bool ClearOfOthers(const Cylinder& c) const;
  void PlaceContainer();
  void PlaceOccluder();
  bool AllTopsVisible() const;
  double VisibleFraction(int i, double* in_frame) const;

  TabletopSceneOptions o_;
  World w_;
  std::vector<TabletopKind> kinds_;  // per cylinder of w_
};

void TabletopBuilder::SetupCamera() {
  Rng& rng = w_.rng_;
  Camera& cam = w_.cam_;
  const double tilt = rng.Uniform(o_.min_tilt_deg, o_.max_tilt_deg) * kPi / 180;
  const double yaw = rng.Uniform(-15, 15) * kPi / 180;
  const double roll = rng.Uniform(-5, 5) * kPi / 180;
  const double dist = rng.Uniform(o_.min_distance_m, o_.max_distance_m);
  cam.f = rng.Uniform(500, 700) * w_.W_ / 640.0;
  cam.pcx = (w_.W_ - 1) / 2.0;
  cam.pcy = (w_.H_ - 1) / 2.0;
  const V3 fwd{std::cos(tilt) * std::cos(yaw), std::cos(tilt) * std::sin(yaw), -std::sin(tilt)};
  const V3 right0{std::sin(yaw), -std::cos(yaw), 0};
  const V3 down0 = Cross(fwd, right0);
  cam.fwd = fwd;
  cam.right = right0 * std::cos(roll) + down0 * std::sin(roll);
  cam.down = down0 * std::cos(roll) - right0 * std::sin(roll);
  const V3 target{rng.Uniform(-0.05, 0.05), rng.Uniform(-0.05, 0.05), 0};
  cam.pos = target - fwd * dist;
}

// The world's light and surfaces, then a table drawn for this set: wood 40 %, cloth 30 %,
// mottled 20 %, plain 10 %.
void TabletopBuilder::SetupTable() {
  w_.SetupLightAndSurfaces();
  Rng& rng = w_.rng_;
  const double pick = rng.Uniform();
  w_.table_kind_ = pick < 0.4 ? TableKind::kWood
                   : pick < 0.7 ? TableKind::kCloth
                   : pick < 0.9 ? TableKind::kMottled
                                : TableKind::kPlain;
  if (w_.table_kind_ == TableKind::kCloth) w_.noise_contrast_ = rng.Uniform(0.05, 0.2);
}

TabletopKind TabletopBuilder::DrawKind() {
  if (o_.bottles && w_.rng_.Chance(kBottleShare)) return TabletopKind::kBottle;
  const double p = w_.rng_.Uniform();
  return p < 0.25   ? TabletopKind::kCan
         : p < 0.45 ? TabletopKind::kCup
         : p < 0.65 ? TabletopKind::kJar
         : p < 0.83 ? TabletopKind::kWood
                    : TabletopKind::kCardboard;
}

Cylinder TabletopBuilder::MakeContainer(TabletopKind kind) {
  Rng& rng = w_.rng_;
  Cylinder c;
  switch (kind) {
    case TabletopKind::kCan:
      c.kind = CylKind::kCan;
      c.r = rng.Uniform(0.026, 0.034);
      c.h = rng.Uniform(0.095, 0.125);
      break;
    case TabletopKind::kCup:
      c.kind = CylKind::kCup;
      c.r = rng.Uniform(0.035, 0.05);
      c.h = rng.Uniform(0.07, 0.105);
      break;
    case TabletopKind::kJar:
      c.kind = CylKind::kJar;
      c.r = rng.Uniform(0.03, 0.05);
      c.h = rng.Uniform(0.08, 0.15);
      break;
    case TabletopKind::kBottle:
      c.kind = CylKind::kJar;
      c.r = rng.Uniform(0.028, 0.042);
      c.h = rng.Uniform(0.16, 0.26);
      break;
    case TabletopKind::kWood:
    case TabletopKind::kCardboard:
      c.kind = CylKind::kCan;
      c.r = rng.Uniform(0.02, 0.05);
      c.h = rng.Uniform(0.04, 0.18);
      break;
  }
  SetCanShape(&c);
  w_.ColorCylinder(&c);
  switch (kind) {
    case TabletopKind::kCan:
      World::ShapeContainer(Container::kRecessedCan, rng.Chance(0.4), &rng, &c);
      break;
    case TabletopKind::kCup:
      World::ShapeContainer(rng.Chance(0.25) ? Container::kCupFilled : Container::kCupEmpty, false, &rng, &c);
      break;
    case TabletopKind::kJar:
      World::ShapeContainer(Container::kJar, rng.Chance(0.25), &rng, &c);
      break;
    case TabletopKind::kBottle:
      World::ShapeContainer(Container::kBottle, rng.Chance(0.25), &rng, &c);
      break;
    case TabletopKind::kWood:
    case TabletopKind::kCardboard: {
      const bool wood = kind == TabletopKind::kWood;
      c.material = wood ? PlainMaterial::kWood : PlainMaterial::kCardboard;
      c.has_rim = c.has_label = c.has_neck = c.has_print = false;
      c.spec = 0;
      c.side_albedo = wood ? rng.Uniform(0.3, 0.75) : rng.Uniform(0.35, 0.65);
      c.top_albedo = c.side_albedo * (wood ? rng.Uniform(0.8, 1.1) : rng.Uniform(0.92, 1.1));
      c.grain_contrast = wood ? rng.Uniform(0.15, 0.35) : rng.Uniform(0.05, 0.12);
      c.grain_period = rng.Uniform(0.002, 0.005);
      c.pith_x = rng.Uniform(-0.3, 0.3) * c.r;
      c.pith_y = rng.Uniform(-0.3, 0.3) * c.r;
      break;
    }
  }
  return c;
}

// Footprints apart: 4 mm from every container and box already placed.
bool TabletopBuilder::ClearOfOthers(const Cylinder& c) const {
  for (const Cylinder& o : w_.cyl_)
    if (std::hypot(o.x - c.x, o.y - c.y) < o.r + c.r + 0.004) return false;
  for (const Box& b : w_.box_) {
    const double dx = c.x - b.x, dy = c.y - b.y;
    const double lx = dx * b.c + dy * b.s, ly = -dx * b.s + dy * b.c;
    const double qx = lx - Clamp(lx, -b.hx, b.hx), qy = ly - Clamp(ly, -b.hy, b.hy);
    if (std::hypot(qx, qy) < c.r + 0.004) return false;
  }
  return true;
}

double TabletopBuilder::VisibleFraction(int i, double* in_frame) const {
  const Cylinder& c = w_.cyl_[i];
  constexpr int kSamples = 360;
  int inside = 0, visible = 0;
  for (int k = 0; k < kSamples; ++k) {
    const double phi = 2 * kPi * k / kSamples;
    const V3 P{c.x + c.rim_r() * std::cos(phi), c.y + c.rim_r() * std::sin(phi), c.h};
    double u = 0, v = 0;
    if (!w_.cam_.Project(P, &u, &v)) continue;
    if (!(u >= -0.5 && u < w_.W_ - 0.5 && v >= -0.5 && v < w_.H_ - 0.5)) continue;
    ++inside;
    const int px = std::clamp(static_cast<int>(std::lround(u)), 0, w_.W_ - 1);
    const int py = std::clamp(static_cast<int>(std::lround(v)), 0, w_.H_ - 1);
    if (!w_.OccludedBefore(P - w_.cam_.pos, 1 - 1e-9, px, py, i)) ++visible;
  }
  if (in_frame != nullptr) *in_frame = static_cast<double>(inside) / kSamples;
  return static_cast<double>(visible) / kSamples;
}

bool TabletopBuilder::AllTopsVisible() const {
  for (int i = 0; i < static_cast<int>(w_.cyl_.size()); ++i)
    if (VisibleFraction(i, nullptr) < o_.min_visible_fraction) return false;
  return true;
}

void TabletopBuilder::PlaceContainer() {
  Rng& rng = w_.rng_;
  const int W = w_.W_, H = w_.H_;
  for (int tries = 0; tries < 60; ++tries) {
    const TabletopKind kind = DrawKind();
    Cylinder c = MakeContainer(kind);
    const bool edge = rng.Chance(o_.edge_cut_share);
    const double lo = edge ? -0.08 : 0.06, hi = edge ? 1.08 : 0.94;
    V3 top;
    if (!w_.TablePointAt(rng.Uniform(lo, hi) * W, rng.Uniform(lo, hi) * H, c.h, &top)) continue;
    c.x = top.x;
    c.y = top.y;
    if (w_.has_wall_ && c.x + c.r > w_.wall_x_ - 0.01) continue;
    if (!w_.ComputeTruth(&c)) continue;
    if (c.truth.b < 5 || c.truth.a > 0.4 * std::min(W, H) || !ClearOfOthers(c)) continue;
    w_.FinishCylinderBounds(&c);
    w_.cyl_.push_back(c);
    kinds_.push_back(kind);
    if (AllTopsVisible()) return;
    w_.cyl_.pop_back();
    kinds_.pop_back();
  }
}

// A box between a container and the camera, offset sideways, about as tall as the container:
// it hides part of the top (kept only while every top stays visible enough).
void TabletopBuilder::PlaceOccluder() {
  Rng& rng = w_.rng_;
  for (int tries = 0; tries < 15 && !w_.cyl_.empty(); ++tries) {
    const Cylinder& t = w_.cyl_[rng.Int(0, static_cast<int>(w_.cyl_.size()) - 1)];
    V3 dir{w_.cam_.pos.x - t.x, w_.cam_.pos.y - t.y, 0};
    if (Dot(dir, dir) < 1e-12) continue;
    dir = Normalize(dir);
    const V3 perp{-dir.y, dir.x, 0};
    Box b;
    b.hx = rng.Uniform(0.015, 0.05);  // along the view
    b.hy = rng.Uniform(0.02, 0.08);   // across
    b.hz = std::min(0.25, t.h * rng.Uniform(0.8, 1.5));
    const double lat = rng.Uniform(-1, 1) * (t.r + 0.5 * b.hy), gap = rng.Uniform(0.005, 0.03);
    b.x = t.x + dir.x * (t.r + gap + b.hx) + perp.x * lat;
    b.y = t.y + dir.y * (t.r + gap + b.hx) + perp.y * lat;
    const double a = std::atan2(dir.y, dir.x) + rng.Uniform(-0.3, 0.3);
    b.c = std::cos(a);
    b.s = std::sin(a);
    b.bound_r = std::hypot(b.hx, b.hy);
    b.albedo = rng.Uniform(0.1, 0.9);
    b.has_print = rng.Chance(0.5);
    b.print_hx = b.hx * rng.Uniform(0.3, 0.8);
    b.print_hy = b.hy * rng.Uniform(0.3, 0.8);
    b.print_albedo = rng.Uniform(0.05, 0.95);
    if (w_.has_wall_ && b.x + b.bound_r > w_.wall_x_ - 0.01) continue;
    bool clash = false;
    for (const Box& o : w_.box_) clash |= std::hypot(o.x - b.x, o.y - b.y) < o.bound_r + b.bound_r + 0.01;
    for (const Cylinder& c : w_.cyl_) {
      const double dx = c.x - b.x, dy = c.y - b.y;
      const double lx = dx * b.c + dy * b.s, ly = -dx * b.s + dy * b.c;
      const double qx = lx - Clamp(lx, -b.hx, b.hx), qy = ly - Clamp(ly, -b.hy, b.hy);
      clash |= std::hypot(qx, qy) < c.r + 0.004;
    }
    if (clash || !w_.FinishBoxBounds(&b)) continue;
    w_.box_.push_back(b);
    if (AllTopsVisible()) return;
    w_.box_.pop_back();
  }
}

TabletopScene TabletopBuilder::Build() {
  Rng& rng = w_.rng_;
  SetupCamera();
  SetupTable();
  // Free-standing boxes first (containers keep clear of them), occluders after the containers.
  const int boxes = o_.max_boxes > 0 ? rng.Int(1, o_.max_boxes) : 0;
  int occluders = 0;
  for (int k = 0; k < boxes; ++k) {
    if (rng.Chance(0.7))
      ++occluders;
    else
      w_.PlaceBox();
  }
  for (int k = 0; k < o_.clutter_shapes; ++k) {
    static constexpr ShapeKind kKinds[5] = {ShapeKind::kLine, ShapeKind::kPolygon, ShapeKind::kRect,
                                            ShapeKind::kStripes, ShapeKind::kBlob};
    w_.PlaceShape(kKinds[rng.Int(0, 4)]);
  }
  const int wanted = rng.Int(o_.min_containers, o_.max_containers);
  for (int n = 0; n < wanted; ++n) PlaceContainer();
  for (int k = 0; k < occluders; ++k) PlaceOccluder();
  // The contrast fix for cans, cups and jars; wood and cardboard keep their own.
  w_.FixContrast();
  for (int i = 0; i < static_cast<int>(w_.cyl_.size()); ++i)
    if (w_.cyl_[i].material != PlainMaterial::kNone) w_.cyl_[i].top_scale = 1;

  std::vector<float> img;
  w_.Render(&img);
  TabletopScene scene;
  w_.Finish(img, &scene.gray);
  for (int i = 0; i < static_cast<int>(w_.cyl_.size()); ++i) {
    const Cylinder& c = w_.cyl_[i];
    TabletopTop top;
    top.kind = kinds_[i];
    top.visible_fraction = VisibleFraction(i, &top.in_frame_fraction);
    top.rim_centre = cv::Vec3d(c.x, c.y, c.h);
    top.rim_radius_m = c.rim_r();
    scene.truth.push_back(c.truth);
    scene.tops.push_back(top);
  }
  scene.K = w_.cam_.K();
  scene.R = w_.cam_.R();
  scene.t = w_.cam_.T();
  return scene;
}

}  // namespace detail

// ---------------------------------------------------------------- public API
const char* TabletopKindName(TabletopKind kind) {
  switch (kind) {
    case TabletopKind::kCan: return "can";
    case TabletopKind::kCup: return "cup";
    case TabletopKind::kJar: return "jar";
    case TabletopKind::kWood: return "wood";
    case TabletopKind::kCardboard: return "cardboard";
    case TabletopKind::kBottle: return "bottle";
  }
  return "?";
}

bool ParseTabletopKind(const std::string& name, TabletopKind* out) {
  for (int k = 0; k < kTabletopKinds; ++k) {
    if (name == TabletopKindName(static_cast<TabletopKind>(k))) {
      *out = static_cast<TabletopKind>(k);
      return true;
    }
  }
  return false;
}

ellipsekit::Status ValidateTabletopSceneOptions(const TabletopSceneOptions& o) {
  auto bad = [](const std::string& m) { return ellipsekit::Status(ellipsekit::StatusCode::kInvalidArgument, m); };
  if (o.width < 64 || o.width > 8192 || o.height < 64 || o.height > 8192)
    return bad("tabletop scene size must be 64..8192 px, got " + std::to_string(o.width) + "x" +
               std::to_string(o.height));
  if (o.min_containers < 1 || o.max_containers < o.min_containers || o.max_containers > 20)
    return bad("containers must satisfy 1 <= min_containers <= max_containers <= 20");
  if (!(o.min_tilt_deg > 0 && o.min_tilt_deg <= o.max_tilt_deg && o.max_tilt_deg <= 85))
    return bad("tilt range must satisfy 0 < min_tilt_deg <= max_tilt_deg <= 85");
  if (!(o.min_distance_m >= 0.1 && o.min_distance_m <= o.max_distance_m && o.max_distance_m <= 10))
    return bad("distance range must satisfy 0.1 <= min_distance_m <= max_distance_m <= 10");
  if (o.max_boxes < 0 || o.max_boxes > 20) return bad("max_boxes must be 0..20");
  if (o.clutter_shapes < 0 || o.clutter_shapes > 1000) return bad("clutter_shapes must be 0..1000");
  if (!(o.min_visible_fraction >= 0.05 && o.min_visible_fraction <= 1))
    return bad("min_visible_fraction must be in [0.05, 1]");
  if (!(o.edge_cut_share >= 0 && o.edge_cut_share <= 1)) return bad("edge_cut_share must be in [0, 1]");
  if (!(o.noise_sigma >= 0 && o.noise_sigma <= 1000)) return bad("noise_sigma must be finite and >= 0");
  if (!(o.blur_sigma >= 0 && o.blur_sigma <= 50)) return bad("blur_sigma must be 0..50");
  return ellipsekit::Status::Ok();
}

TabletopScene RenderTabletopScene(std::uint64_t seed, const TabletopSceneOptions& options) {
  if (!ValidateTabletopSceneOptions(options).ok()) return TabletopScene();
  detail::TabletopBuilder builder(options, seed);
  return builder.Build();
}

std::string FormatTabletopMetaLine(const TabletopTop& top) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s %.4f", TabletopKindName(top.kind), top.visible_fraction);
  return buf;
}

ellipsekit::Status WriteTabletopDataset(const std::string& dir, int count, std::uint64_t seed,
                                        const TabletopSceneOptions& options) {
  using ellipsekit::Status;
  using ellipsekit::StatusCode;
  if (Status st = ValidateTabletopSceneOptions(options); !st.ok()) return st;
  std::vector<std::string> meta;  // per scene, in the order WriteDataset renders them
  Status st = WriteDataset(dir, count, seed, [&](std::uint64_t s) {
    TabletopScene t = RenderTabletopScene(s, options);
    std::string text;
    for (const TabletopTop& top : t.tops) text += FormatTabletopMetaLine(top) + "\n";
    meta.push_back(std::move(text));
    Scene scene;
    scene.gray = t.gray;
    scene.truth = std::move(t.truth);
    return scene;
  });
  if (!st.ok()) return st;
  const std::filesystem::path meta_dir = std::filesystem::path(dir) / "meta";
  std::error_code ec;
  std::filesystem::create_directories(meta_dir, ec);
  if (ec || !std::filesystem::is_directory(meta_dir, ec))
    return Status(StatusCode::kInternal, "cannot create directory " + meta_dir.string() + ": " + ec.message());
  for (std::size_t i = 0; i < meta.size(); ++i) {
    char stem[32];
    std::snprintf(stem, sizeof stem, "scene_%04zu", i);
    const std::string path = (meta_dir / (std::string(stem) + ".txt")).string();
    const std::string tmp = (meta_dir / (std::string(".") + stem + ".tmp.txt")).string();
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (f == nullptr) return Status(StatusCode::kInternal, "cannot open " + tmp + " for writing");
    bool ok = std::fwrite(meta[i].data(), 1, meta[i].size(), f) == meta[i].size();
    ok &= std::fclose(f) == 0;
    if (!ok) {
      std::filesystem::remove(tmp, ec);
      return Status(StatusCode::kInternal, "cannot write " + tmp);
    }
    std::filesystem::rename(tmp, path, ec);
    if (ec) return Status(StatusCode::kInternal, "cannot rename " + tmp + " to " + path + ": " + ec.message());
  }
  return Status::Ok();
}

}  // namespace ellipsekit::scenes

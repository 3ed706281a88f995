// World setup: camera, light, surfaces, table clutter, cylinders placed visibly.
#include "tools/scenes/world.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "tools/scenes/conic.h"

namespace ellipsekit::scenes::detail {

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
    if (clash || !FinishBoxBounds(&b)) continue;
    box_.push_back(b);
    return true;
  }
  return false;
}

bool World::FinishBoxBounds(Box* b) const {
  V3 corners[8];
  for (int k = 0; k < 8; ++k) {
    const double lx = (k & 1) ? b->hx : -b->hx, ly = (k & 2) ? b->hy : -b->hy;
    corners[k] = {b->x + lx * b->c - ly * b->s, b->y + lx * b->s + ly * b->c, (k & 4) ? b->hz : 0.0};
  }
  b->bbox = ProjectBounds(cam_, corners, 8, W_, H_);
  const double area = double(b->bbox.x1 - b->bbox.x0 + 1) * (b->bbox.y1 - b->bbox.y0 + 1);
  if (b->bbox.x1 < b->bbox.x0 || b->bbox.y1 < b->bbox.y0 || area > 0.2 * W_ * H_) return false;
  // Shadow region: footprint and the footprint moved by the top's shadow offset.
  const double ox = -b->hz * light_.x / light_.z, oy = -b->hz * light_.y / light_.z;
  b->shadow = TRect();
  for (int k = 0; k < 4; ++k) {
    b->shadow.Add(corners[k].x, corners[k].y);
    b->shadow.Add(corners[k].x + ox, corners[k].y + oy);
  }
  b->shadow.Grow(0.02);
  b->shadow_bbox = ProjectTableRect(cam_, b->shadow, W_, H_);
  return true;
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

void World::ShapeContainer(Container kind, bool metal_top, Rng* rng, Cylinder* c) {
  switch (kind) {
    case Container::kFlatCan:
      break;
    case Container::kRecessedCan:  // 330 ml style: rolled rim bead, lid floor 3-6 mm down
      c->recess = rng->Uniform(0.003, 0.006);
      c->rim_width = rng->Uniform(0.002, 0.0035);
      c->r_in = c->r - c->rim_width;
      c->r_in2 = c->r_in * c->r_in;
      c->z_floor = c->h - c->recess;
      c->inner_albedo = c->top_albedo;
      break;
    case Container::kCupEmpty:
    case Container::kCupFilled: {
      c->kind = CylKind::kCup;
      c->has_rim = false;
      c->has_neck = false;
      c->r_in = c->r - rng->Uniform(0.002, 0.004);
      c->r_in2 = c->r_in * c->r_in;
      c->top_albedo = Clamp(c->side_albedo * rng->Uniform(1.0, 1.25), 0.05, 0.95);  // lip
      c->inner_albedo = Clamp(c->side_albedo * rng->Uniform(0.8, 1.0), 0.05, 0.95);
      c->spec = rng->Uniform(0.0, 0.15);
      c->z_floor = rng->Uniform(0.006, 0.012);
      if (kind == Container::kCupFilled) {
        c->z_floor = c->h * rng->Uniform(0.45, 0.85);
        double a;
        do {
          a = rng->Uniform(0.05, 0.9);  // coffee .. milk, unlike the wall
        } while (std::abs(a - c->inner_albedo) < 0.15);
        c->floor_albedo = a;
      }
      break;
    }
    case Container::kJar:  // glass body with a shoulder, a narrower screw lid on top
    case Container::kBottle:
      c->kind = CylKind::kJar;
      c->lid_r = c->r - rng->Uniform(0.004, 0.008);
      c->shoulder_h = c->h - rng->Uniform(0.008, 0.014);
      c->has_neck = false;
      c->has_rim = rng->Chance(0.5);
      c->rim_width = rng->Uniform(0.002, 0.004);
      do {
        c->top_albedo = rng->Uniform(0.1, 0.9);
      } while (std::abs(c->top_albedo - c->side_albedo) < 0.15);
      c->rim_albedo = Clamp(c->top_albedo + (rng->Chance(0.5) ? 1 : -1) * rng->Uniform(0.08, 0.2), 0.05, 0.95);
      if (kind == Container::kBottle) {  // the jar's "lid" becomes a narrow neck and cap (world.h)
        const double cap = rng->Uniform(0.012, 0.022), neck = rng->Uniform(0.01, 0.03), cone = rng->Uniform(0.02, 0.04);
        const double fit = std::min(1.0, 0.55 * c->h / (cap + neck + cone));
        c->lid_r = rng->Uniform(0.012, 0.017);
        c->cap_h = fit * cap;
        c->neck_h = c->h - fit * (cap + neck);
        c->shoulder_h = c->neck_h - fit * cone;
      }
      break;
  }
  if (metal_top) {
    c->metal_top = true;
    c->spec = rng->Uniform(0.6, 1.1);
    c->shininess = rng->Uniform(6, 20);
  }
}

bool World::ComputeTruth(Cylinder* c) const {
  const cv::Matx33d q = ProjectCircleConic(cam_.K(), cam_.R(), cam_.T(), cv::Vec3d(c->x, c->y, c->h),
                                           cv::Vec3d(1, 0, 0), cv::Vec3d(0, 1, 0), c->rim_r());
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
    const V3 P{c.x + c.rim_r() * std::cos(phi), c.y + c.rim_r() * std::sin(phi), c.h};
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
    const V3 P{c.x + c.rim_r() * std::cos(phi), c.y + c.rim_r() * std::sin(phi), c.h};
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

}  // namespace ellipsekit::scenes::detail

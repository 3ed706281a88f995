// Conveyor, stacking and crossing sequences rendered in one world, with sensor-like depth.
#include "tools/scenes/world.h"

#include <algorithm>
#include <cmath>

namespace ellipsekit::scenes::detail {

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
  Rng crng(Mix64(seed ^ 0x3C6EF372FE94F82Bull));  // container shape: its own stream
  ShapeContainer(co.container, co.metal_top, &crng, &can);

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
  double u = 0, v = 0;  // Project leaves them alone for a point behind the camera
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
  seq.container = co.container;
  seq.rim_radius_m = can.rim_r();
  seq.recess_m = can.recess > 0 ? can.recess : (can.floor_albedo >= 0 ? can.h - can.z_floor : 0);
  if (info != nullptr) *info = seq;

  Rng drng(Mix64(seed ^ 0x6A09E667F3BCC909ull));
  std::vector<float> img, sub_img;
  std::vector<double> z;
  constexpr int kExposureSamples = 16;  // sub-frames of a blurred image
  for (int i = 0; i < co.frames; ++i) {
    ConveyorFrame fr;
    fr.index = i;
    fr.t = i / co.fps;
    const cv::Vec3d p = seq.TopCentreAt(fr.t);
    Cylinder& c = cyl_[0];
    if (co.exposure_s > 0) {  // the mean of the sub-frames spread over the shutter time
      img.assign(bg.size(), 0.0f);
      for (int k = 0; k < kExposureSamples; ++k) {
        const double dt = ((k + 0.5) / kExposureSamples - 0.5) * co.exposure_s;
        if (!MoveTopTo(seq.TopCentreAt(fr.t + dt), &c))
          return Status(StatusCode::kInternal, "conveyor: degenerate top ellipse");
        sub_img = bg;
        RenderRect(RedrawRect(c), &sub_img);
        for (std::size_t q = 0; q < img.size(); ++q) img[q] += sub_img[q] * (1.0f / kExposureSamples);
      }
    }
    if (!MoveTopTo(p, &c)) return Status(StatusCode::kInternal, "conveyor: degenerate top ellipse");
    const IRect r = RedrawRect(c);
    if (!(co.exposure_s > 0)) {
      img = bg;
      RenderRect(r, &img);
    }
    z = bgz;
    RenderDepth(r, &z);
    Finish(img, &fr.gray);
    DegradeDepth(z, W_, H_, co.depth_noise_mm, co.depth_invalid_fraction, &drng, &fr.depth_mm);
    fr.top_centre = p;
    cam_.Project(V3{p[0], p[1], p[2]}, &u, &v);
    fr.top_pixel = cv::Vec2d(u, v);
    fr.truth = c.truth;
    fr.rim.centre = p;
    fr.rim.radius = c.rim_r();
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
  Rng crng(Mix64(seed ^ 0x3C6EF372FE94F82Bull));  // container shapes: their own stream
  for (int k = 0; k < 2; ++k) ShapeContainer(co.containers[static_cast<std::size_t>(k)], co.metal_top, &crng, &cans[k]);
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
    seq.container.push_back(co.containers[static_cast<std::size_t>(k)]);
    seq.rim_radius_m.push_back(cans[k].rim_r());
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
      RimCircle rim;
      rim.centre = p;
      rim.radius = cyl_[k].rim_r();
      fr.rim.push_back(rim);
    }
    if (ellipsekit::Status st = sink(fr); !st.ok()) return st;
  }
  return Status::Ok();
}

}  // namespace ellipsekit::scenes::detail

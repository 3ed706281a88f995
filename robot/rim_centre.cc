// 3-D rim centre from depth sampled on the rim (see rim_centre.h).
#include "ellipsekit/robot/rim_centre.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "ellipsekit/robot/circle_pose.h"
#include "ellipsekit/robot/depth_sampling.h"

namespace ellipsekit::robot {

namespace {

constexpr int kSectors = 16;
constexpr double kPi = 3.14159265358979323846;

// The q-quantile (0..1) of v (reordered).
double Quantile(std::vector<double>& v, double q) {
  const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

}  // namespace

const char* TopCentreMethodName(TopCentreMethod m) {
  return m == TopCentreMethod::kRimPlane ? "rim-plane" : "interior-median";
}

Result<RimSample> RimCentreSampler::Sample(const Ellipse& e, const DepthImageView& depth, const CameraModel& camera) {
  using R = Result<RimSample>;
  RimSample s;
  if (TrySample(e, depth, camera, &s)) return R::Ok(s);
  return R{LastError(), {}};
}

Status RimCentreSampler::LastError() const {
  auto too_few = [&](const std::string& what) {
    return Status(StatusCode::kInvalidArgument, "rim depth: " + what + " (" + std::to_string(fail_valid_) + " valid of " +
                                                    std::to_string(fail_total_) + " samples on the rim)");
  };
  switch (failure_) {
    case Failure::kNone: return Status::Ok();
    case Failure::kBadView:
      return Status(StatusCode::kInvalidArgument, "rim depth: empty image or step < width * bytes per pixel");
    case Failure::kBadEllipse: return Status(StatusCode::kInvalidArgument, "rim depth: degenerate ellipse");
    case Failure::kBadOptions:
      return Status(StatusCode::kInvalidArgument,
                    "rim depth: bad options (0 <= offsets[0] <= offsets[1] < b, 8 <= min_angles <= max_angles, "
                    "positive gates, 3 <= min_inliers, 1 <= min_sectors <= 16)");
    case Failure::kBadNormal:
      return Status(StatusCode::kInvalidArgument, "rim depth: plane_normal must be a finite non-zero vector");
    case Failure::kTooFewValid: return too_few("too few valid depth samples");
    case Failure::kTooFewOnPlane: return too_few("too few samples on the rim's plane");
    case Failure::kTooFewSectors: return too_few("rim samples cover " + std::to_string(fail_sectors_) + " of 16 sectors");
    case Failure::kEdgeOn: return Status(StatusCode::kInvalidArgument, "rim depth: the rim plane is edge-on");
    case Failure::kBehind: return Status(StatusCode::kInvalidArgument, "rim depth: the rim plane is behind the camera");
    case Failure::kInner: return inner_;
  }
  return Status(StatusCode::kInternal, "rim depth: unknown failure");
}

bool RimCentreSampler::TrySample(const Ellipse& e, const DepthImageView& depth, const CameraModel& camera,
                                 RimSample* result) {
  const RimSampleOptions& o = options_;
  failure_ = Failure::kNone;
  auto fail = [&](Failure f) {
    failure_ = f;
    return false;
  };
  const std::size_t bpp = depth.encoding == DepthEncoding::k16UC1 ? 2 : 4;
  if (depth.data == nullptr || depth.width <= 0 || depth.height <= 0 ||
      depth.step < static_cast<std::size_t>(depth.width) * bpp)
    return fail(Failure::kBadView);
  if (!(std::isfinite(e.cx) && std::isfinite(e.cy) && std::isfinite(e.theta) && std::isfinite(e.a) &&
        std::isfinite(e.b) && e.a > 0 && e.b > 0))
    return fail(Failure::kBadEllipse);
  if (!(o.offsets_px[0] >= 0 && o.offsets_px[1] >= o.offsets_px[0] && o.offsets_px[1] < e.b &&
        o.min_angles >= 8 && o.max_angles >= o.min_angles && o.inlier_sigmas > 0 && o.off_object_m > 0 &&
        o.min_noise_m > 0 && o.min_inliers >= 3 && o.min_sectors >= 1 && o.min_sectors <= kSectors))
    return fail(Failure::kBadOptions);

  // 1. Samples on both sides of the outline; remember each sample's side and angle sector.
  const double a = e.a, b = e.b, ct = std::cos(e.theta), st = std::sin(e.theta);
  const double perimeter = kPi * (3 * (a + b) - std::sqrt((3 * a + b) * (a + 3 * b)));
  const int n_ang = std::clamp(static_cast<int>(std::ceil(perimeter)), o.min_angles, o.max_angles);
  pts_.clear();
  // Room for the most samples any outline can give (2 sides x offsets x max_angles), once: the
  // vectors then never grow.
  const std::size_t most = 2 * o.offsets_px.size() * static_cast<std::size_t>(o.max_angles);
  if (pts_.capacity() < most) pts_.reserve(most);
  if (tmp_.capacity() < most) tmp_.reserve(most);
  if (idx_.capacity() < most) idx_.reserve(most);
  if (fit_idx_.capacity() < most) fit_idx_.reserve(most);
  RimSample out;
  for (int k = 0; k < n_ang; ++k) {
    const double phi = 2 * kPi * k / n_ang, cp = std::cos(phi), sp = std::sin(phi);
    const double px = e.cx + a * cp * ct - b * sp * st, py = e.cy + a * cp * st + b * sp * ct;
    double gx = cp / a * ct - sp / b * st, gy = cp / a * st + sp / b * ct;  // outward normal
    const double gl = std::hypot(gx, gy);
    gx /= gl;
    gy /= gl;
    for (int side = 0; side < 2; ++side) {
      for (double off : o.offsets_px) {
        const double sgn = side == 0 ? -1.0 : 1.0;
        const int x = static_cast<int>(std::lround(px + sgn * off * gx));
        const int y = static_cast<int>(std::lround(py + sgn * off * gy));
        if (x < 0 || y < 0 || x >= depth.width || y >= depth.height) continue;
        ++out.total_samples;
        const double z = DepthAt(depth, x, y);
        if (!(z >= o.min_depth_m && z <= o.max_depth_m)) continue;
        const Eigen::Vector2d nrm = camera.UndistortPixel(Eigen::Vector2d(x, y));
        pts_.push_back(Pt{Eigen::Vector3d(nrm.x() * z, nrm.y() * z, z), 0.f, static_cast<std::uint8_t>(side),
                          static_cast<std::uint8_t>(k * kSectors / n_ang)});
      }
    }
  }
  out.valid_samples = static_cast<int>(pts_.size());
  fail_valid_ = out.valid_samples;
  fail_total_ = out.total_samples;
  if (out.valid_samples < o.min_inliers) return fail(Failure::kTooFewValid);

  const Eigen::Vector2d ne = camera.UndistortPixel(Eigen::Vector2d(e.cx, e.cy));
  const Eigen::Vector3d ray_e(ne.x(), ne.y(), 1);

  // Steps 2-4 for one normal: side, rim level, inliers (into idx_; keep() below moves a chosen
  // fit's to fit_idx_), plane offset. With `refit`, the plane (normal too) is then fitted to the
  // inliers and the gate applied once more.
  struct Fit {
    Eigen::Vector3d n;
    double d = 0, noise = 0, rms = 0;
    double level = 0, ceiling = 0;  // the rim level found; samples above `ceiling` were left out
    int inliers = 0, sectors = 0;
    bool outer = false, ok = false;
  };
  auto run = [&](Eigen::Vector3d n, bool refit, double ceiling) {
    Fit f;
    f.ceiling = ceiling;
    if (n.dot(ray_e) > 0) n = -n;  // towards the camera: higher = larger n . X
    for (int pass = 0; pass < (refit ? 2 : 1); ++pass) {
      for (Pt& p : pts_) p.h = static_cast<float>(n.dot(p.X));
      // Side levels: median of the samples not far below the side's 90th percentile.
      double level[2] = {-1e300, -1e300};
      for (int side = 0; side < 2; ++side) {
        tmp_.clear();
        for (const Pt& p : pts_)
          if (p.outer == side && p.h <= ceiling) tmp_.push_back(p.h);
        if (static_cast<int>(tmp_.size()) < o.min_inliers) continue;
        const double top = Quantile(tmp_, 0.9);
        std::size_t m = 0;
        for (double v : tmp_)
          if (v > top - o.off_object_m) tmp_[m++] = v;
        tmp_.resize(m);
        if (static_cast<int>(m) >= o.min_inliers) level[side] = Quantile(tmp_, 0.5);
      }
      if (level[0] <= -1e299 && level[1] <= -1e299) return f;
      f.outer = level[1] > level[0];
      const int side = f.outer ? 1 : 0;
      const double top_level = level[side];
      // Noise: differences of neighbouring on-object samples of the side (same offset, next angle).
      tmp_.clear();
      const Pt* prev = nullptr;
      for (const Pt& p : pts_) {
        if (p.outer != side || p.h < top_level - o.off_object_m || p.h > ceiling) continue;
        if (prev != nullptr) tmp_.push_back(std::abs(static_cast<double>(p.h) - prev->h));
        prev = &p;
      }
      const double noise =
          std::max(o.min_noise_m, tmp_.size() >= 4 ? Quantile(tmp_, 0.5) / (0.6745 * std::sqrt(2.0)) : 0.0);
      // Mean shift from the side's upper quartile.
      tmp_.clear();
      for (const Pt& p : pts_)
        if (p.outer == side && p.h > top_level - o.off_object_m && p.h <= ceiling) tmp_.push_back(p.h);
      double L = Quantile(tmp_, 0.75);
      for (int it = 0; it < 30; ++it) {
        double sw = 0, swh = 0;
        for (double v : tmp_) {
          const double u = (v - L) / noise;
          if (std::abs(u) > 3) continue;
          const double w = std::exp(-0.5 * u * u);
          sw += w;
          swh += w * v;
        }
        if (sw <= 0) break;
        const double next = swh / sw;
        const bool done = std::abs(next - L) < 1e-6;
        L = next;
        if (done) break;
      }
      // Inliers and the plane through them.
      idx_.clear();
      unsigned sector_mask = 0;
      for (int i = 0; i < static_cast<int>(pts_.size()); ++i) {
        const Pt& p = pts_[static_cast<std::size_t>(i)];
        if (p.outer == side && p.h <= ceiling && std::abs(p.h - L) <= o.inlier_sigmas * noise) {
          idx_.push_back(i);
          sector_mask |= 1u << p.sector;
        }
      }
      f.inliers = static_cast<int>(idx_.size());
      f.sectors = __builtin_popcount(sector_mask);
      f.noise = noise;
      f.level = L;
      if (f.inliers < o.min_inliers) return f;
      if (refit && pass == 0) {
        Eigen::Vector3d c = Eigen::Vector3d::Zero();
        for (int i : idx_) c += pts_[static_cast<std::size_t>(i)].X;
        c /= f.inliers;
        Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
        for (int i : idx_) {
          const Eigen::Vector3d dd = pts_[static_cast<std::size_t>(i)].X - c;
          S += dd * dd.transpose();
        }
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(S);
        n = es.eigenvectors().col(0);
        if (n.dot(ray_e) > 0) n = -n;
        continue;
      }
      double sum = 0, sum2 = 0;
      for (int i : idx_) sum += n.dot(pts_[static_cast<std::size_t>(i)].X);
      f.d = sum / f.inliers;
      for (int i : idx_) {
        const double r = n.dot(pts_[static_cast<std::size_t>(i)].X) - f.d;
        sum2 += r * r;
      }
      f.rms = std::sqrt(sum2 / f.inliers);
      f.n = n;
      f.ok = true;
    }
    return f;
  };

  Fit fit;
  // Takes the fit just run (its inliers are in idx_) as the chosen one: its inliers move to
  // fit_idx_ (a swap of equally reserved vectors: no copy, no allocation), and the next run()
  // reuses idx_.
  auto keep = [&](const Fit& f) {
    fit = f;
    idx_.swap(fit_idx_);
  };
  int min_sectors = o.min_sectors;
  if (o.plane_normal) {
    if (!(o.plane_normal->allFinite() && o.plane_normal->norm() > 1e-9)) return fail(Failure::kBadNormal);
    const Eigen::Vector3d n0 = o.plane_normal->normalized();
    keep(run(n0, false, INFINITY));
    // An occluder in front of the rim (a taller object passing nearer the camera) is higher than the
    // rim along the normal over the part of the outline it hides, and is then taken for the rim (the
    // highest surface). With the rim's expected centre (a tracked object's prediction), a level more
    // than off_object_m from it is tried again without the samples above expected + off_object_m,
    // and the lower level is kept when it is nearer the expectation and covers at least as many
    // sectors. A lid floor or a cup's contents below the rim are never reached this way (only
    // samples above the expectation are left out).
    if (fit.ok && o.expected_centre && o.expected_centre->allFinite()) {
      const double expected = fit.n.dot(*o.expected_centre);
      if (std::abs(fit.level - expected) > o.off_object_m) {
        const Fit below = run(n0, false, expected + o.off_object_m);
        // The occluder hides part of the outline, the rim shows around the rest: the lower level
        // must cover at least as many of the 16 sectors. (So a wrong expectation -- a track started
        // on the table -- cannot pull a rim seen all round down to a table seen on the far half.)
        if (below.ok && below.sectors >= min_sectors && below.sectors >= fit.sectors &&
            std::abs(below.level - expected) < std::abs(fit.level - expected))
          keep(below);
      }
    }
  } else {
    auto cand = CirclePoseCandidates(e, 1.0, camera);
    if (!cand.ok()) {
      inner_ = cand.status;
      return fail(Failure::kInner);
    }
    min_sectors = std::max(min_sectors, 8);
    for (const CirclePose& c : cand.value) {
      const Fit f = run(c.normal, true, INFINITY);
      if (f.ok && (!fit.ok || f.inliers > fit.inliers)) keep(f);
    }
  }
  if (!fit.ok || fit.inliers < o.min_inliers) return fail(Failure::kTooFewOnPlane);
  if (fit.sectors < min_sectors) {
    fail_sectors_ = fit.sectors;
    return fail(Failure::kTooFewSectors);
  }

  // 5. The centre: the pole ray meets the plane n . X = d.
  auto pole = ProjectedCircleCentre(e, camera, fit.n);
  if (!pole.ok()) {
    inner_ = pole.status;
    return fail(Failure::kInner);
  }
  const Eigen::Vector2d np = camera.UndistortPixel(pole.value);
  const Eigen::Vector3d ray(np.x(), np.y(), 1);
  const double den = fit.n.dot(ray);
  if (std::abs(den) < 1e-9) return fail(Failure::kEdgeOn);
  out.pole_centre = ray * (fit.d / den);
  if (!(out.pole_centre.z() > 0)) return fail(Failure::kBehind);
  out.centre = out.pole_centre;
  // The circle through the inliers, in the plane (algebraic fit, then once more without the points
  // off it by more than 3 robust sigmas): its centre does not depend on the detected outline's
  // exact size or position, only on where the rim samples lie.
  if (fit.sectors >= o.min_circle_sectors) {
    const Eigen::Vector3d u = fit.n.unitOrthogonal(), v = fit.n.cross(u);
    double rad_gate = 1e300;
    Eigen::Vector2d c2(0, 0);
    double R2 = 0;
    bool ok = false;
    for (int pass = 0; pass < 2; ++pass) {
      Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
      Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
      int used = 0;
      for (int i : fit_idx_) {
        const Eigen::Vector3d& X = pts_[static_cast<std::size_t>(i)].X;
        const double x = u.dot(X), y = v.dot(X);
        if (pass == 1 && std::abs(std::hypot(x - c2.x(), y - c2.y()) - R2) > rad_gate) continue;
        const Eigen::Vector3d row(x, y, 1);
        A += row * row.transpose();
        rhs -= row * (x * x + y * y);
        ++used;
      }
      if (used < o.min_inliers) break;
      const Eigen::Vector3d sol = A.ldlt().solve(rhs);
      c2 = Eigen::Vector2d(-0.5 * sol(0), -0.5 * sol(1));
      const double rr = c2.squaredNorm() - sol(2);
      if (!(rr > 0) || !sol.allFinite()) break;
      R2 = std::sqrt(rr);
      ok = true;
      tmp_.clear();
      for (int i : fit_idx_) {
        const Eigen::Vector3d& X = pts_[static_cast<std::size_t>(i)].X;
        tmp_.push_back(std::abs(std::hypot(u.dot(X) - c2.x(), v.dot(X) - c2.y()) - R2));
      }
      rad_gate = std::max(3 * 1.4826 * Quantile(tmp_, 0.5), 0.001);
    }
    if (ok) {
      out.circle_centre = u * c2.x() + v * c2.y() + fit.n * fit.d;
      out.circle_radius_m = R2;
      out.has_circle = true;
      if (o.centre_from_circle) out.centre = out.circle_centre;
    }
  }
  out.normal = fit.n;
  out.centre_pixel = pole.value;
  const Eigen::Vector3d J = ray / den;  // d(centre) / d(d)
  out.covariance = J * J.transpose() * (fit.rms * fit.rms / fit.inliers);
  out.noise_m = fit.noise;
  out.plane_rms_m = fit.rms;
  out.inliers = fit.inliers;
  out.sectors = fit.sectors;
  out.outer_side = fit.outer;
  double rsum = 0;
  int rn = 0;
  for (int k = 0; k < kSectors; ++k) {  // the outline on the plane
    const double phi = 2 * kPi * k / kSectors, cp = std::cos(phi), sp = std::sin(phi);
    const Eigen::Vector2d q = camera.UndistortPixel(
        Eigen::Vector2d(e.cx + a * cp * ct - b * sp * st, e.cy + a * cp * st + b * sp * ct));
    const Eigen::Vector3d rq(q.x(), q.y(), 1);
    const double dq = fit.n.dot(rq);
    if (std::abs(dq) < 1e-9) continue;
    rsum += (rq * (fit.d / dq) - out.centre).norm();
    ++rn;
  }
  out.radius_m = rn > 0 ? rsum / rn : 0;
  *result = out;
  return true;
}

}  // namespace ellipsekit::robot

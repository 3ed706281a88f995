#include "fit/rim_search.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <numbers>

#include "fit/ellipse_rows.h"

namespace ellipsekit {

namespace {

constexpr int kMaxBins = 128;
constexpr int kSectors = 64;  // one bit each in a std::uint64_t

// tan(k pi / 32), k = 1..7: the sector boundaries inside an octant.
const std::array<double, 7> kOctantTan = [] {
  std::array<double, 7> t{};
  for (int k = 1; k <= 7; ++k) t[k - 1] = std::tan(k * std::numbers::pi / 32);
  return t;
}();

// floor(angle(x, y) * 32 / pi), the angle of (x, y) in [0, 2 pi): its sector of 64, from the
// quadrant's signs and a ratio compared with kOctantTan instead of an atan2 per pixel (equal
// except where rounding puts a point within ~1e-16 of a boundary). (0, 0) gives 0.
int Sector64(double x, double y) {
  int quadrant = 0;
  if (!(y >= 0 && x > 0)) {  // rotate into [0, pi / 2) by quarter turns
    if (x <= 0 && y > 0) {
      quadrant = 1;
      const double t = x;
      x = y;
      y = -t;
    } else if (x < 0 && y <= 0) {
      quadrant = 2;
      x = -x;
      y = -y;
    } else if (x >= 0 && y < 0) {
      quadrant = 3;
      const double t = x;
      x = -y;
      y = t;
    } else {
      return 0;
    }
  }
  int sub = 0;
  if (y < x) {  // [0, pi / 4)
    const double t = y / x;
    for (const double b : kOctantTan) sub += t >= b;
  } else {  // [pi / 4, pi / 2)
    const double t = x / y;
    sub = 15;
    for (const double b : kOctantTan) sub -= b < t;
  }
  return 16 * quadrant + sub;
}

}  // namespace

bool FindOuterRim(const EdgeMapView& in, const Ellipse& inner, double min_coverage, Ellipse* outer,
                  long* scanned_pixels, const RimContacts* contacts) {
  *scanned_pixels = 0;
  if (!(inner.b >= 2) || !(inner.a >= inner.b)) return false;
  const double k_min = std::max(kRimSearchMinScale, 1 + 1.5 / inner.b), k_max = kRimSearchMaxScale;
  if (!(k_min < k_max)) return false;
  const double c = std::cos(inner.theta), s = std::sin(inner.theta);
  // Row spans of the annulus k_min * inner .. k_max * inner; the search box: k_max * inner's
  // bounding box, clipped to the frame.
  const EllipseRows outer_rows(inner.theta, k_max * inner.a, k_max * inner.b);
  const EllipseRows inner_rows(inner.theta, k_min * inner.a, k_min * inner.b);
  const double hx = outer_rows.half_width(), hy = outer_rows.half_height();
  // Clipped in doubles before any conversion, so a far-off or huge ellipse cannot overflow an int.
  const double fx0 = std::max(0.0, std::floor(inner.cx - hx)), fx1 = std::min(in.width - 1.0, std::ceil(inner.cx + hx));
  const double fy0 = std::max(0.0, std::floor(inner.cy - hy)), fy1 = std::min(in.height - 1.0, std::ceil(inner.cy + hy));
  if (!(fx0 <= fx1) || !(fy0 <= fy1)) return false;
  const int x0 = static_cast<int>(fx0), x1 = static_cast<int>(fx1), y0 = static_cast<int>(fy0), y1 = static_cast<int>(fy1);

  // Radius bins of ~0.5 px on the minor axis; a band of +-1 px is `half` bins either side.
  const double bin = std::max(0.5 / inner.b, (k_max - k_min) / kMaxBins);
  const int bins = std::min(kMaxBins, static_cast<int>(std::ceil((k_max - k_min) / bin)));
  const int half = std::max(1, static_cast<int>(std::lround(1.0 / (inner.b * bin))));
  std::uint64_t sectors[kMaxBins] = {};
  double radius_sum[kMaxBins] = {};
  int count[kMaxBins] = {};
  const double ia = 1 / inner.a, ib = 1 / inner.b;
  const double k_min2 = k_min * k_min, k_max2 = k_max * k_max;
  auto scan = [&](int y, int xa, int xb) {
    const std::uint8_t* edges = in.edge_map + y * in.stride;
    const std::int16_t* gxs = in.dx + y * in.grad_stride;
    const std::int16_t* gys = in.dy + y * in.grad_stride;
    for (int x = FirstNonZeroByte(edges, xa, xb + 1); x <= xb; x = FirstNonZeroByte(edges, x + 1, xb + 1)) {
      const double ddx = x - inner.cx, ddy = y - inner.cy;
      const double u = (ddx * c + ddy * s) * ia, v = (ddy * c - ddx * s) * ib;  // unit-circle frame
      const double r2 = u * u + v * v;
      if (r2 < k_min2 || r2 >= k_max2) continue;
      // The normal of every k * inner at this pixel: (u / a, v / b) in the ellipse frame.
      const double nu = u * ia, nv = v * ib;
      const double nx = nu * c - nv * s, ny = nu * s + nv * c;
      if (!GradientAlongNormal(gxs[x], gys[x], nx, ny)) continue;
      const double r = std::sqrt(r2);
      const int b = static_cast<int>((r - k_min) / bin);
      if (b >= bins) continue;
      // The angle of (-u, -v), that is atan2(v, u) + pi: the sectors' numbering, which the half
      // test below relies on ([0, 32): v < 0).
      const int sector = Sector64(-u, -v);
      sectors[b] |= std::uint64_t{1} << sector;
      radius_sum[b] += r;
      ++count[b];
    }
  };
  long scanned = 0;
  for (int y = y0; y <= y1; ++y) {
    const double dy = y - inner.cy;
    double out_lo, out_hi, in_lo, in_hi;
    if (!outer_rows.Span(dy, &out_lo, &out_hi)) continue;
    // Widened by a pixel, so that rounding never drops a pixel the exact test in scan() would keep,
    // and clamped to [x0 - 1, x1 + 1] in doubles before conversion (NaN goes to the low end).
    auto to_x = [&](double v) { return v >= x0 - 1.0 ? static_cast<int>(std::min(v, x1 + 1.0)) : x0 - 1; };
    const int xa = std::max(x0, to_x(std::floor(inner.cx + out_lo)) - 1);
    const int xb = std::min(x1, to_x(std::ceil(inner.cx + out_hi)) + 1);
    if (xa > xb) continue;
    int skip_a = xb + 1, skip_b = xb;  // [skip_a, skip_b]: inside k_min * inner, not scanned
    if (inner_rows.Span(dy, &in_lo, &in_hi)) {
      skip_a = std::max(xa, to_x(std::ceil(inner.cx + in_lo)) + 1);
      skip_b = std::min(xb, to_x(std::floor(inner.cx + in_hi)) - 1);
    }
    if (skip_a > skip_b) {
      scan(y, xa, xb);
      scanned += xb - xa + 1;
    } else {
      scan(y, xa, skip_a - 1);
      scan(y, skip_b + 1, xb);
      scanned += (skip_a - xa) + (xb - skip_b);
    }
  }
  *scanned_pixels = scanned;
  int best = -1, best_covered = 0, best_half = 0;
  std::uint64_t best_band = 0;
  for (int i = 0; i < bins; ++i) {
    std::uint64_t band = 0;
    for (int j = std::max(0, i - half); j <= std::min(bins - 1, i + half); ++j) band |= sectors[j];
    const int covered = std::popcount(band);
    if (covered > best_covered) {
      best_covered = covered;
      best = i;
      best_band = band;
      best_half = std::max(std::popcount(band & 0xffffffffull), std::popcount(band >> 32));
    }
  }
  if (best < 0) return false;
  // The far-half rule (kRimFarHalfMinCoverage) first: it rejects without the contacts' work.
  // Sectors [0, 32) lie on the side of -v, which points up in the image when cos theta > 0.
  const int upper_half = c > 0 ? std::popcount(best_band & 0xffffffffull) : std::popcount(best_band >> 32);
  if (std::abs(c) >= kRimFarHalfMinUp && upper_half < kRimFarHalfMinCoverage * (kSectors / 2)) return false;
  double sum = 0;
  int n = 0;
  for (int j = std::max(0, best - half); j <= std::min(bins - 1, best + half); ++j) {
    sum += radius_sum[j];
    n += count[j];
  }
  const double k = sum / n;
  // Sectors [0, 32) are the half v < 0 of the ellipse frame, [32, 64) the half v > 0.
  const bool half_backed =
      best_half >= kRimHalfCoverage * (kSectors / 2) && best_covered >= kRimHalfMinCoverage * kSectors;
  if (best_covered < min_coverage * kSectors && !half_backed) {
    if (contacts == nullptr || best_covered < kRimHalfMinCoverage * kSectors) return false;
    const int explained = std::popcount(contacts->Touching(inner, k) & ~best_band);
    if (best_covered < min_coverage * (kSectors - explained)) return false;
  }
  *outer = inner;
  outer->a = k * inner.a;
  outer->b = k * inner.b;
  return true;
}

}  // namespace ellipsekit

// Arc selection on hand-built curves (sec. II-A, II-B-1, II-B-2): polyline, splits at turning and
// inflection points, arc statistics and quadrants; curve tracing on a drawn circle; OBB_min.
#include <cmath>
#include <cstdlib>
#include <functional>
#include <numbers>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "fit/curve_tracing.h"
#include "fit/obb.h"
#include "kernels/arc_split.h"
#include "kernels/arc_stats.h"
#include "kernels/arc_types.h"
#include "kernels/edge_sign.h"
#include "kernels/polyline.h"

namespace ellipsekit {
namespace {

constexpr double kPi = std::numbers::pi;

struct Pt {
  double x, y;
};

// Rasterises a parametric curve f(s), s in [0, 1], into an 8-connected chain of integer pixels
// (samples dense enough that consecutive rounded points are neighbours; repeats dropped) and
// appends it to `curves` as one curve. Gradients come from grad(x, y).
void AppendCurve(const std::function<Pt(double)>& f, double length_px, std::uint8_t sign_class,
                 const std::function<Pt(int, int)>& grad, Curves* curves, bool thin = true) {
  if (curves->offset.empty()) curves->offset.push_back(0);
  const int begin = static_cast<int>(curves->x.size());
  const int steps = std::max(4, static_cast<int>(length_px * 5));
  for (int i = 0; i <= steps; ++i) {
    const Pt p = f(static_cast<double>(i) / steps);
    const int x = static_cast<int>(std::lround(p.x)), y = static_cast<int>(std::lround(p.y));
    if (static_cast<int>(curves->x.size()) > begin) {
      if (curves->x.back() == x && curves->y.back() == y) continue;
      ASSERT_LE(std::abs(curves->x.back() - x), 1);
      ASSERT_LE(std::abs(curves->y.back() - y), 1);
    }
    const Pt g = grad(x, y);
    curves->x.push_back(x);
    curves->y.push_back(y);
    curves->gx.push_back(static_cast<std::int16_t>(std::lround(g.x)));
    curves->gy.push_back(static_cast<std::int16_t>(std::lround(g.y)));
  }
  // Thin the chain as an edge tracer sees a one-pixel-wide edge: drop a point whose two
  // chain neighbours are already 8-neighbours of each other (the corner of a staircase step).
  std::size_t out = begin;
  for (std::size_t i = begin; i < curves->x.size(); ++i) {
    if (thin && out >= static_cast<std::size_t>(begin) + 2 &&
        std::abs(curves->x[i] - curves->x[out - 2]) <= 1 && std::abs(curves->y[i] - curves->y[out - 2]) <= 1) {
      --out;  // the previous point was a corner
    }
    curves->x[out] = curves->x[i]; curves->y[out] = curves->y[i];
    curves->gx[out] = curves->gx[i]; curves->gy[out] = curves->gy[i];
    ++out;
  }
  curves->x.resize(out); curves->y.resize(out); curves->gx.resize(out); curves->gy.resize(out);
  curves->offset.push_back(static_cast<std::int32_t>(curves->x.size()));
  curves->sign_class.push_back(sign_class);
}

Pt ConstGrad(int, int) { return {100, 100}; }

struct ArcRun {
  Polylines polylines;
  Splits splits;
  std::vector<ArcStats> stats;
};

ArcRun RunArcStage(const Curves& curves, int min_points = 3, double tolerance = 1.0, double angle = 35.0) {
  ArcRun r;
  std::vector<std::int32_t> stack;
  int longest = 0;
  for (int c = 0; c < curves.size(); ++c) longest = std::max(longest, curves.offset[c + 1] - curves.offset[c]);
  stack.reserve(2 * longest + 4);
  scalar::Polyline(curves, PolylineToleranceQ16(tolerance), &r.polylines, &stack);
  scalar::ArcSplit(curves, r.polylines, SplitTanQ16(angle), &r.splits);
  scalar::ArcStatsFromSplits(curves, r.splits, min_points, &r.stats);
  return r;
}

// Index of the chain point nearest (x, y).
int NearestIndex(const Curves& c, int curve, double x, double y) {
  int best = -1;
  double bd = 1e300;
  for (int i = c.offset[curve]; i < c.offset[curve + 1]; ++i) {
    const double d = std::hypot(c.x[i] - x, c.y[i] - y);
    if (d < bd) { bd = d; best = i; }
  }
  return best;
}

TEST(FitArcs, PolylineVerticesOfAnLAreItsCorners) {
  Curves c;
  c.clear();
  // (0,0) -> (40,0) -> (40,40): the corner is at point index 40.
  AppendCurve([](double s) { return s < 0.5 ? Pt{80 * s, 0} : Pt{40, 80 * (s - 0.5)}; }, 80, kEdgePlus, ConstGrad, &c,
               /*thin=*/false);
  ASSERT_EQ(c.x.size(), 81u);
  const ArcRun r = RunArcStage(c);
  ASSERT_EQ(r.polylines.offset.size(), 2u);
  const std::vector<std::int32_t> want = {0, 40, 80};
  EXPECT_EQ(r.polylines.vertex, want);
  // A two-segment L has one interior vertex: Algorithm I compares consecutive turn angles
  // theta_i, theta_{i+1}, so a single corner with nothing to compare against is not split (as in
  // the paper's Algorithm I). The turning-point test below gives the corner a neighbour.
  EXPECT_EQ(r.splits.index.size(), 0u);
}

TEST(FitArcs, SplitsAnLShapedChainAtItsCorner) {
  Curves c;
  c.clear();
  // 40 px right, corner, 40 px down, then a gentle 14 degree bend for 40 px more
  // (down-left at slope 1/4, the same turning sense as the corner): turns of 90 and 14 degrees
  // differ by more than T_theta.
  auto f = [](double s) {
    const double t = 120 * s;
    if (t <= 40) return Pt{t, 0};
    if (t <= 80) return Pt{40, t - 40};
    return Pt{40 - (t - 80) * 0.25, 40 + (t - 80)};
  };
  AppendCurve(f, 120, kEdgePlus, ConstGrad, &c, /*thin=*/false);
  const int corner = NearestIndex(c, 0, 40, 0);
  ASSERT_EQ(c.x[corner], 40);
  ASSERT_EQ(c.y[corner], 0);
  const ArcRun r = RunArcStage(c);
  ASSERT_GE(r.splits.index.size(), 1u);
  bool found = false;
  for (std::int32_t s : r.splits.index) found |= std::abs(s - corner) <= 2;
  EXPECT_TRUE(found) << "no split near the corner at index " << corner;
  // The gentle bend (14 degrees) is not itself a turning point: no split near it.
  const int bend = NearestIndex(c, 0, 40, 40);
  for (std::int32_t s : r.splits.index) EXPECT_GT(std::abs(s - bend), 2) << "split at the gentle bend";
  // The arcs share the split point and cover the curve.
  ASSERT_GE(r.stats.size(), 2u);
  EXPECT_EQ(r.stats.front().begin, 0);
  EXPECT_EQ(r.stats.back().end, static_cast<int>(c.x.size()) - 1);
  for (std::size_t i = 1; i < r.stats.size(); ++i) EXPECT_EQ(r.stats[i].begin, r.stats[i - 1].end);
}

TEST(FitArcs, SplitsAnSCurveNearItsInflection) {
  Curves c;
  c.clear();
  const double R = 40;
  // Quarter of the circle around (100, 100) from (60, 100) up to (100, 60), then the opposite
  // quarter around (100, 20) from (100, 60) to (140, 20): tangent continuous, curvature flips
  // sign at (100, 60).
  auto f = [R](double s) {
    if (s <= 0.5) {
      const double phi = kPi + (s / 0.5) * (kPi / 2);
      return Pt{100 + R * std::cos(phi), 100 + R * std::sin(phi)};
    }
    const double phi = kPi / 2 - ((s - 0.5) / 0.5) * (kPi / 2);
    return Pt{100 + R * std::cos(phi), 20 + R * std::sin(phi)};
  };
  AppendCurve(f, 2 * R * kPi / 2, kEdgePlus, ConstGrad, &c);
  const int inflection = NearestIndex(c, 0, 100, 60);
  const ArcRun r = RunArcStage(c);
  ASSERT_EQ(r.splits.index.size(), 1u) << "expected exactly the inflection split";
  EXPECT_LE(std::abs(r.splits.index[0] - inflection), 12)
      << "split at " << r.splits.index[0] << ", inflection at " << inflection;
  ASSERT_EQ(r.stats.size(), 2u);
}

TEST(FitArcs, SmoothCircleArcIsNotSplit) {
  for (double R : {20.0, 60.0, 200.0}) {
    Curves c;
    c.clear();
    // 150 degrees of a circle.
    AppendCurve([R](double s) {
      const double phi = 0.1 + s * (150 * kPi / 180);
      return Pt{300 + R * std::cos(phi), 300 + R * std::sin(phi)};
    }, R * 2.7, kEdgePlus, ConstGrad, &c);
    const ArcRun r = RunArcStage(c);
    EXPECT_EQ(r.splits.index.size(), 0u) << "R = " << R;
    ASSERT_EQ(r.stats.size(), 1u);
    EXPECT_EQ(r.stats[0].begin, 0);
    EXPECT_EQ(r.stats[0].end, static_cast<int>(c.x.size()) - 1);
  }
}

// Quadrant arcs of a circle around (cx, cy), screen coordinates (y down). Quadrant q spans the
// screen angles: I upper-right (x > cx, y < cy), II upper-left, III lower-left, IV lower-right.
void AppendQuadrantArc(int quadrant, double cx, double cy, double r, bool reversed, Curves* c) {
  // Angle of the direction (cos phi, -sin phi) measured counter-clockwise on screen.
  const double lo = (quadrant - 1) * kPi / 2 + 0.12, hi = quadrant * kPi / 2 - 0.12;
  auto f = [=](double s) {
    const double phi = reversed ? hi - s * (hi - lo) : lo + s * (hi - lo);
    return Pt{cx + r * std::cos(phi), cy - r * std::sin(phi)};
  };
  // The gradient of a bright disc on a dark ground points inwards; either way its class is the same.
  auto grad = [=](int x, int y) { return Pt{-(x - cx) * 10, -(y - cy) * 10}; };
  const std::uint8_t cls = (quadrant == 1 || quadrant == 3) ? kEdgeMinus : kEdgePlus;
  AppendCurve(f, r * 1.6, cls, grad, c);
}

TEST(FitArcs, QuadrantClassificationOfTheFourArcsOfACircle) {
  for (double r : {12.0, 30.0, 90.0}) {
    for (bool reversed : {false, true}) {
      Curves c;
      c.clear();
      for (int q = 1; q <= 4; ++q) AppendQuadrantArc(q, 200, 150, r, reversed, &c);
      // Sanity of the construction: the classes follow eq. 1 on the stored gradients.
      for (int k = 0; k < c.size(); ++k) {
        for (int i = c.offset[k]; i < c.offset[k + 1]; ++i) {
          const int prod = c.gx[i] * c.gy[i];
          if (prod == 0) continue;
          EXPECT_EQ(c.sign_class[k], prod > 0 ? kEdgePlus : kEdgeMinus);
        }
      }
      const ArcRun run = RunArcStage(c);
      ASSERT_EQ(run.stats.size(), 4u) << "r = " << r;
      for (int q = 1; q <= 4; ++q) {
        const ArcStats& s = run.stats[q - 1];
        EXPECT_EQ(s.curve, q - 1);
        EXPECT_EQ(s.quadrant, q) << "r = " << r << " reversed = " << reversed;
        // Where the quadrant lies on screen.
        const bool right = q == 1 || q == 4, up = q == 1 || q == 2;
        EXPECT_EQ(s.min_x >= 200, right);
        EXPECT_EQ(s.max_y <= 150, up);
        // End-tangent gradient sums point along the stored gradients' direction (inwards).
        EXPECT_LT(s.g0x * (s.x0 - 200) + s.g0y * (s.y0 - 150), 0);
        EXPECT_LT(s.g1x * (s.x1 - 200) + s.g1y * (s.y1 - 150), 0);
      }
    }
  }
}

TEST(FitArcs, ArcStatsDropsShortArcs) {
  Curves c;
  c.clear();
  AppendQuadrantArc(2, 100, 100, 10, false, &c);
  const int n = c.offset[1];
  EXPECT_EQ(RunArcStage(c, n).stats.size(), 1u);
  EXPECT_EQ(RunArcStage(c, n + 1).stats.size(), 0u);
}

// A drawn circle: 8-connected rim pixels with radial gradients, classed by eq. 1.
TEST(FitArcs, TraceCurvesOnADrawnCircleGivesOneChainPerQuadrant) {
  const int w = 200, h = 160, cx = 97, cy = 83, r = 50;
  std::vector<std::uint8_t> map(static_cast<std::size_t>(w) * h, 0);
  std::vector<std::int16_t> dx(map.size(), 0), dy(map.size(), 0);
  // Rim: the pixels whose distance to the centre rounds to r (a closed 8-connected ring, 1-2 px thick
  // is avoided by taking the pixels inside the disc that have a 4-neighbour outside it).
  auto inside = [&](int x, int y) { return (x - cx) * (x - cx) + (y - cy) * (y - cy) <= r * r; };
  int rim = 0;
  for (int y = 1; y + 1 < h; ++y) {
    for (int x = 1; x + 1 < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * w + x;
      dx[i] = static_cast<std::int16_t>(cx - x);  // bright disc: gradient points inwards
      dy[i] = static_cast<std::int16_t>(cy - y);
      if (!inside(x, y)) continue;
      if (inside(x + 1, y) && inside(x - 1, y) && inside(x, y + 1) && inside(x, y - 1)) continue;
      const int prod = dx[i] * dy[i];
      map[i] = prod > 0 ? kEdgePlus : prod < 0 ? kEdgeMinus : kEdgeNone;
      ++rim;
    }
  }
  ASSERT_GT(rim, 250);
  Curves curves;
  TraceScratch scratch;
  TraceCurves(map.data(), w, dx.data(), dy.data(), w, w, h, 10, &curves, &scratch);
  ASSERT_EQ(curves.size(), 4);
  int total = 0;
  int seen[5] = {0, 0, 0, 0, 0};
  for (int k = 0; k < curves.size(); ++k) {
    const int b = curves.offset[k], e = curves.offset[k + 1];
    total += e - b;
    // All points of one chain lie in one quadrant and carry the chain's class.
    const bool right = curves.x[b] > cx, up = curves.y[b] < cy;
    const int q = up ? (right ? 1 : 2) : (right ? 4 : 3);
    ++seen[q];
    EXPECT_EQ(curves.sign_class[k], (q == 1 || q == 3) ? kEdgeMinus : kEdgePlus);
    for (int i = b; i < e; ++i) {
      EXPECT_EQ(curves.x[i] > cx, right);
      EXPECT_EQ(curves.y[i] < cy, up);
      EXPECT_EQ(curves.gx[i], cx - curves.x[i]);
      EXPECT_EQ(curves.gy[i], cy - curves.y[i]);
      if (i > b) {  // 8-connected chain
        EXPECT_LE(std::abs(curves.x[i] - curves.x[i - 1]), 1);
        EXPECT_LE(std::abs(curves.y[i] - curves.y[i - 1]), 1);
      }
    }
  }
  for (int q = 1; q <= 4; ++q) EXPECT_EQ(seen[q], 1) << "quadrant " << q;
  // Nearly every classed rim pixel is on a chain (short spurs at staircase corners are dropped).
  EXPECT_LE(total, rim);
  EXPECT_GE(total, rim * 97 / 100);

  // The arc stage keeps each chain whole and classifies it into its quadrant.
  const ArcRun run = RunArcStage(curves, 10);
  EXPECT_EQ(run.splits.index.size(), 0u);
  ASSERT_EQ(run.stats.size(), 4u);
  for (const ArcStats& s : run.stats) {
    const bool right = s.x0 > cx, up = s.y0 < cy;
    EXPECT_EQ(s.quadrant, up ? (right ? 1 : 2) : (right ? 4 : 3));
  }

  // T_n: a minimum length above a quadrant's length drops every chain.
  TraceCurves(map.data(), w, dx.data(), dy.data(), w, w, h, rim, &curves, &scratch);
  EXPECT_EQ(curves.size(), 0);
}

TEST(FitObb, RectangleOfPoints) {
  std::vector<std::int32_t> x, y;
  for (int j = 0; j <= 10; ++j) {
    for (int i = 0; i <= 20; ++i) { x.push_back(i + 5); y.push_back(j - 3); }
  }
  std::vector<std::int64_t> hull;
  ObbSides s = MinAreaObb(x.data(), y.data(), 0, static_cast<int>(x.size()), &hull);
  EXPECT_NEAR(s.short_side, 10.0, 1e-9);
  EXPECT_NEAR(s.long_side, 20.0, 1e-9);
  // The same lattice rotated by atan2(4, 3): basis (3, 4) and (-4, 3), sides 4 * 5 and 2 * 5.
  x.clear(); y.clear();
  for (int j = 0; j <= 2; ++j) {
    for (int i = 0; i <= 4; ++i) { x.push_back(100 + 3 * i - 4 * j); y.push_back(50 + 4 * i + 3 * j); }
  }
  s = MinAreaObb(x.data(), y.data(), 0, static_cast<int>(x.size()), &hull);
  EXPECT_NEAR(s.short_side, 10.0, 1e-9);
  EXPECT_NEAR(s.long_side, 20.0, 1e-9);
  // The range [begin, end) is honoured: only the first row (a line of 5 points, 20 px long).
  s = MinAreaObb(x.data(), y.data(), 0, 5, &hull);
  EXPECT_NEAR(s.short_side, 0.0, 1e-9);
  EXPECT_NEAR(s.long_side, 20.0, 1e-9);
}

TEST(FitObb, LineOfPoints) {
  std::vector<std::int32_t> x, y;
  for (int i = 0; i < 30; ++i) { x.push_back(i); y.push_back(2 * i); }
  std::vector<std::int64_t> hull;
  const ObbSides s = MinAreaObb(x.data(), y.data(), 0, 30, &hull);
  EXPECT_NEAR(s.short_side, 0.0, 1e-9);
  EXPECT_NEAR(s.long_side, 29 * std::sqrt(5.0), 1e-9);
  // A staircase (8-connected diagonal-ish line) is thin, not zero.
  x.clear(); y.clear();
  for (int i = 0; i < 30; ++i) { x.push_back(i); y.push_back(i / 2); }
  const ObbSides t = MinAreaObb(x.data(), y.data(), 0, 30, &hull);
  EXPECT_GT(t.short_side, 0.0);
  EXPECT_LT(t.short_side, 1.0);
  EXPECT_GT(t.long_side, 29.0);
}

// The column-extreme hull agrees with a brute force over every point pair as a box side, on
// random 8-connected walks (the chains the detector feeds it) and on scattered points.
TEST(FitObb, MatchesBruteForceOnRandomWalksAndScatteredPoints) {
  auto brute = [](const std::vector<std::int32_t>& x, const std::vector<std::int32_t>& y) {
    const int n = static_cast<int>(x.size());
    double best_area = INFINITY, short_side = 0, long_side = 0;
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        const double ex = x[j] - x[i], ey = y[j] - y[i], len = std::hypot(ex, ey);
        if (len == 0) continue;
        double lo = INFINITY, hi = -INFINITY, plo = INFINITY, phi = -INFINITY;
        for (int k = 0; k < n; ++k) {
          const double along = (x[k] * ex + y[k] * ey) / len, across = (y[k] * ex - x[k] * ey) / len;
          lo = std::min(lo, along); hi = std::max(hi, along);
          plo = std::min(plo, across); phi = std::max(phi, across);
        }
        if ((hi - lo) * (phi - plo) < best_area) {
          best_area = (hi - lo) * (phi - plo);
          short_side = std::min(hi - lo, phi - plo);
          long_side = std::max(hi - lo, phi - plo);
        }
      }
    }
    return std::pair{short_side, long_side};
  };
  std::srand(11);
  std::vector<std::int64_t> hull;
  for (int trial = 0; trial < 60; ++trial) {
    std::vector<std::int32_t> x{300}, y{200};
    const int n = 3 + trial;
    for (int i = 1; i < n; ++i) {
      if (trial % 3 == 2) {  // scattered
        x.push_back(std::rand() % 50); y.push_back(std::rand() % 50);
      } else {               // 8-connected walk
        x.push_back(x.back() + std::rand() % 3 - 1); y.push_back(y.back() + std::rand() % 3 - 1);
      }
    }
    const ObbSides s = MinAreaObb(x.data(), y.data(), 0, n, &hull);
    const auto [short_side, long_side] = brute(x, y);
    if (short_side == 0 && long_side == 0) continue;  // all points equal
    EXPECT_NEAR(s.short_side * s.long_side, short_side * long_side, 1e-6) << "trial " << trial;
    EXPECT_LE(s.short_side, s.long_side);  // (equal-area boxes can differ in shape: area only)
  }
}

// The O(1) / one-pass OBB tests never contradict MinAreaObb, and each proves its case often on
// curve-like point sets (arcs of circles, near-straight walks, random walks).
TEST(FitArcs, ObbQuickTestsAgreeWithTheBox) {
  std::srand(23);
  std::vector<std::int64_t> hull;
  int proven_at_least = 0, proven_below = 0;
  for (int trial = 0; trial < 400; ++trial) {
    std::vector<std::int32_t> x, y;
    const int n = 5 + trial % 60;
    const int kind = trial % 4;
    const double r = 5 + trial % 40, span = 0.3 + 0.01 * (trial % 250);
    for (int i = 0; i < n; ++i) {
      if (kind == 0) {  // an arc of a circle
        const double t = span * i / n;
        x.push_back(static_cast<std::int32_t>(std::lround(100 + r * std::cos(t))));
        y.push_back(static_cast<std::int32_t>(std::lround(100 + r * std::sin(t))));
      } else if (kind == 1) {  // a near-straight walk
        x.push_back(i);
        y.push_back(std::rand() % 4 == 0 ? 1 : 0);
      } else if (kind == 3) {  // a near-straight walk about as thick as the default T_O, tilted
        x.push_back(i + i / 3);
        y.push_back(i / 2 + std::rand() % 3);
      } else {  // a random 8-connected walk
        x.push_back(i == 0 ? 0 : x.back() + std::rand() % 3 - 1);
        y.push_back(i == 0 ? 0 : y.back() + std::rand() % 3 - 1);
      }
    }
    const ObbSides box = MinAreaObb(x.data(), y.data(), 0, n, &hull);
    for (const double t : {1.0, 2.0, 3.0, 5.0}) {
      if (ObbShortSideAtLeast(x.data(), y.data(), 0, n, t)) {
        EXPECT_GE(box.short_side, t - 1e-9) << "trial " << trial << " t " << t;
        ++proven_at_least;
      }
    }
    const ObbShortSideBounds bounds = ShortSideBounds(x.data(), y.data(), 0, n, 0);
    EXPECT_LE(bounds.lower, box.short_side) << "trial " << trial;
    EXPECT_GE(bounds.upper, box.short_side) << "trial " << trial;
    for (const double t : {1.0, 2.0, 3.0, 5.0}) {
      proven_at_least += bounds.lower >= t;
      proven_below += bounds.upper < t;
      // Asked at t, the lower bound is left out only when the upper one already decides.
      const ObbShortSideBounds at_t = ShortSideBounds(x.data(), y.data(), 0, n, t);
      EXPECT_EQ(at_t.upper, bounds.upper);
      EXPECT_TRUE(at_t.lower == bounds.lower || (at_t.lower == 0 && at_t.upper < t));
    }
  }
  EXPECT_GT(proven_at_least, 200);
  EXPECT_GT(proven_below, 200);
}

}  // namespace
}  // namespace ellipsekit

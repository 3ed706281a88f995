// Inputs and helpers shared by the arc-stage conformance tests (conformance_polyline.cc,
// conformance_arc_split.cc, conformance_arc_stats.cc): curve sets that reach every branch and
// bound of kernels/polyline.h, arc_split.h and arc_stats.h, the curves traced from every dataset
// image, a loop over the Highway targets, and a first-difference report for output vectors.
//
// Curve sets (all coordinates in [0, 16383], kMaxImageDimension - 1; fixed seeds):
//   random 8-connected walks (short and long, > 4096 points), 1- and 2-point curves, straight
//   lines in many directions (longer than kMaxSegmentComponent, so segments get halved, and
//   exactly at it), zig-zags and plateaus (ties in the farthest-point search), walks squeezed
//   against 0 and against 16383, a full-size diagonal, each also alone (fewer points than one
//   vector: the kernels' scalar fallbacks), and the curves of every dataset image.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "kernels/arc_types.h"
#include "kernels/edge_sign.h"
#include "tests/conformance_util.h"
#include "tests/stage_test_util.h"

namespace ellipsekit::conformance {

inline constexpr std::int32_t kMaxCoord = kMaxImageDimension - 1;

struct CurveSet {
  std::string name;
  Curves curves;
};

// Appends one curve with random gradients (any int16 Sobel value) and a random sign class.
inline void AddCurve(const std::vector<std::int32_t>& xs, const std::vector<std::int32_t>& ys, std::mt19937* rng,
                     Curves* c) {
  if (c->offset.empty()) c->offset.assign(1, 0);
  std::uniform_int_distribution<int> grad(-1020, 1020);
  for (std::size_t i = 0; i < xs.size(); ++i) {
    c->x.push_back(xs[i]);
    c->y.push_back(ys[i]);
    c->gx.push_back(static_cast<std::int16_t>(grad(*rng)));
    c->gy.push_back(static_cast<std::int16_t>(grad(*rng)));
  }
  c->offset.push_back(static_cast<std::int32_t>(c->x.size()));
  c->sign_class.push_back((*rng)() % 2 ? kEdgePlus : kEdgeMinus);
}

// An 8-connected random walk of n points inside [lo, hi]^2, with some persistence of direction
// so it bends like an edge rather than a cloud.
inline void AddWalk(int n, std::int32_t lo, std::int32_t hi, std::mt19937* rng, Curves* c) {
  std::vector<std::int32_t> xs, ys;
  std::int32_t x = lo + static_cast<std::int32_t>((*rng)() % (hi - lo + 1));
  std::int32_t y = lo + static_cast<std::int32_t>((*rng)() % (hi - lo + 1));
  int dir = static_cast<int>((*rng)() % 8);
  const int ddx[8] = {1, 1, 0, -1, -1, -1, 0, 1}, ddy[8] = {0, 1, 1, 1, 0, -1, -1, -1};
  for (int i = 0; i < n; ++i) {
    xs.push_back(x);
    ys.push_back(y);
    const std::uint32_t r = (*rng)() % 10;
    if (r == 0) dir = (dir + 1) % 8;
    if (r == 1) dir = (dir + 7) % 8;
    if (r == 2) dir = static_cast<int>((*rng)() % 8);
    std::int32_t nx = x + ddx[dir], ny = y + ddy[dir];
    if (nx < lo || nx > hi || ny < lo || ny > hi) {  // turn back inside
      dir = (dir + 4) % 8;
      nx = std::clamp(x + ddx[dir], lo, hi);
      ny = std::clamp(y + ddy[dir], lo, hi);
    }
    x = nx;
    y = ny;
  }
  AddCurve(xs, ys, rng, c);
}

// A digital straight line of n points from (x0, y0) with direction (dx, dy) (Bresenham-like
// rounding of the exact positions), 8-connected since |dx|, |dy| <= 1 per step on the major axis.
inline void AddLine(std::int32_t x0, std::int32_t y0, int dx, int dy, int n, std::mt19937* rng, Curves* c) {
  std::vector<std::int32_t> xs, ys;
  const int major = std::max(std::abs(dx), std::abs(dy));
  for (int i = 0; i < n; ++i) {
    xs.push_back(x0 + static_cast<std::int32_t>(std::lround(static_cast<double>(i) * dx / major)));
    ys.push_back(y0 + static_cast<std::int32_t>(std::lround(static_cast<double>(i) * dy / major)));
  }
  AddCurve(xs, ys, rng, c);
}

// Zig-zag: `teeth` teeth of height h (every step diagonal), starting at (x0, y0).
inline void AddZigZag(std::int32_t x0, std::int32_t y0, int h, int teeth, std::mt19937* rng, Curves* c) {
  std::vector<std::int32_t> xs{x0}, ys{y0};
  for (int t = 0; t < teeth; ++t) {
    for (int s = 0; s < 2 * h; ++s) {
      xs.push_back(xs.back() + 1);
      ys.push_back(ys.back() + (s < h ? 1 : -1));
    }
  }
  AddCurve(xs, ys, rng, c);
}

// A trapezoid bump: up h diagonally, flat for `flat` points, down h: every flat point is equally
// far from the chord, so the farthest-point search must return the first of them.
inline void AddPlateau(std::int32_t x0, std::int32_t y0, int h, int flat, std::mt19937* rng, Curves* c) {
  std::vector<std::int32_t> xs{x0}, ys{y0};
  auto step = [&](int dx, int dy) {
    xs.push_back(xs.back() + dx);
    ys.push_back(ys.back() + dy);
  };
  for (int i = 0; i < h; ++i) step(1, 1);
  for (int i = 0; i < flat; ++i) step(1, 0);
  for (int i = 0; i < h; ++i) step(1, -1);
  AddCurve(xs, ys, rng, c);
}

// A full digital circle of radius r around (cx, cy), traced in order (8-connected).
inline void AddCircle(std::int32_t cx, std::int32_t cy, int r, std::mt19937* rng, Curves* c) {
  std::vector<std::int32_t> xs, ys;
  const int n = static_cast<int>(8 * r);
  for (int i = 0; i < n; ++i) {
    const double t = 2.0 * 3.14159265358979323846 * i / n;
    const std::int32_t x = cx + static_cast<std::int32_t>(std::lround(r * std::cos(t)));
    const std::int32_t y = cy + static_cast<std::int32_t>(std::lround(r * std::sin(t)));
    if (!xs.empty() && xs.back() == x && ys.back() == y) continue;
    xs.push_back(x);
    ys.push_back(y);
  }
  AddCurve(xs, ys, rng, c);
}

// The curves of one image as the detector traces them (scalar edge stage, default options);
// min_points 1 keeps every curve, not only those the detector keeps.
inline Curves CurvesOfImage(const cv::Mat& m, int min_points) {
  return stage_test::ScalarCurves(stage_test::ViewOf(m), Options(), min_points);
}

inline const std::vector<CurveSet>& ArcCurveSets() {
  static const std::vector<CurveSet> sets = [] {
    std::vector<CurveSet> s;
    std::mt19937 rng(20240611);
    auto set = [&](std::string name) -> Curves& {
      s.push_back({std::move(name), Curves{}});
      s.back().curves.clear();
      return s.back().curves;
    };
    set("empty");
    AddCurve({5}, {7}, &rng, &set("one 1-point curve"));
    AddCurve({5, 6}, {7, 8}, &rng, &set("one 2-point curve"));
    AddCurve({0, 1, 2}, {0, 1, 0}, &rng, &set("one 3-point curve"));
    AddZigZag(100, 100, 1, 3, &rng, &set("one short zig-zag"));
    {
      Curves& c = set("1..4-point curves");
      for (int i = 0; i < 40; ++i) AddWalk(1 + i % 4, 0, kMaxCoord, &rng, &c);
    }
    for (std::uint32_t seed = 1; seed <= 6; ++seed) {
      Curves& c = set("random walks seed " + std::to_string(seed));
      std::mt19937 r(seed);
      for (int i = 0; i < 60; ++i) AddWalk(1 + static_cast<int>(r() % 700), 0, kMaxCoord, &r, &c);
    }
    {
      Curves& c = set("long walks (> 4096 points)");
      std::mt19937 r(77);
      AddWalk(5000, 0, kMaxCoord, &r, &c);
      AddWalk(20000, 1000, 3000, &r, &c);
      AddWalk(4097, 0, kMaxCoord, &r, &c);
    }
    {
      Curves& c = set("straight lines");
      const int dirs[][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}, {1, 1}, {-1, 1}, {2, 1}, {1, 3},
                             {-5, 2}, {7, -3}, {1, 10}, {13, 1}};
      for (const auto& dxy : dirs) {
        for (int n : {2, 3, 17, 100, 1024, 1025, 1026, 2049, 3000}) AddLine(8000, 8000, dxy[0], dxy[1], n, &rng, &c);
      }
    }
    {
      Curves& c = set("lines at kMaxSegmentComponent");
      for (int n : {1023, 1024, 1025, 2048, 2049, 4097, 8193}) {
        AddLine(0, 0, 1, 0, n, &rng, &c);
        AddLine(0, kMaxCoord, 1, -1, n, &rng, &c);
        AddLine(kMaxCoord, 0, 0, 1, n, &rng, &c);
      }
    }
    AddLine(0, 0, 1, 1, kMaxImageDimension, &rng, &set("full diagonal (0,0)-(16383,16383)"));
    AddLine(0, kMaxCoord, 1, -1, kMaxImageDimension, &rng, &set("full anti-diagonal"));
    {
      Curves& c = set("zig-zags and plateaus (ties)");
      for (int h : {1, 2, 3, 8, 50}) {
        for (int teeth : {1, 2, 5, 40}) AddZigZag(200, 5000, h, teeth, &rng, &c);
      }
      for (int h : {1, 3, 10, 40}) {
        for (int flat : {0, 1, 2, 15, 16, 17, 33, 100}) AddPlateau(300, 9000, h, flat, &rng, &c);
      }
    }
    {
      Curves& c = set("near 0");
      for (int i = 0; i < 30; ++i) AddWalk(1 + static_cast<int>(rng() % 300), 0, 40, &rng, &c);
    }
    {
      Curves& c = set("near 16383");
      for (int i = 0; i < 30; ++i) AddWalk(1 + static_cast<int>(rng() % 300), kMaxCoord - 40, kMaxCoord, &rng, &c);
    }
    {
      Curves& c = set("circles");
      for (int r : {2, 5, 20, 100, 700, 3000}) AddCircle(8191, 8191, r, &rng, &c);
      AddCircle(8191, 8191, 8191, &rng, &c);
    }
    for (const std::string& path : DatasetImagePaths()) {
      const cv::Mat m = cv::imread(path, cv::IMREAD_GRAYSCALE);
      if (m.empty()) continue;
      s.push_back({path + " (all traced curves)", CurvesOfImage(m, 1)});
      s.push_back({path + " (curves >= T_n points)", CurvesOfImage(m, Options().min_curve_points)});
    }
    return s;
  }();
  return sets;
}

// One line saying what a test covered (the sets, their points, the targets).
inline void PrintCoverage(const char* test) {
  std::size_t points = 0;
  for (const CurveSet& s : ArcCurveSets()) points += s.curves.x.size();
  std::string names;
  for (const simd::TargetKernels& t : simd::Targets()) names += std::string(names.empty() ? "" : ",") + t.name;
  std::printf("%s: %zu curve sets, %zu points, targets %s\n", test, ArcCurveSets().size(), points, names.c_str());
}

// Runs fn once per Highway target compiled in and supported here, with that target's kernels.
inline void ForEachSimdTarget(const std::function<void(const simd::TargetKernels& target)>& fn) {
  ASSERT_FALSE(simd::Targets().empty());
  for (const simd::TargetKernels& t : simd::Targets()) fn(t);
}

// "" when equal; otherwise the sizes or the first differing element.
template <class T, class Eq = std::equal_to<T>>
std::string FirstDifference(const std::vector<T>& want, const std::vector<T>& got, Eq eq = Eq()) {
  if (want.size() != got.size()) {
    return "size " + std::to_string(got.size()) + ", scalar " + std::to_string(want.size());
  }
  for (std::size_t i = 0; i < want.size(); ++i) {
    if (!eq(want[i], got[i])) {
      std::ostringstream s;
      s << "element " << i << " differs";
      if constexpr (std::is_arithmetic_v<T>) s << ": scalar " << want[i] << ", simd " << got[i];
      return s.str();
    }
  }
  return "";
}

}  // namespace ellipsekit::conformance

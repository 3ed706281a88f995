// ClassifyFlatStretches (fit/flat_stretches.h): a level stretch whose eq. 1 class flickers takes
// the classes of its shape (one change, at the apex) and is traced as two long curves, also at the
// end of a row in frames of any width; a clean stretch, a short one, one with a speck of the other
// class, a slow alternation and an upright one keep their classes; on a hard tabletop frame the
// option finds a wooden top the flicker hid, and `flat_stretch_classes=false` does not.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "ellipsekit/detector.h"
#include "fit/curve_tracing.h"
#include "fit/flat_stretches.h"
#include "kernels/edge_sign.h"
#include "tools/eval/metrics.h"
#include "tools/scenes/rng.h"
#include "tools/scenes/tabletop_scenes.h"

namespace ellipsekit {
namespace {

constexpr int kW = 160, kH = 80;

// An edge map and its gradients: the pixels set by Add, classed as eq. 1 does (edge_sign.h).
struct Frame {
  int w;
  std::vector<std::uint8_t> edges;
  std::vector<std::int16_t> dx, dy;
  std::vector<std::int32_t> queue;

  explicit Frame(int width = kW) : w(width), edges(w * kH, 0), dx(w * kH, 0), dy(w * kH, 0), queue(w * kH, 0) {}
  void Add(int x, int y, int gx, int gy) {
    const int i = y * w + x;
    dx[i] = static_cast<std::int16_t>(gx);
    dy[i] = static_cast<std::int16_t>(gy);
    edges[i] = gx * gy > 0 ? kEdgePlus : gx * gy < 0 ? kEdgeMinus : kEdgeNone;
  }
  int Classify() { return ClassifyFlatStretches(edges.data(), w, dx.data(), dy.data(), w, w, kH, queue.data()); }
  std::uint8_t At(int x, int y) const { return edges[y * w + x]; }
};

// The upper half of an ellipse centred at (80, 50), a = 60, b = 20: one pixel per column, the
// gradient its outward normal (magnitude ~40). `noise`: within `flicker` px of the apex, dx is
// +-noise alternately (a weak flat edge's), every 2 px.
void AddUpperArc(Frame* f, int noise, int flicker) {
  for (int x = 22; x <= 138; ++x) {
    const double u = (x - 80) / 60.0;
    const int y = static_cast<int>(std::lround(50 - 20 * std::sqrt(1 - u * u)));
    const double nx = u / 60.0, ny = -(std::sqrt(1 - u * u)) / 20.0, len = std::hypot(nx, ny);
    int gx = static_cast<int>(std::lround(40 * nx / len));
    const int gy = static_cast<int>(std::lround(40 * ny / len));
    if (std::abs(x - 80) <= flicker) gx = ((x / 2) % 2 == 0 ? 1 : -1) * noise;
    f->Add(x, y, gx, gy);
  }
}

// The classes along the arc, left to right, and how often they change.
int Changes(const Frame& f, std::uint8_t* left, std::uint8_t* right) {
  int changes = 0;
  std::uint8_t last = 0;
  for (int x = 22; x <= 138; ++x) {
    for (int y = 0; y < kH; ++y) {
      const std::uint8_t c = f.At(x, y);
      if (c == 0) continue;
      if (last != 0 && c != last) ++changes;
      if (x == 60) *left = c;
      if (x == 100) *right = c;
      last = c;
    }
  }
  return changes;
}

TEST(FlatStretches, FlickeringApexTakesTheClassesOfItsShape) {
  Frame f;
  AddUpperArc(&f, 5, 14);
  std::uint8_t left = 0, right = 0;
  ASSERT_GE(Changes(f, &left, &right), 10);  // the flicker
  EXPECT_GT(f.Classify(), 0);
  EXPECT_EQ(Changes(f, &left, &right), 1);  // at the apex only
  EXPECT_EQ(left, kEdgePlus);              // the upper-left quarter, as eq. 1
  EXPECT_EQ(right, kEdgeMinus);
  // Traced: two curves, each half of the arc, instead of pieces shorter than T_n = 15.
  Curves curves;
  TraceScratch scratch;
  TraceCurves(f.edges.data(), kW, f.dx.data(), f.dy.data(), kW, kW, kH, 15, &curves, &scratch);
  ASSERT_EQ(curves.size(), 2);
  EXPECT_GE(curves.offset[1] - curves.offset[0], 55);
  EXPECT_GE(curves.offset[2] - curves.offset[1], 55);
}

// A flickering level stretch that ends at the right border is found there too, whatever the
// frame's width (the last pixels of a row are read as one word ending at the row's end), and in
// a frame narrower than a word.
TEST(FlatStretches, FlickerAtTheRowsEndInFramesOfEveryWidth) {
  for (int width = 3; width <= 64; ++width) {
    Frame f(width);
    const int from = std::max(0, width - kFlatMinPixels);  // the shortest stretch, at the end
    // One row, then the next from its middle on: descending to the right, the tangent's class is
    // kEdgeMinus all along.
    auto y_at = [&](int x) { return 30 + (2 * (x - from) >= width - from ? 1 : 0); };
    for (int x = from; x < width; ++x) f.Add(x, y_at(x), x % 2 == 0 ? 5 : -5, 40);
    const bool flat = width - from >= kFlatMinPixels;  // long enough to be a stretch
    EXPECT_EQ(f.Classify() > 0, flat) << width;
    for (int x = from; flat && x < width; ++x) EXPECT_EQ(f.At(x, y_at(x)), kEdgeMinus) << width << " " << x;
  }
}

TEST(FlatStretches, CleanShortSpeckledAndUprightStretchesKeepTheirClasses) {
  Frame clean;
  AddUpperArc(&clean, 0, -1);
  const std::vector<std::uint8_t> before = clean.edges;
  EXPECT_EQ(clean.Classify(), 0);
  EXPECT_EQ(clean.edges, before);

  // A level stretch of 7 pixels whose classes alternate (fewer than kFlatMinPixels) keeps them;
  // one of 8 takes one class (a straight stretch: the slope's sign throughout).
  for (const int n : {kFlatMinPixels - 1, kFlatMinPixels}) {
    Frame line;
    for (int x = 70; x < 70 + n; ++x) line.Add(x, 30, x % 2 == 0 ? 5 : -5, 40);
    const std::vector<std::uint8_t> line_before = line.edges;
    line.Classify();
    if (n < kFlatMinPixels) {
      EXPECT_EQ(line.edges, line_before);
    } else {
      for (int x = 71; x < 70 + n; ++x) EXPECT_EQ(line.At(x, 30), line.At(70, 30)) << x;
    }
  }

  // A straight level stretch with one pixel of the other class (two changes: a junction or a
  // speck, not a flicker) keeps its classes.
  Frame speck;
  for (int x = 60; x < 80; ++x) speck.Add(x, 30, x == 66 ? -5 : 5, 40);
  const std::vector<std::uint8_t> speck_before = speck.edges;
  EXPECT_EQ(speck.Classify(), 0);
  EXPECT_EQ(speck.edges, speck_before);

  // A level stretch whose class changes every 8 px, once in each aligned run of 8 pixels: a slow
  // alternation (texture along an edge), not the flicker of a flat apex (changes 2-3 px apart).
  Frame slow;
  for (int x = 64; x < 104; ++x) slow.Add(x, 30, (x / 8) % 2 == 0 ? 5 : -5, 40);
  const std::vector<std::uint8_t> slow_before = slow.edges;
  EXPECT_EQ(slow.Classify(), 0);
  EXPECT_EQ(slow.edges, slow_before);

  // An upright edge three pixels wide whose dy flickers (classes alternate side by side): not
  // level, so kept.
  Frame upright;
  for (int y = 10; y < 70; ++y) {
    for (int x = 40; x <= 42; ++x) upright.Add(x, y, 40, (x + y / 2) % 2 == 0 ? 5 : -5);
  }
  const std::vector<std::uint8_t> upright_before = upright.edges;
  EXPECT_EQ(upright.Classify(), 0);
  EXPECT_EQ(upright.edges, upright_before);
}

// Hard tabletop seed 1, frame 16 (`ellipsekit scenes --hard --seed 1`): its wooden top at (321,
// 207) (a 48 px, b 35 px) is found with the flat stretches classed by their shape and not without.
TEST(FlatStretches, FindsTheWoodenTopOfHardTabletopFrame16) {
  const scenes::TabletopScene s = scenes::RenderTabletopScene(scenes::MixSeed(1, 16));
  ASSERT_FALSE(s.gray.empty());
  int wood = -1;
  for (std::size_t i = 0; i < s.tops.size(); ++i) {
    if (s.tops[i].kind == scenes::TabletopKind::kWood && std::abs(s.truth[i].cx - 321) < 2 &&
        std::abs(s.truth[i].cy - 207) < 2) {
      wood = static_cast<int>(i);
    }
  }
  ASSERT_GE(wood, 0);
  auto found = [&](bool flat) {
    Options o;
    o.flat_stretch_classes = flat;
    Detector detector(o);
    DetectionResult r;
    EXPECT_TRUE(detector.detect({s.gray.data, s.gray.cols, s.gray.rows, static_cast<std::ptrdiff_t>(s.gray.step)}, &r).ok());
    return eval::MatchEllipses(r.ellipses, s.truth).detection_of_truth[wood] >= 0;
  };
  EXPECT_TRUE(found(true));
  EXPECT_FALSE(found(false));
}

}  // namespace
}  // namespace ellipsekit

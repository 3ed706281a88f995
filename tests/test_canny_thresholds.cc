// ThresholdsFromHistogram (kernels/canny_thresholds.h) on histograms whose quantiles are known:
// the percentile rule, and the floor that follows the frame's contrast; SelectThresholds: each
// tile's pair from its maximum; the scalar MagnitudeHistogram's tiles' maxima.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <iterator>
#include <vector>

#include "kernels/canny_thresholds.h"

namespace ellipsekit {
namespace {

// 1000 pixels: 900 at magnitude `ground` (Q(500) = Q(900) = ground), 95 at `outline`, 5 at
// `peak`, so Q(995) = outline.
std::vector<std::uint32_t> Histogram(int outline, int peak, int ground = 2) {
  std::vector<std::uint32_t> hist(kMaxMagnitude + 1, 0);
  hist[ground] += 900;
  hist[outline] += 95;
  hist[peak] += 5;
  return hist;
}

TEST(CannyThresholds, FixedFloorWhenContrastRefIsZero) {
  const auto hist = Histogram(50, 100);
  const CannyThresholds t = ThresholdsFromHistogram(hist.data(), 900, 400, 40, 0);
  EXPECT_EQ(t.high, 40);
  EXPECT_EQ(t.low, 16);
}

TEST(CannyThresholds, FloorFollowsContrast) {
  // Q(995) = 100 of a reference 200: floor 40 * 100 / 200 = 20.
  CannyThresholds t = ThresholdsFromHistogram(Histogram(100, 300).data(), 900, 400, 40, 200);
  EXPECT_EQ(t.high, 20);
  EXPECT_EQ(t.low, 8);
  // Q(995) = 150: 40 * 150 / 200 = 30.
  t = ThresholdsFromHistogram(Histogram(150, 300).data(), 900, 400, 40, 200);
  EXPECT_EQ(t.high, 30);
  // Q(995) at or above the reference: the full floor.
  EXPECT_EQ(ThresholdsFromHistogram(Histogram(200, 300).data(), 900, 400, 40, 200).high, 40);
  EXPECT_EQ(ThresholdsFromHistogram(Histogram(900, 1000).data(), 900, 400, 40, 200).high, 40);
}

TEST(CannyThresholds, FloorNeverUnderAQuarter) {
  // Q(995) = 20: 40 * 20 / 200 = 4, held at 40 / 4 = 10.
  const CannyThresholds t = ThresholdsFromHistogram(Histogram(20, 30).data(), 900, 400, 40, 200);
  EXPECT_EQ(t.high, 10);
  EXPECT_EQ(t.low, 4);
}

TEST(CannyThresholds, FloorNeverUnderTheNoise) {
  // Q(995) = 100 would give 20, but the median magnitude is 8: the floor is 3 x 8 = 24.
  CannyThresholds t = ThresholdsFromHistogram(Histogram(100, 300, 8).data(), 900, 400, 40, 200);
  EXPECT_EQ(t.high, 24);
  EXPECT_EQ(t.low, 9);
  // A median of 15: 3 x 15 = 45, held at min_high.
  EXPECT_EQ(ThresholdsFromHistogram(Histogram(100, 300, 15).data(), 900, 400, 40, 200).high, 40);
}

TEST(CannyThresholds, PercentileAboveTheFloorWins) {
  // 1000 pixels: 899 at 0, then 101 at 60: Q(900) = 60, Q(995) = 60 -> floor 12; high 60.
  std::vector<std::uint32_t> hist(kMaxMagnitude + 1, 0);
  hist[0] = 899;
  hist[60] = 101;
  const CannyThresholds t = ThresholdsFromHistogram(hist.data(), 900, 400, 40, 200);
  EXPECT_EQ(t.high, 60);
  EXPECT_EQ(t.low, 24);
}

TEST(CannyThresholds, FlatFrame) {
  // Every magnitude 0: Q(995) = 0, so the floor is a quarter of min_high.
  std::vector<std::uint32_t> hist(kMaxMagnitude + 1, 0);
  hist[0] = 640 * 120;
  EXPECT_EQ(ThresholdsFromHistogram(hist.data(), 900, 400, 40, 200).high, 10);
  EXPECT_EQ(ThresholdsFromHistogram(hist.data(), 900, 400, 40, 0).high, 40);
}

// Histogram(300, 400, 20): Q(900) = 20 under a floor of 40, so high 40; Q(995) = 300, noise bound
// 3 x 20 = 60 (above high / 4 = 10).
TEST(CannyThresholds, TilesLowerInProportionToTheirMaximum) {
  CannyTiles tiles;
  tiles.Resize(64 * 7, 64, 6);  // seven 64 px tiles in a row
  ASSERT_EQ(tiles.tiles_x, 7);
  ASSERT_EQ(tiles.high.size(), 7u);
  const std::uint16_t maxima[] = {300, 1000, 150, 210, 0, 39, 40};
  std::copy(std::begin(maxima), std::end(maxima), tiles.tile_max.begin());
  SelectThresholds(Histogram(300, 400, 20).data(), 900, 400, 40, 200, &tiles);
  ASSERT_EQ(tiles.frame.high, 40);
  ASSERT_EQ(tiles.frame.contrast, 300);
  ASSERT_EQ(tiles.frame.noise, 60);
  // Lowered tiles (40 <= M < 300) are held at max(10, 60), above the frame's 40: all keep 40.
  for (int t = 0; t < 7; ++t) EXPECT_EQ(tiles.high[t], 40) << "tile " << t;
  // With a low noise bound the proportion shows: Histogram(300, 400, 2): noise 6, high / 4 = 10.
  SelectThresholds(Histogram(300, 400, 2).data(), 900, 400, 40, 200, &tiles);
  ASSERT_EQ(tiles.frame.high, 40);
  EXPECT_EQ(tiles.high[0], 40);  // M = Q(995)
  EXPECT_EQ(tiles.high[1], 40);  // M above it
  EXPECT_EQ(tiles.high[2], 20);  // 40 * 150 / 300
  EXPECT_EQ(tiles.low[2], 8);    // 20 * 400 / 1000
  EXPECT_EQ(tiles.high[3], 28);  // 40 * 210 / 300
  EXPECT_EQ(tiles.high[4], 40);  // a flat tile: no strong pixel under the frame's pair, kept
  EXPECT_EQ(tiles.high[5], 40);  // M = 39 < 40: kept
  EXPECT_EQ(tiles.high[6], 10);  // M = 40: 40 * 40 / 300 = 5, held at high / 4
  EXPECT_EQ(tiles.low[6], 4);
}

TEST(CannyThresholds, OneTileKeepsTheFramesPair) {
  CannyTiles tiles;
  tiles.Resize(640, 480, CannyTileShift(0));
  ASSERT_EQ(tiles.high.size(), 1u);
  tiles.tile_max[0] = 300;  // a frame's maximum is >= its Q(995)
  SelectThresholds(Histogram(100, 300).data(), 900, 400, 40, 200, &tiles);
  EXPECT_EQ(tiles.high[0], tiles.frame.high);
  EXPECT_EQ(tiles.low[0], tiles.frame.low);
}

TEST(CannyThresholds, TileShiftOfTheOption) {
  EXPECT_EQ(CannyTileShift(0), kNmsOneTileShift);
  EXPECT_EQ(CannyTileShift(32), 5);
  EXPECT_EQ(CannyTileShift(64), 6);
  EXPECT_EQ(CannyTileShift(16384), 14);
}

// The scalar histogram's tiles' maxima: only rows 0, 4, 8, ... count; a frame's edge cuts the
// last tiles short.
TEST(CannyThresholds, TileMaximaOnTheHistogramRows) {
  const int w = 70, h = 40;  // 32 px tiles: 3 x 2, the last column and row cut short
  std::vector<std::uint16_t> mag(static_cast<std::size_t>(w) * h, 1);
  mag[5 * w + 3] = 900;     // row 5: not a histogram row, not counted
  mag[4 * w + 40] = 500;    // tile (1, 0)
  mag[36 * w + 69] = 700;   // tile (2, 1): the last pixel of a histogram row
  mag[32 * w + 0] = 60;     // tile (0, 1)
  std::vector<std::uint32_t> hist(kMaxMagnitude + 1);
  std::vector<std::uint16_t> tile_max(6, 12345);
  scalar::MagnitudeHistogram(mag.data(), w, h, w, 5, hist.data(), tile_max.data());
  EXPECT_EQ(tile_max, (std::vector<std::uint16_t>{1, 500, 1, 60, 1, 700}));
  EXPECT_EQ(hist[900], 0u);
  EXPECT_EQ(hist[500] + hist[700] + hist[60], 3u);
}

}  // namespace
}  // namespace ellipsekit

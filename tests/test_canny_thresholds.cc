// ThresholdsFromHistogram (kernels/canny_thresholds.h) on histograms whose quantiles are known:
// the percentile rule, and the floor that follows the frame's contrast.
#include <gtest/gtest.h>

#include <cstdint>
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

}  // namespace
}  // namespace ellipsekit

// The edge-map checks of the fit back end on synthetic edge maps with known rings: outer-rim
// completion (fit/rim_search.h), the recessed rim, the top over a side and the lid inside
// (fit/recessed_rim.h, fit/top_over_side.h), also end to end through the Detector on a drawn lid
// whose outer rim has contrast over only part of its length, and edge coverage, claims and fine
// coverage (fit/edge_coverage.h).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "ellipsekit/detector.h"
#include "fit/edge_coverage.h"
#include "fit/edge_refit.h"
#include "fit/recessed_rim.h"
#include "fit/rim_search.h"
#include "fit/top_over_side.h"

namespace {

using ellipsekit::Ellipse;

constexpr int kW = 200, kH = 160;

// An edge map with gradients, with rings drawn into it.
struct EdgeFrame {
  std::vector<std::uint8_t> edges = std::vector<std::uint8_t>(kW * kH, 0);
  std::vector<std::int16_t> dx = std::vector<std::int16_t>(kW * kH, 0), dy = std::vector<std::int16_t>(kW * kH, 0);

  // Marks the pixels of scale * e over parametric angles [t0, t1), gradient along the normal
  // (turned by `turn` rad, to make a ring whose gradients do not fit).
  void Ring(const Ellipse& e, double scale, double t0, double t1, double turn = 0) {
    const double a = scale * e.a, b = scale * e.b, c = std::cos(e.theta), s = std::sin(e.theta);
    for (double t = t0; t < t1; t += 0.2 / a) {
      const double u = a * std::cos(t), v = b * std::sin(t);
      const int x = static_cast<int>(std::lround(e.cx + u * c - v * s));
      const int y = static_cast<int>(std::lround(e.cy + u * s + v * c));
      if (x < 0 || y < 0 || x >= kW || y >= kH) continue;
      const double nu = std::cos(t) / a, nv = std::sin(t) / b;  // normal in the ellipse frame
      const double nx = nu * c - nv * s, ny = nu * s + nv * c, len = std::hypot(nx, ny);
      const double gx = nx * std::cos(turn) - ny * std::sin(turn), gy = nx * std::sin(turn) + ny * std::cos(turn);
      edges[y * kW + x] = 1;
      dx[y * kW + x] = static_cast<std::int16_t>(std::lround(200 * gx / len));
      dy[y * kW + x] = static_cast<std::int16_t>(std::lround(200 * gy / len));
    }
  }
  ellipsekit::EdgeMapView Input() const { return {edges.data(), kW, dx.data(), dy.data(), kW, kW, kH}; }
};

Ellipse Inner() {
  Ellipse e;
  e.cx = 97.3;
  e.cy = 81.6;
  e.a = 40;
  e.b = 26;
  e.theta = 0.3;
  e.score = 1.7;
  return e;
}

constexpr double kTwoPi = 2 * std::numbers::pi;

TEST(RimSearch, FindsAFullOuterRingAtItsScale) {
  EdgeFrame f;
  f.Ring(Inner(), 1.0, 0, kTwoPi);   // the inner ellipse itself: never its own rim
  f.Ring(Inner(), 1.22, 0, kTwoPi);  // the outer rim
  Ellipse rim;
  long scanned = 0;
  ASSERT_TRUE(ellipsekit::FindOuterRim(f.Input(), Inner(), 0.6, &rim, &scanned));
  EXPECT_NEAR(rim.a, 1.22 * Inner().a, 0.6);
  EXPECT_NEAR(rim.b, 1.22 * Inner().b, 0.6);
  EXPECT_EQ(rim.cx, Inner().cx);
  EXPECT_EQ(rim.cy, Inner().cy);
  EXPECT_EQ(rim.theta, Inner().theta);
  EXPECT_EQ(rim.score, Inner().score);
  EXPECT_GT(scanned, 0);
  EXPECT_LE(scanned, static_cast<long>(kW) * kH);
}

TEST(RimSearch, CoverageDecides) {
  EdgeFrame f;
  // 45 % of the angle, most of it on the upper (far) half: Inner()'s minor axis is near vertical.
  f.Ring(Inner(), 1.3, std::numbers::pi + 0.2, std::numbers::pi + 0.2 + 0.45 * kTwoPi);
  Ellipse rim;
  long scanned = 0;
  EXPECT_FALSE(ellipsekit::FindOuterRim(f.Input(), Inner(), 0.6, &rim, &scanned));
  EXPECT_TRUE(ellipsekit::FindOuterRim(f.Input(), Inner(), 0.4, &rim, &scanned));
  EXPECT_NEAR(rim.a, 1.3 * Inner().a, 0.6);
}

TEST(RimSearch, RejectsRingsWithWrongGradientsOrOutOfRange) {
  Ellipse rim;
  long scanned = 0;
  EdgeFrame tangential;  // edge pixels on a concentric ring, but gradients along it (texture)
  tangential.Ring(Inner(), 1.2, 0, kTwoPi, std::numbers::pi / 2);
  EXPECT_FALSE(ellipsekit::FindOuterRim(tangential.Input(), Inner(), 0.6, &rim, &scanned));
  EdgeFrame too_far;  // beyond kRimSearchMaxScale
  too_far.Ring(Inner(), 1.6, 0, kTwoPi);
  EXPECT_FALSE(ellipsekit::FindOuterRim(too_far.Input(), Inner(), 0.6, &rim, &scanned));
  EdgeFrame shifted;  // a same-shaped ring 12 px lower: not concentric
  Ellipse low = Inner();
  low.cy += 12;
  shifted.Ring(low, 1.2, 0, kTwoPi);
  EXPECT_FALSE(ellipsekit::FindOuterRim(shifted.Input(), Inner(), 0.6, &rim, &scanned));
}

TEST(RimSearch, EllipsesAtOrBeyondTheBorderAreSafe) {
  EdgeFrame f;
  f.Ring(Inner(), 1.2, 0, kTwoPi);
  Ellipse rim, e = Inner();
  long scanned = 0;
  e.cx = -500;  // the search box misses the frame
  EXPECT_FALSE(ellipsekit::FindOuterRim(f.Input(), e, 0.6, &rim, &scanned));
  EXPECT_EQ(scanned, 0);
  e = Inner();
  e.cx = 5;  // partly outside: the box is clipped
  ellipsekit::FindOuterRim(f.Input(), e, 0.6, &rim, &scanned);
  EXPECT_LE(scanned, static_cast<long>(kW) * kH);
  for (const double far : {1e12, -1e12, 1e300}) {  // far off or huge: no int overflow, nothing found
    e = Inner();
    e.cx = far;
    EXPECT_FALSE(ellipsekit::FindOuterRim(f.Input(), e, 0.6, &rim, &scanned));
    EXPECT_EQ(ellipsekit::EdgeCoverage(f.Input(), e), 0.0);
    e = Inner();
    e.a = std::abs(far);
    e.b = std::abs(far) / 2;
    ellipsekit::FindOuterRim(f.Input(), e, 0.6, &rim, &scanned);
    EXPECT_LE(scanned, static_cast<long>(kW) * kH);
    EXPECT_LE(ellipsekit::EdgeCoverage(f.Input(), e), 1.0);
  }
  e = Inner();
  e.b = 1;  // too small to have a rim band outside its own edge
  EXPECT_FALSE(ellipsekit::FindOuterRim(f.Input(), e, 0.6, &rim, &scanned));
}

// A lid drawn as a dark inner disc in a bright rim ring whose outer edge has contrast against the
// background along its upper (far) half only (the lower half of the ring is the background's gray): the
// outer rim's arcs lie in two quadrants, too few for a triplet, so only the inner edge is a
// candidate; the search, asked for half the angle, completes the outer rim.
TEST(RimSearch, DetectorReportsTheOuterRimOfADrawnLid) {
  // The outer rim has contrast over half its length: as one half along the major axis (cv::ellipse
  // angles 180-360), or as two opposite quarters (0-90 and 180-270).
  const cv::Point centre(160, 120);
  const cv::Size outer(70, 45), inner(56, 36);  // 1.25x
  auto draw = [&](bool quarters) {
    cv::Mat img(240, 320, CV_8UC1, cv::Scalar(110));
    cv::ellipse(img, centre, outer, 20, quarters ? 0 : 180, quarters ? 90 : 360, cv::Scalar(190), cv::FILLED, cv::LINE_AA);
    if (quarters) cv::ellipse(img, centre, outer, 20, 180, 270, cv::Scalar(190), cv::FILLED, cv::LINE_AA);
    cv::ellipse(img, centre, inner, 20, 0, 360, cv::Scalar(40), cv::FILLED, cv::LINE_AA);
    return img;
  };
  auto run = [&](const cv::Mat& img, double coverage) {
    ellipsekit::Options o;
    o.rim_min_coverage = coverage;
    ellipsekit::Detector d(o);
    EXPECT_TRUE(d.status().ok());
    ellipsekit::DetectionResult r;
    ellipsekit::ImageView view{img.data, img.cols, img.rows, static_cast<std::ptrdiff_t>(img.step[0])};
    EXPECT_TRUE(d.detect(view, &r).ok());
    EXPECT_EQ(r.caps_hit & ellipsekit::kCapRimSearch, 0u);
    return r.ellipses;
  };
  for (const bool quarters : {false, true}) {
    SCOPED_TRACE(quarters ? "two quarters" : "one half");
    const cv::Mat img = draw(quarters);
    const std::vector<Ellipse> without = run(img, 2.0);  // search off
    ASSERT_FALSE(without.empty());
    EXPECT_NEAR(without[0].a, inner.width, 2.0) << "the inner edge is what the arcs give";
    // 50 % coverage is below 0.6; one half backed over 90 % passes (kRimHalfCoverage).
    const std::vector<Ellipse> at_06 = run(img, 0.6);
    ASSERT_FALSE(at_06.empty());
    EXPECT_NEAR(at_06[0].a, quarters ? inner.width : outer.width, 2.0);
    const std::vector<Ellipse> with = run(img, 0.45);
    ASSERT_FALSE(with.empty());
    EXPECT_NEAR(with[0].a, outer.width, 2.0);
    EXPECT_NEAR(with[0].b, outer.height, 2.0);
    EXPECT_NEAR(with[0].cx, centre.x, 1.0);
    EXPECT_NEAR(with[0].cy, centre.y, 1.0);
  }
}

// Bounded work: the search scans at most ~2 frames' worth of pixels per frame, then stops and says
// so. Nine large overlapping circles: each search box covers most of the frame. (Measured with
// the default options: 10 ellipses, the budget reached; six such circles stopped reaching it once
// cluster_recessed_rims and fit_pair_centers changed which of their ellipses are kept.)
TEST(RimSearch, BudgetIsBoundedAndReported) {
  cv::Mat img(240, 320, CV_8UC1, cv::Scalar(60));
  for (int i = 0; i < 9; ++i) {
    cv::circle(img, cv::Point(100 + 50 * i / 3, 110 + 8 * (i % 2)), 90 - 8 * i / 3, cv::Scalar(200), 2, cv::LINE_AA);
  }
  ellipsekit::ImageView view{img.data, img.cols, img.rows, static_cast<std::ptrdiff_t>(img.step[0])};
  ellipsekit::Detector d{ellipsekit::Options()};
  ellipsekit::DetectionResult r;
  ASSERT_TRUE(d.detect(view, &r).ok());
  EXPECT_GE(r.ellipses.size(), 4u);
  EXPECT_NE(r.caps_hit & ellipsekit::kCapRimSearch, 0u) << r.ellipses.size() << " ellipses";
}

TEST(EdgeCoverage, IsTheShareOfTheOutlineWithNormalEdges) {
  EdgeFrame full, part, tangential;
  full.Ring(Inner(), 1.0, 0, kTwoPi);
  part.Ring(Inner(), 1.0, 0, 0.5 * kTwoPi);
  tangential.Ring(Inner(), 1.0, 0, kTwoPi, std::numbers::pi / 2);
  EXPECT_GE(ellipsekit::EdgeCoverage(full.Input(), Inner()), 0.98);
  EXPECT_NEAR(ellipsekit::EdgeCoverage(part.Input(), Inner()), 0.5, 0.04);
  EXPECT_EQ(ellipsekit::EdgeCoverage(tangential.Input(), Inner()), 0.0);
  // With a minimum share it may stop early, but the decision is the same.
  EXPECT_GE(ellipsekit::EdgeCoverage(full.Input(), Inner(), 0.7), 0.98);
  EXPECT_LT(ellipsekit::EdgeCoverage(part.Input(), Inner(), 0.7), 0.7);
  EXPECT_GE(ellipsekit::EdgeCoverage(part.Input(), Inner(), 0.45), 0.45);
  Ellipse larger = Inner();  // 1.15x: 4-6 px off the ring, beyond the 3x3 neighbourhood
  larger.a *= 1.15;
  larger.b *= 1.15;
  EXPECT_EQ(ellipsekit::EdgeCoverage(full.Input(), larger), 0.0);
  Ellipse shifted = Inner();  // 3 px down: only the near-vertical parts of the ring stay in reach
  shifted.cy += 3;
  EXPECT_LE(ellipsekit::EdgeCoverage(full.Input(), shifted), 0.6);
  Ellipse outside = Inner();
  outside.cx = -1000;
  EXPECT_EQ(ellipsekit::EdgeCoverage(full.Input(), outside), 0.0);
}


// A ring covered over one half (split along the major axis) passes the half rule (rim_search.h)
// below min_coverage; the same 50 % as two opposite quarters does not.
// Inner()'s parametric angles [0, pi) are its lower (near) half in the image, [pi, 2 pi) its
// upper (far) half.
TEST(RimSearch, HalfBackedRingPassesBelowMinCoverage) {
  EdgeFrame half_ring, quarters, near_half;
  half_ring.Ring(Inner(), 1.2, 0.5 * kTwoPi, kTwoPi);
  half_ring.Ring(Inner(), 1.0, 0, kTwoPi);
  quarters.Ring(Inner(), 1.2, 0, 0.25 * kTwoPi);
  quarters.Ring(Inner(), 1.2, 0.5 * kTwoPi, 0.75 * kTwoPi);
  quarters.Ring(Inner(), 1.0, 0, kTwoPi);
  Ellipse out;
  long scanned = 0;
  ASSERT_TRUE(ellipsekit::FindOuterRim(half_ring.Input(), Inner(), 0.6, &out, &scanned));
  EXPECT_NEAR(out.a / Inner().a, 1.2, 0.02);
  EXPECT_FALSE(ellipsekit::FindOuterRim(quarters.Input(), Inner(), 0.6, &out, &scanned));
  EXPECT_TRUE(ellipsekit::FindOuterRim(quarters.Input(), Inner(), 0.45, &out, &scanned));
  // The near half alone is not a rim: its far half would stand against the background.
  near_half.Ring(Inner(), 1.2, 0, 0.5 * kTwoPi);
  near_half.Ring(Inner(), 1.0, 0, kTwoPi);
  EXPECT_FALSE(ellipsekit::FindOuterRim(near_half.Input(), Inner(), 0.45, &out, &scanned));
}

// A ledge below a top (a lidded jar's shoulder) backed along its near half and sides, 65 % of
// the angle, its far half hidden behind the top: rejected although 65 % passes min_coverage, as
// a rim is backed along its far half (kRimFarHalfMinCoverage). The same ring turned upside down
// is a rim; and with the minor axis horizontal the image says nothing of which half is far.
TEST(RimSearch, ALedgeBelowTheTopIsNotItsRim) {
  const double pi = std::numbers::pi;
  EdgeFrame ledge, rim;
  ledge.Ring(Inner(), 1.2, -0.15 * pi, 1.15 * pi);
  rim.Ring(Inner(), 1.2, 0.85 * pi, 2.15 * pi);
  Ellipse out;
  long scanned = 0;
  EXPECT_FALSE(ellipsekit::FindOuterRim(ledge.Input(), Inner(), 0.6, &out, &scanned));
  ASSERT_TRUE(ellipsekit::FindOuterRim(rim.Input(), Inner(), 0.6, &out, &scanned));
  EXPECT_NEAR(out.a / Inner().a, 1.2, 0.02);
  Ellipse upright = Inner();
  upright.theta += pi / 2;
  EdgeFrame side;
  side.Ring(upright, 1.2, -0.15 * pi, 1.15 * pi);
  EXPECT_TRUE(ellipsekit::FindOuterRim(side.Input(), upright, 0.6, &out, &scanned));
}

// RimContacts that marks the sectors whose middle lies in the parametric ranges [t0, t1) of
// `ranges` (rim_search.h numbers sectors by the angle of (-u, -v), that is t + pi).
class ContactsAt final : public ellipsekit::RimContacts {
 public:
  explicit ContactsAt(std::vector<std::pair<double, double>> ranges) : ranges_(std::move(ranges)) {}
  std::uint64_t Touching(const Ellipse&, double) const override {
    std::uint64_t mask = 0;
    for (int s = 0; s < 64; ++s) {
      const double t = std::fmod((s + 0.5) * std::numbers::pi / 32 + std::numbers::pi, kTwoPi);
      for (const auto& [t0, t1] : ranges_) {
        if (t >= t0 && t < t1) mask |= std::uint64_t{1} << s;
      }
    }
    return mask;
  }

 private:
  std::vector<std::pair<double, double>> ranges_;
};

// A rim backed over 55 % of its angle, its two gaps where neighbours touch it: accepted when the
// contacts explain the gaps, not without them, not when they explain only a sliver, and never
// when less than half of the rim is backed (rim_search.h, RimContacts).
TEST(RimSearch, ContactsExplainTheGapsOfATouchingRim) {
  EdgeFrame f;
  f.Ring(Inner(), 1.0, 0, kTwoPi);
  f.Ring(Inner(), 1.2, 0, 0.3 * kTwoPi);
  f.Ring(Inner(), 1.2, 0.5 * kTwoPi, 0.75 * kTwoPi);
  const ContactsAt gaps({{0.3 * kTwoPi, 0.5 * kTwoPi}, {0.75 * kTwoPi, kTwoPi}});
  const ContactsAt sliver({{0.3 * kTwoPi, 0.35 * kTwoPi}});
  Ellipse out;
  long scanned = 0;
  EXPECT_FALSE(ellipsekit::FindOuterRim(f.Input(), Inner(), 0.6, &out, &scanned));
  EXPECT_FALSE(ellipsekit::FindOuterRim(f.Input(), Inner(), 0.6, &out, &scanned, &sliver));
  ASSERT_TRUE(ellipsekit::FindOuterRim(f.Input(), Inner(), 0.6, &out, &scanned, &gaps));
  EXPECT_NEAR(out.a / Inner().a, 1.2, 0.02);
  EXPECT_NEAR(out.b / Inner().b, 1.2, 0.02);

  EdgeFrame thin;  // 40 % backed: below kRimHalfMinCoverage, whatever the contacts
  thin.Ring(Inner(), 1.0, 0, kTwoPi);
  thin.Ring(Inner(), 1.2, 0, 0.2 * kTwoPi);
  thin.Ring(Inner(), 1.2, 0.5 * kTwoPi, 0.7 * kTwoPi);
  const ContactsAt everywhere({{0, kTwoPi}});
  EXPECT_FALSE(ellipsekit::FindOuterRim(thin.Input(), Inner(), 0.6, &out, &scanned, &everywhere));
}

// A recessed lid's rim (fit/recessed_rim.h): wider along b than along a and centred higher than
// the lid's outline; found from the lid, close to where it was drawn. Not found when nothing is
// drawn there, nor when the only larger ellipse lies lower than the lid (no rim sits so).
// A search around a detection (recessed rim, top over a side) found `want` within 0.5 px, kept the
// detection's score, and reported a bounded, non-zero scan.
void ExpectSearchFound(const Ellipse& found, const Ellipse& want, double score, long scanned) {
  EXPECT_GT(scanned, 0);
  EXPECT_LE(scanned, 3L * kW * kH);
  EXPECT_NEAR(found.cx, want.cx, 0.5);
  EXPECT_NEAR(found.cy, want.cy, 0.5);
  EXPECT_NEAR(found.a, want.a, 0.5);
  EXPECT_NEAR(found.b, want.b, 0.5);
  EXPECT_EQ(found.score, score);
}

TEST(RecessedRim, FindsTheRimAboveARecessedLid) {
  Ellipse lid = Inner();
  lid.theta = 0.1;
  const double up_x = std::sin(lid.theta), up_y = -std::cos(lid.theta);  // minor axis, up in the image
  auto rim_at = [&](double shift_b) {
    Ellipse r = lid;
    r.cx += shift_b * lid.b * up_x;
    r.cy += shift_b * lid.b * up_y;
    r.a *= 1.15;
    r.b *= 1.3;
    return r;
  };
  ellipsekit::EdgeRefitScratch scratch;
  scratch.Reserve(kW, kH);
  Ellipse found;
  EdgeFrame f;
  f.Ring(lid, 1.0, 0, kTwoPi);
  const Ellipse rim = rim_at(0.2);
  f.Ring(rim, 1.0, 0, kTwoPi);
  long scanned = 0;
  ASSERT_TRUE(ellipsekit::FindRecessedRim(f.Input(), lid, &scratch, &found, &scanned));
  ExpectSearchFound(found, rim, lid.score, scanned);

  EdgeFrame alone;
  alone.Ring(lid, 1.0, 0, kTwoPi);
  EXPECT_FALSE(ellipsekit::FindRecessedRim(alone.Input(), lid, &scratch, &found, &scanned));

  EdgeFrame below;
  below.Ring(lid, 1.0, 0, kTwoPi);
  below.Ring(rim_at(-0.2), 1.0, 0, kTwoPi);
  EXPECT_FALSE(ellipsekit::FindRecessedRim(below.Input(), lid, &scratch, &found, &scanned));
}

// f with rings of opposite gradient drawn 3 px inside and outside e: e becomes one stripe of a
// pattern (the growth rings of a wooden top), which the searches inside a detection refuse.
EdgeFrame AmongStripes(EdgeFrame f, const Ellipse& e) {
  for (double d : {-3.0, 3.0}) {
    Ellipse ring = e;
    ring.a += d;
    ring.b += d;
    f.Ring(ring, 1.0, 0, kTwoPi, std::numbers::pi);
  }
  return f;
}

// A lid's top rim (backed all round, as Canny finds its weak near arc) and the lower edge of the
// lid's side, h px below its near arc; the detection is the fit through the rim's far arc and that
// lower edge (wider, as measured on jars). The top inside it is found; not without its near arc,
// not when the inner ellipse is a concentric ring (a cup's inner rim), not among stripes.
TEST(TopOverSide, FindsTheTopInsideAFitThroughItsSide) {
  Ellipse top = Inner();
  top.b = 14;
  top.theta = 0.08;
  const double h = 9;  // the lid's side, px
  Ellipse side_bottom = top;
  side_bottom.cx -= h * std::sin(top.theta);
  side_bottom.cy += h * std::cos(top.theta);
  Ellipse fit = top;
  fit.cx = 0.5 * (top.cx + side_bottom.cx);
  fit.cy = 0.5 * (top.cy + side_bottom.cy);
  fit.a *= 1.08;
  fit.b += h / 2;
  const double pi = std::numbers::pi;
  ellipsekit::EdgeRefitScratch scratch;
  scratch.Reserve(kW, kH);
  Ellipse found;
  long scanned = 0;

  EdgeFrame jar;
  jar.Ring(top, 1.0, 0, kTwoPi);
  jar.Ring(side_bottom, 1.0, 0, pi);  // the near half (y down: sin t > 0)
  ASSERT_TRUE(ellipsekit::FindTopOverSide(jar.Input(), fit, &scratch, &found, &scanned));
  ExpectSearchFound(found, top, fit.score, scanned);
  EXPECT_TRUE(ellipsekit::IsTopOverSide(found, fit));

  EdgeFrame no_near_arc;
  no_near_arc.Ring(top, 1.0, pi, kTwoPi);
  no_near_arc.Ring(side_bottom, 1.0, 0, pi);
  EXPECT_FALSE(ellipsekit::FindTopOverSide(no_near_arc.Input(), fit, &scratch, &found, &scanned));

  EdgeFrame cup;  // outer rim and a concentric inner one
  cup.Ring(fit, 1.0, 0, kTwoPi);
  cup.Ring(fit, 0.88, 0, kTwoPi);
  EXPECT_FALSE(ellipsekit::FindTopOverSide(cup.Input(), fit, &scratch, &found, &scanned));

  // The top among rings of opposite gradient 3 px inside and outside.
  EXPECT_FALSE(ellipsekit::FindTopOverSide(AmongStripes(jar, top).Input(), fit, &scratch, &found, &scanned));
}

// A jar's lid (backed all round) and the near half of the body's top outline below it, 1.2x the
// lid about the lid's far point; the detection is the fit through the lid's far arc and that
// outline (the outline itself). The lid inside it is found; not without the lid's near arc, not
// when the inner ellipse is a concentric ring (a cup's inner rim), not inside a nearly round
// detection, not among stripes.
TEST(LidInside, FindsTheLidInsideAFitThroughTheBodysOutline) {
  Ellipse lid = Inner();
  lid.b = 20;
  lid.theta = 0.08;
  const double up_x = std::sin(lid.theta), up_y = -std::cos(lid.theta);  // minor axis, up in the image
  Ellipse fit = lid;
  fit.a *= 1.2;
  fit.b *= 1.2;
  fit.cx -= 0.2 * lid.b * up_x;  // the far points meet
  fit.cy -= 0.2 * lid.b * up_y;
  const double pi = std::numbers::pi;
  ellipsekit::EdgeRefitScratch scratch;
  scratch.Reserve(kW, kH);
  Ellipse found;
  long scanned = 0;

  EdgeFrame jar;
  jar.Ring(lid, 1.0, 0, kTwoPi);
  jar.Ring(fit, 1.0, 0, pi);  // the near half (y down: sin t > 0)
  ASSERT_TRUE(ellipsekit::FindLidInside(jar.Input(), fit, &scratch, &found, &scanned));
  ExpectSearchFound(found, lid, fit.score, scanned);
  EXPECT_TRUE(ellipsekit::IsLidInside(found, fit));
  EXPECT_FALSE(ellipsekit::IsLidInside(fit, fit));
  Ellipse concentric = fit;  // the lid's size, but centred on the fit: its far point 0.17 b lower
  concentric.a = lid.a;
  concentric.b = lid.b;
  EXPECT_FALSE(ellipsekit::IsLidInside(concentric, fit));
  Ellipse flatter = lid;  // through the same far point, b scaled 0.07 less than a
  flatter.b -= 0.07 * fit.b;
  flatter.cx += 0.07 * fit.b * up_x;
  flatter.cy += 0.07 * fit.b * up_y;
  EXPECT_FALSE(ellipsekit::IsLidInside(flatter, fit));
  flatter.b += 0.04 * fit.b;  // 0.03 less: within the tolerance
  flatter.cx -= 0.04 * fit.b * up_x;
  flatter.cy -= 0.04 * fit.b * up_y;
  EXPECT_TRUE(ellipsekit::IsLidInside(flatter, fit));

  EdgeFrame no_near_arc;
  no_near_arc.Ring(lid, 1.0, pi, kTwoPi);
  no_near_arc.Ring(fit, 1.0, 0, pi);
  EXPECT_FALSE(ellipsekit::FindLidInside(no_near_arc.Input(), fit, &scratch, &found, &scanned));

  EdgeFrame cup;  // outer rim and a concentric inner one
  cup.Ring(fit, 1.0, 0, kTwoPi);
  cup.Ring(fit, 0.84, 0, kTwoPi);
  EXPECT_FALSE(ellipsekit::FindLidInside(cup.Input(), fit, &scratch, &found, &scanned));

  Ellipse round_fit = fit;  // the same drawing inside a nearly round detection: no way is up
  round_fit.b = 0.95 * round_fit.a;
  EXPECT_FALSE(ellipsekit::FindLidInside(jar.Input(), round_fit, &scratch, &found, &scanned));

  // The lid among rings of opposite gradient 3 px inside and outside.
  EXPECT_FALSE(ellipsekit::FindLidInside(AmongStripes(jar, lid).Input(), fit, &scratch, &found, &scanned));
}

// Claimed edges support nothing else: not the ellipse that claimed them, nor one a pixel off it;
// a ring elsewhere keeps its coverage, and Clear() gives every edge back.
TEST(EdgeCoverage, ClaimedEdgesAreLeftOut) {
  EdgeFrame f;
  Ellipse other = Inner();
  other.a = 12;
  other.b = 8;
  other.cx = 170;
  other.cy = 25;
  f.Ring(Inner(), 1.0, 0, kTwoPi);
  f.Ring(other, 1.0, 0, kTwoPi);
  ellipsekit::EdgeClaims claims;
  claims.Resize(kW, kH);
  ellipsekit::ClaimEdges(f.Input(), Inner(), &claims);
  EXPECT_FALSE(claims.claimed.empty());
  EXPECT_EQ(ellipsekit::EdgeCoverage(f.Input(), Inner(), 0, &claims), 0.0);
  Ellipse off = Inner();
  off.cx += 1;
  off.cy -= 0.7;
  EXPECT_GE(ellipsekit::EdgeCoverage(f.Input(), off), 0.9) << "backed by the ring when nothing is claimed";
  EXPECT_LE(ellipsekit::EdgeCoverage(f.Input(), off, 0, &claims), 0.05);
  EXPECT_GE(ellipsekit::EdgeCoverage(f.Input(), other, 0, &claims), 0.98);
  claims.Clear();
  EXPECT_TRUE(claims.claimed.empty());
  EXPECT_GE(ellipsekit::EdgeCoverage(f.Input(), Inner(), 0, &claims), 0.98);
}

// The fine coverage ranks the ellipse on the edges above one 1.5 px off (which the 3x3 coverage
// cannot tell apart), and stops early once it cannot beat a given share.
TEST(EdgeCoverage, FineCoverageRanksTheTighterFit) {
  EdgeFrame f;
  f.Ring(Inner(), 1.0, 0, kTwoPi);
  Ellipse off = Inner();
  off.a += 1.5;
  off.b += 1.5;
  const double on_ring = ellipsekit::FineEdgeCoverage(f.Input(), Inner());
  const double beside = ellipsekit::FineEdgeCoverage(f.Input(), off);
  EXPECT_GE(on_ring, 0.95);
  EXPECT_LT(beside, on_ring - 0.3);
  EXPECT_GE(ellipsekit::EdgeCoverage(f.Input(), off), 0.9) << "the 3x3 coverage backs both";
  EXPECT_LE(ellipsekit::FineEdgeCoverage(f.Input(), off, on_ring), on_ring);
  EXPECT_EQ(ellipsekit::FineEdgeCoverage(f.Input(), Inner(), 0.5), on_ring) << "a better one is counted in full";
}

// The band scans (ClaimEdges, EdgePointsNear): every pixel of a ring drawn along the ellipse is
// found once, nothing of a ring 1.2x larger, and far-off, huge or degenerate ellipses (infinite or
// NaN chord ends) find nothing and touch no pixel outside the frame.
TEST(EdgeCoverage, BandScansFindTheRingOnceAndAreSafeAnywhere) {
  EdgeFrame f;
  f.Ring(Inner(), 1.0, 0, kTwoPi);
  f.Ring(Inner(), 1.2, 0, kTwoPi);
  int on_ring = 0;
  EdgeFrame only;
  only.Ring(Inner(), 1.0, 0, kTwoPi);
  for (const std::uint8_t v : only.edges) on_ring += v != 0;
  std::vector<std::int32_t> xs, ys;
  xs.reserve(8 * (kW + kH));
  ys.reserve(8 * (kW + kH));
  EXPECT_EQ(ellipsekit::EdgePointsNear(f.Input(), Inner(), 1.5, &xs, &ys), on_ring);
  for (std::size_t i = 0; i < xs.size(); ++i) EXPECT_NE(only.edges[ys[i] * kW + xs[i]], 0) << "only the inner ring";
  ellipsekit::EdgeClaims claims;
  claims.Resize(kW, kH);
  ellipsekit::ClaimEdges(f.Input(), Inner(), &claims);
  EXPECT_EQ(static_cast<int>(claims.claimed.size()), on_ring);
  claims.Clear();
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  for (const double far : {1e12, -1e12, 1e300, inf, nan}) {
    for (int field = 0; field < 3; ++field) {
      Ellipse e = Inner();
      if (field == 0) e.cx = far;
      if (field == 1) e.a = std::abs(far);
      if (field == 2) e.b = 1e-300;  // a line: the band is its outer ellipse's chord
      ellipsekit::EdgePointsNear(f.Input(), e, 1.5, &xs, &ys);
      ellipsekit::ClaimEdges(f.Input(), e, &claims);
      for (std::size_t i = 0; i < xs.size(); ++i) {
        EXPECT_TRUE(xs[i] >= 0 && xs[i] < kW && ys[i] >= 0 && ys[i] < kH);
      }
      if (field == 0) EXPECT_TRUE(xs.empty() && claims.claimed.empty()) << far;
      claims.Clear();
    }
  }
}

// The refit to the edges (fit/edge_refit.h) moves an ellipse a pixel off a ring onto it, and leaves
// alone one too far off to be backed by that ring.
TEST(EdgeRefit, SnapsAnEllipseOntoItsRing) {
  EdgeFrame f;
  f.Ring(Inner(), 1.0, 0, kTwoPi);
  ellipsekit::EdgeRefitScratch scratch;
  scratch.Reserve(kW, kH);
  Ellipse off = Inner();
  off.cx += 0.8;
  off.cy -= 0.6;
  off.a += 0.7;
  ASSERT_TRUE(ellipsekit::RefitToEdges(f.Input(), &off, &scratch));
  EXPECT_NEAR(off.cx, Inner().cx, 0.25);
  EXPECT_NEAR(off.cy, Inner().cy, 0.25);
  EXPECT_NEAR(off.a, Inner().a, 0.3);
  EXPECT_NEAR(off.b, Inner().b, 0.3);
  EXPECT_NEAR(off.theta, Inner().theta, 0.02);
  EXPECT_EQ(off.score, Inner().score);
  Ellipse far = Inner();
  far.a *= 1.2;
  far.b *= 1.2;
  const Ellipse before = far;
  EXPECT_FALSE(ellipsekit::RefitToEdges(f.Input(), &far, &scratch));
  EXPECT_EQ(far.a, before.a);
  EXPECT_EQ(far.cx, before.cx);
}

}  // namespace

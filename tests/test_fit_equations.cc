// Analytic checks of the fit back end's equations (Dong et al. 2018, sec. II-C and II-D):
// centres (eqs. 3-7), parameters (eqs. 8-12), validation (eqs. 13-16), clustering (eq. 17),
// the least-squares refinement and the small helpers they rest on.
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "ellipsekit/options.h"
#include "ellipsekit/types.h"
#include "fit/arc.h"
#include "fit/center.h"
#include "fit/clustering.h"
#include "fit/conic_refine.h"
#include "fit/parameters.h"
#include "fit/point_moments.h"
#include "fit/recessed_rim.h"
#include "fit/validation.h"
#include "kernels/arc_types.h"
#include "tests/ellipse_test_util.h"

namespace ellipsekit {
namespace {

constexpr double kPi = std::numbers::pi;

using test::TrueEllipse;

Arc ArcOn(const TrueEllipse& e, double t0, double t1) {
  Arc arc;
  arc.p0 = e.Point(t0);
  arc.p1 = e.Point(t1);
  arc.mid = e.Point(0.5 * (t0 + t1));
  arc.n0 = e.Normal(t0);
  arc.n1 = e.Normal(t1);
  return arc;
}

double AngleDiffModPi(double x, double y) {
  double d = std::fmod(std::abs(x - y), kPi);
  return std::min(d, kPi - d);
}

// Appends the rounded integer points of e over parameters [t0, t1] as one arc (one curve) of
// `curves`, with gradients 1000 * (normal at the rounded point + offset), and returns the Arc.
// offset_px moves each sample along its normal before rounding.
Arc AppendArc(const TrueEllipse& e, double t0, double t1, double offset_px, Curves* curves) {
  if (curves->offset.empty()) curves->offset.push_back(0);
  const int begin = static_cast<int>(curves->x.size());
  const double len = std::max(e.a, e.b) * std::abs(t1 - t0);
  const int steps = std::max(8, static_cast<int>(len * 4));
  int min_x = 1 << 30, min_y = 1 << 30, max_x = -(1 << 30), max_y = -(1 << 30);
  for (int i = 0; i <= steps; ++i) {
    const double t = t0 + (t1 - t0) * i / steps;
    const Eigen::Vector2d p = e.Point(t) + offset_px * e.Normal(t);
    const int x = static_cast<int>(std::lround(p.x())), y = static_cast<int>(std::lround(p.y()));
    if (static_cast<int>(curves->x.size()) > begin && curves->x.back() == x && curves->y.back() == y) continue;
    const Eigen::Vector2d n = e.NormalAt(Eigen::Vector2d(x, y));
    curves->x.push_back(x);
    curves->y.push_back(y);
    curves->gx.push_back(static_cast<std::int16_t>(std::lround(1000 * n.x())));
    curves->gy.push_back(static_cast<std::int16_t>(std::lround(1000 * n.y())));
    min_x = std::min(min_x, x); max_x = std::max(max_x, x);
    min_y = std::min(min_y, y); max_y = std::max(max_y, y);
  }
  curves->offset.push_back(static_cast<std::int32_t>(curves->x.size()));
  curves->sign_class.push_back(0);
  Arc arc;
  arc.begin = begin;
  arc.end = static_cast<int>(curves->x.size()) - 1;
  arc.p0 = {double(curves->x[arc.begin]), double(curves->y[arc.begin])};
  arc.p1 = {double(curves->x[arc.end]), double(curves->y[arc.end])};
  arc.n0 = e.Normal(t0);
  arc.n1 = e.Normal(t1);
  arc.min_x = min_x; arc.max_x = max_x; arc.min_y = min_y; arc.max_y = max_y;
  arc.width = max_x - min_x;
  arc.height = max_y - min_y;
  SetArcMoments(*curves, &arc);
  return arc;
}

const TrueEllipse kRotated{160.3, 121.7, 70.0, 42.0, 0.47};

// ---- (a) centres, eqs. 3-7

TEST(FitCenter, ChordCenterLinePassesThroughTheCentre) {
  const TrueEllipse& e = kRotated;
  const double ts[][2] = {{0.1, 0.9}, {1.0, 2.7}, {2.0, 4.0}, {3.3, 5.9}, {-0.6, 0.4}};
  for (const auto& t : ts) {
    Eigen::Vector3d line;
    ASSERT_TRUE(ChordCenterLine(e.Point(t[0]), e.Normal(t[0]), e.Point(t[1]), e.Normal(t[1]), &line));
    line /= line.head<2>().norm();  // any scale: normalised, the residual is a distance in px
    EXPECT_NEAR(line.dot(Eigen::Vector3d(e.cx, e.cy, 1.0)), 0.0, 1e-6) << t[0] << " " << t[1];
  }
}

TEST(FitCenter, ChordCenterLineOfADiameterIsDefined) {
  // End points antipodal: parallel tangents, pole at infinity; the line is the conjugate diameter.
  const TrueEllipse& e = kRotated;
  Eigen::Vector3d line;
  ASSERT_TRUE(ChordCenterLine(e.Point(0.8), e.Normal(0.8), e.Point(0.8 + kPi), e.Normal(0.8 + kPi), &line));
  line /= line.head<2>().norm();
  EXPECT_NEAR(line.dot(Eigen::Vector3d(e.cx, e.cy, 1.0)), 0.0, 1e-6);
  // The conjugate diameter is parallel to the tangent at the end points: its normal is e.Normal.
  const Eigen::Vector2d n = e.Normal(0.8);
  EXPECT_NEAR(std::abs(line.head<2>().dot(Eigen::Vector2d(-n.y(), n.x()))), 0.0, 1e-9);
}

TEST(FitCenter, IntersectLines) {
  Eigen::Vector2d p;
  // x = 3 and y = -2.
  ASSERT_TRUE(IntersectLines({1, 0, -3}, {0, 2, 4}, &p));
  EXPECT_NEAR(p.x(), 3.0, 1e-12);
  EXPECT_NEAR(p.y(), -2.0, 1e-12);
  // Parallel and near-parallel lines (under ~6 degrees) are refused.
  EXPECT_FALSE(IntersectLines({1, 0, -3}, {1, 0, 5}, &p));
  EXPECT_FALSE(IntersectLines({1, 0, -3}, {std::cos(0.05), std::sin(0.05), 5}, &p));
  EXPECT_TRUE(IntersectLines({1, 0, -3}, {std::cos(0.2), std::sin(0.2), 5}, &p));
}

TEST(FitCenter, PairCenterRecoversTheCentreWithBothMethods) {
  const TrueEllipse& e = kRotated;
  // Arcs from consecutive quarters of the parameter circle (as an arc pair is on an ellipse).
  const double groups[][4] = {{0.15, 1.4}, {1.7, 3.0}, {3.25, 4.5}, {4.8, 6.1}};
  for (CenterMethod method : {CenterMethod::kLongestChords, CenterMethod::kArcChords}) {
    for (int i = 0; i < 4; ++i) {
      const Arc a = ArcOn(e, groups[i][0], groups[i][1]);
      const Arc b = ArcOn(e, groups[(i + 1) % 4][0], groups[(i + 1) % 4][1]);
      Eigen::Vector2d c;
      ASSERT_TRUE(PairCenter(a, b, method, &c)) << "method " << int(method) << " pair " << i;
      EXPECT_NEAR(c.x(), e.cx, 1e-6) << "method " << int(method) << " pair " << i;
      EXPECT_NEAR(c.y(), e.cy, 1e-6) << "method " << int(method) << " pair " << i;
    }
  }
}

TEST(FitCenter, PairCenterOfACircleWithBothMethods) {
  const TrueEllipse e{50.25, -20.5, 33.0, 33.0, 0.0};
  for (CenterMethod method : {CenterMethod::kLongestChords, CenterMethod::kArcChords}) {
    Eigen::Vector2d c;
    ASSERT_TRUE(PairCenter(ArcOn(e, 0.2, 1.3), ArcOn(e, 1.9, 2.9), method, &c));
    EXPECT_NEAR(c.x(), e.cx, 1e-6);
    EXPECT_NEAR(c.y(), e.cy, 1e-6);
  }
}

TEST(FitCenter, TripletCenterOfExactArcsIsTheCentre) {
  const TrueEllipse& e = kRotated;
  const Arc a = ArcOn(e, 0.15, 1.4), b = ArcOn(e, 1.7, 3.0), c = ArcOn(e, 3.25, 4.5);
  for (CenterMethod method : {CenterMethod::kLongestChords, CenterMethod::kArcChords}) {
    Options o;
    o.center_method = method;
    Eigen::Vector2d cab, cbc;
    ASSERT_TRUE(PairCenter(a, b, method, &cab));
    ASSERT_TRUE(PairCenter(b, c, method, &cbc));
    bool capped = true;
    const Eigen::Vector2d t = TripletCenter(a, b, c, cab, cbc, o, &capped);
    EXPECT_FALSE(capped);
    EXPECT_NEAR(t.x(), e.cx, 1e-6);
    EXPECT_NEAR(t.y(), e.cy, 1e-6);
  }
}

// ---- (b) parameters, eqs. 8-12

TEST(FitParameters, EstimateParametersRecoversNOrientationAndA) {
  const TrueEllipse cases[] = {
      {200.0, 150.0, 90.0, 50.0, 0.47},
      {180.4, 160.6, 80.0, 60.0, -1.1},
      {250.0, 200.0, 120.0, 40.0, 1.4},
      {140.0, 140.0, 60.0, 58.0, 0.2},  // near-circle: orientation meaningless
  };
  for (const TrueEllipse& e : cases) {
    Curves curves;
    curves.clear();
    // Three arcs well inside three quarters of the parameter circle.
    const Arc a0 = AppendArc(e, 0.2, 1.35, 0.0, &curves);
    const Arc a1 = AppendArc(e, 1.8, 2.95, 0.0, &curves);
    const Arc a2 = AppendArc(e, 3.35, 4.5, 0.0, &curves);
    const Arc* arcs[3] = {&a0, &a1, &a2};
    ParameterScratch scratch;
    Ellipse out;
    ASSERT_TRUE(EstimateParameters(curves, arcs, 3, Eigen::Vector2d(e.cx, e.cy), &scratch, &out));
    EXPECT_EQ(out.cx, e.cx);
    EXPECT_EQ(out.cy, e.cy);
    EXPECT_NEAR(out.b / out.a, e.b / e.a, 0.03) << "N";
    if (e.a / e.b > 1.1) EXPECT_LT(AngleDiffModPi(out.theta, e.theta), 2.5 * kPi / 180) << "theta " << out.theta;
    EXPECT_NEAR(out.a, e.a, 0.015 * e.a) << "A";
    EXPECT_NEAR(out.b, e.b, 0.03 * e.b) << "B";
    EXPECT_GE(out.a, out.b);
    EXPECT_GE(out.theta, -kPi / 2);
    EXPECT_LT(out.theta, kPi / 2);
  }
}

TEST(FitParameters, EstimateParametersRefusesAGroupWithoutGradients) {
  const TrueEllipse e{200.0, 150.0, 90.0, 50.0, 0.47};
  Curves curves;
  curves.clear();
  const Arc a0 = AppendArc(e, 0.2, 1.35, 0.0, &curves);
  const Arc a1 = AppendArc(e, 1.8, 2.95, 0.0, &curves);
  std::fill(curves.gx.begin(), curves.gx.end(), 0);
  std::fill(curves.gy.begin(), curves.gy.end(), 0);
  const Arc* arcs[2] = {&a0, &a1};
  ParameterScratch scratch;
  Ellipse out;
  out.a = -7;
  EXPECT_FALSE(EstimateParameters(curves, arcs, 2, Eigen::Vector2d(e.cx, e.cy), &scratch, &out));
}

// ---- (c) validation, eqs. 13-16

TEST(FitValidation, LengthRatioOfThreeQuadrantArcsOfACircleIsOne) {
  const TrueEllipse e{100.0, 100.0, 40.0, 40.0, 0.0};
  Curves curves;
  curves.clear();
  const Arc a0 = AppendArc(e, 0.0, kPi / 2, 0.0, &curves);
  const Arc a1 = AppendArc(e, kPi / 2, kPi, 0.0, &curves);
  const Arc a2 = AppendArc(e, kPi, 1.5 * kPi, 0.0, &curves);
  EXPECT_EQ(a0.width, 40);
  EXPECT_EQ(a0.height, 40);
  const Arc* arcs[3] = {&a0, &a1, &a2};
  EXPECT_NEAR(LengthRatio(arcs, 3, e.AsEllipse()), 1.0, 1e-12);
  // Half-length arcs give about half: (m + n) of an eighth of a circle is r (1 - 1/sqrt 2 + 1/sqrt 2) = r.
  Curves c2;
  c2.clear();
  const Arc h0 = AppendArc(e, 0.0, kPi / 4, 0.0, &c2);
  const Arc h1 = AppendArc(e, kPi / 2, 3 * kPi / 4, 0.0, &c2);
  const Arc* halves[2] = {&h0, &h1};
  EXPECT_NEAR(LengthRatio(halves, 2, e.AsEllipse()), 0.5, 0.03);
}

TEST(FitValidation, CircumferenceRatioInliersAndOutliers) {
  const TrueEllipse& e = kRotated;
  Curves on, off;
  on.clear();
  off.clear();
  const Arc o0 = AppendArc(e, 0.2, 1.4, 0.0, &on), o1 = AppendArc(e, 1.8, 3.0, 0.0, &on),
            o2 = AppendArc(e, 3.3, 4.5, 0.0, &on);
  const Arc f0 = AppendArc(e, 0.2, 1.4, 3.0, &off), f1 = AppendArc(e, 1.8, 3.0, -3.0, &off),
            f2 = AppendArc(e, 3.3, 4.5, 3.0, &off);
  const Arc* on_arcs[3] = {&o0, &o1, &o2};
  const Arc* off_arcs[3] = {&f0, &f1, &f2};
  EXPECT_DOUBLE_EQ(CircumferenceRatio(on, on_arcs, 3, e.AsEllipse(), InlierRule::kPixel, 1.0), 1.0);
  EXPECT_LT(CircumferenceRatio(off, off_arcs, 3, e.AsEllipse(), InlierRule::kPixel, 1.0), 0.02);
  // A 4 px threshold accepts the 3 px offsets.
  EXPECT_GT(CircumferenceRatio(off, off_arcs, 3, e.AsEllipse(), InlierRule::kPixel, 4.0), 0.98);
  // Points on the ellipse are inliers under the algebraic rule too.
  EXPECT_DOUBLE_EQ(CircumferenceRatio(on, on_arcs, 3, e.AsEllipse(), InlierRule::kAlgebraic, 0.1), 1.0);
  // One arc of three off: psi is the share of inlier points.
  Curves mixed;
  mixed.clear();
  const Arc m0 = AppendArc(e, 0.2, 1.4, 0.0, &mixed), m1 = AppendArc(e, 1.8, 3.0, 3.0, &mixed),
            m2 = AppendArc(e, 3.3, 4.5, 0.0, &mixed);
  const Arc* mixed_arcs[3] = {&m0, &m1, &m2};
  const double share = double(m0.points() + m2.points()) / (m0.points() + m1.points() + m2.points());
  const double full = CircumferenceRatio(mixed, mixed_arcs, 3, e.AsEllipse(), InlierRule::kPixel, 1.0);
  EXPECT_NEAR(full, share, 0.02);
  // A minimum it reaches: the full value. One it cannot reach: it may stop early (after the second
  // arc here) but returns a value that still fails "psi > minimum".
  EXPECT_EQ(CircumferenceRatio(mixed, mixed_arcs, 3, e.AsEllipse(), InlierRule::kPixel, 1.0, full - 0.05), full);
  const double stopped = CircumferenceRatio(mixed, mixed_arcs, 3, e.AsEllipse(), InlierRule::kPixel, 1.0, 0.9);
  EXPECT_LE(stopped, 0.9);
  EXPECT_GE(stopped, full);
}

// ---- (d) feature distance and clustering, eq. 17

Ellipse Make(double cx, double cy, double a, double b, double theta, double score = 0) {
  Ellipse e;
  e.cx = cx; e.cy = cy; e.a = a; e.b = b; e.theta = theta; e.score = score;
  return e;
}

TEST(FitClustering, FeatureDistanceOnKnownPairs) {
  EXPECT_DOUBLE_EQ(FeatureDistance(Make(10, 20, 30, 20, 0.3), Make(13, 24, 30, 20, 0.3)), 5.0);
  EXPECT_DOUBLE_EQ(FeatureDistance(Make(0, 0, 30, 20, 0.3), Make(0, 0, 33, 24, 0.3)), 5.0);
  EXPECT_DOUBLE_EQ(FeatureDistance(Make(0, 0, 30, 20, 0.3), Make(0, 0, 30, 20, 0.3)), 0.0);
  // Theta wraps modulo pi: 1.5 and -1.5 are pi - 3 apart, not 3.
  EXPECT_NEAR(FeatureDistance(Make(0, 0, 30, 20, 1.5), Make(0, 0, 30, 20, -1.5)), kPi - 3.0, 1e-12);
  EXPECT_NEAR(FeatureDistance(Make(0, 0, 30, 20, 0.1), Make(0, 0, 30, 20, 0.1 + kPi)), 0.0, 1e-12);
  EXPECT_NEAR(FeatureDistance(Make(0, 0, 30, 20, 0.0), Make(0, 0, 30, 20, 0.5)), 0.5, 1e-12);
  // Symmetric.
  const Ellipse v = Make(1, 2, 40, 10, -1.2), w = Make(7, -3, 35, 12, 1.3);
  EXPECT_DOUBLE_EQ(FeatureDistance(v, w), FeatureDistance(w, v));
}

TEST(FitClustering, KeepsTheBestOfNearDuplicatesAndFarApartOnes) {
  Options o;  // kFeatureDistance, T_s = 25
  std::vector<Candidate> c(4);
  c[0].ellipse = Make(100, 100, 40, 30, 0.0, 1.5);
  c[1].ellipse = Make(102, 101, 41, 30, 0.05, 1.8);  // best of the duplicates
  c[2].ellipse = Make(400, 300, 40, 30, 0.0, 1.2);   // far away
  c[3].ellipse = Make(99, 98, 39, 31, -0.02, 1.6);
  const int kept = ClusterCandidates(&c, o);
  ASSERT_EQ(kept, 2);
  EXPECT_DOUBLE_EQ(c[0].ellipse.score, 1.8);
  EXPECT_DOUBLE_EQ(c[0].ellipse.cx, 102);
  EXPECT_DOUBLE_EQ(c[1].ellipse.score, 1.2);
  EXPECT_DOUBLE_EQ(c[1].ellipse.cx, 400);

  // Just past T_s stays apart, just under merges.
  std::vector<Candidate> d(2);
  d[0].ellipse = Make(0, 0, 40, 30, 0.0, 2.0);
  d[1].ellipse = Make(25.5, 0, 40, 30, 0.0, 1.0);
  EXPECT_EQ(ClusterCandidates(&d, o), 2);
  d[1].ellipse = Make(24.5, 0, 40, 30, 0.0, 1.0);
  EXPECT_EQ(ClusterCandidates(&d, o), 1);
}

// A check (the detector's edge coverage) leaves failing candidates out exactly as if they had
// been removed first: here the best duplicate fails, so the next best represents its cluster, and
// a failing outer rim does not replace its lip.
TEST(FitClustering, CheckLeavesFailingCandidatesOut) {
  struct RejectScore final : CandidateCheck {
    double bad;
    bool Passes(const Candidate& c) const override { return c.ellipse.score != bad; }
    double FitShare(const Candidate&, double) const override { return 0; }  // never picks a member
  };
  Options o;
  const std::vector<Candidate> all = [] {
    std::vector<Candidate> c(4);
    c[0].ellipse = Make(100, 100, 40, 30, 0.0, 1.5);
    c[1].ellipse = Make(102, 101, 41, 30, 0.05, 1.8);
    c[2].ellipse = Make(400, 300, 40, 30, 0.0, 1.2);
    c[3].ellipse = Make(99, 98, 39, 31, -0.02, 1.6);
    return c;
  }();
  RejectScore reject;
  reject.bad = 1.8;
  std::vector<Candidate> lazy = all, removed;
  for (const Candidate& x : all) if (x.ellipse.score != reject.bad) removed.push_back(x);
  const int kept_lazy = ClusterCandidates(&lazy, o, &reject);
  ASSERT_EQ(kept_lazy, ClusterCandidates(&removed, o));
  ASSERT_EQ(kept_lazy, 2);
  for (int k = 0; k < kept_lazy; ++k) EXPECT_EQ(lazy[k].ellipse.score, removed[k].ellipse.score);
  EXPECT_DOUBLE_EQ(lazy[0].ellipse.score, 1.6);

  std::vector<Candidate> top(2);
  top[0].ellipse = Make(200, 150, 40, 25, 0.3, 1.9);           // lip
  top[1].ellipse = Make(200.5, 150.5, 46, 28.75, 0.32, 1.7);   // its outer rim
  reject.bad = 1.7;
  ASSERT_EQ(ClusterCandidates(&top, o, &reject), 1);
  EXPECT_DOUBLE_EQ(top[0].ellipse.a, 40);
}

// The second chance (CandidateCheck::PassesRefitted, Options::rescue_min_coverage): after every
// candidate that passed as it was has founded or joined its cluster, each failed would-be founder
// that no cluster holds is refitted; a refit that passes founds a cluster of its own, behind the
// others whatever its score. One that a cluster holds is never refitted, so it cannot take the
// place of the candidate that passed there.
TEST(FitClustering, ASecondChanceFoundsItsClusterAfterTheOthers) {
  struct RefitMovesRight final : CandidateCheck {
    mutable std::vector<double> refitted;  // scores of the candidates given a second chance
    bool Passes(const Candidate& c) const override { return c.ellipse.score == 1.5; }
    double FitShare(const Candidate&, double) const override { return 0; }
    bool PassesRefitted(Candidate* c) const override {
      refitted.push_back(c->ellipse.score);
      if (c->ellipse.score == 1.4) return false;  // its refit fails too
      c->ellipse.cx += 2;
      return true;
    }
  };
  Options o;
  std::vector<Candidate> c(4);
  c[0].ellipse = Make(300, 200, 40, 30, 0.0, 1.9);  // fails, alone: rescued
  c[1].ellipse = Make(100, 100, 40, 30, 0.0, 1.7);  // fails, the same ellipse as the next
  c[2].ellipse = Make(101, 100, 40, 30, 0.0, 1.5);  // passes
  c[3].ellipse = Make(500, 400, 40, 30, 0.0, 1.4);  // fails, and so does its refit
  RefitMovesRight check;
  ClusterScratch scratch;
  for (int run = 0; run < 2; ++run) {  // the scratch's list of failed candidates starts empty each time
    std::vector<Candidate> d = c;
    check.refitted.clear();
    ASSERT_EQ(ClusterCandidates(&d, o, &check, &scratch), 2);
    EXPECT_DOUBLE_EQ(d[0].ellipse.score, 1.5);
    EXPECT_FALSE(d[0].rescued);
    EXPECT_DOUBLE_EQ(d[1].ellipse.score, 1.9);
    EXPECT_DOUBLE_EQ(d[1].ellipse.cx, 302);
    EXPECT_TRUE(d[1].rescued);
    EXPECT_EQ(check.refitted, (std::vector<double>{1.9, 1.4}));
  }
  // Without a check nothing fails, and nothing is rescued.
  std::vector<Candidate> d = c;
  ASSERT_EQ(ClusterCandidates(&d, o), 3);
  for (int k = 0; k < 3; ++k) EXPECT_FALSE(d[k].rescued);
}

// Options::cluster_pick_best_fit: the member with the best FitShare represents its cluster with
// the reference's score; rims of the reference are never that member, and only the best-scoring
// members are tried (fit/clustering.cc kFitTries, 6).
TEST(FitClustering, BestFittingMemberRepresentsItsCluster) {
  struct PreferB final : CandidateCheck {
    bool Passes(const Candidate&) const override { return true; }
    double FitShare(const Candidate& c, double) const override { return c.ellipse.b == 33 ? 0.9 : c.ellipse.b == 35 ? 1.0 : 0.5; }
  };
  const PreferB check;
  Options o;
  std::vector<Candidate> c(3);
  c[0].ellipse = Make(100, 100, 40, 30, 0.0, 2.0);   // reference: best score
  c[1].ellipse = Make(101, 103, 40, 33, 0.0, 1.9);   // the edges back this one best
  c[2].ellipse = Make(400, 300, 40, 30, 0.0, 1.2);
  std::vector<Candidate> picked = c;
  ASSERT_EQ(ClusterCandidates(&picked, o, &check), 2);
  EXPECT_DOUBLE_EQ(picked[0].ellipse.b, 33);
  EXPECT_DOUBLE_EQ(picked[0].ellipse.cy, 103);
  EXPECT_DOUBLE_EQ(picked[0].ellipse.score, 2.0) << "the cluster keeps its best score";
  o.cluster_pick_best_fit = false;
  std::vector<Candidate> by_score = c;
  ASSERT_EQ(ClusterCandidates(&by_score, o, &check), 2);
  EXPECT_DOUBLE_EQ(by_score[0].ellipse.b, 30);
  o.cluster_pick_best_fit = true;

  // An outer rim of the reference (1.15x, too weak a score to be chosen as its rim) fits best,
  // but is another ellipse: not the representative.
  std::vector<Candidate> rim(2);
  rim[0].ellipse = Make(200, 150, 40, 30, 0.3, 1.9);
  rim[1].ellipse = Make(200.5, 150.5, 46, 34.5, 0.3, 1.0);
  struct PreferLarger final : CandidateCheck {
    bool Passes(const Candidate&) const override { return true; }
    double FitShare(const Candidate& c, double) const override { return c.ellipse.a > 45 ? 1.0 : 0.5; }
  };
  const PreferLarger larger;
  ASSERT_EQ(ClusterCandidates(&rim, o, &larger), 1);
  EXPECT_DOUBLE_EQ(rim[0].ellipse.a, 40);

  // Eight members behind the reference, the best fit (b == 35) last by score: not tried.
  std::vector<Candidate> many(9);
  for (int i = 0; i < 9; ++i) many[i].ellipse = Make(100 + 0.5 * i, 100, 40, i == 8 ? 35 : 30 + 0.1 * i, 0.0, 2.0 - 0.05 * i);
  ASSERT_EQ(ClusterCandidates(&many, o, &check), 1);
  EXPECT_LT(many[0].ellipse.b, 35);
  for (int i = 0; i < 9; ++i) many[i].ellipse = Make(100 + 0.5 * i, 100, 40, i == 8 ? 35 : 30 + 0.1 * i, 0.0, i == 8 ? 1.97 : 2.0 - 0.05 * i);
  ASSERT_EQ(ClusterCandidates(&many, o, &check), 1);
  EXPECT_DOUBLE_EQ(many[0].ellipse.b, 35);
}

TEST(FitClustering, OuterRimRepresentsItsNestedLip) {
  // A can top: the lip (inner, best score) and the rim 1.15x larger, concentric, same shape.
  const Ellipse lip = Make(200, 150, 40, 25, 0.3, 1.9);
  const Ellipse rim = Make(200.5, 150.5, 46, 28.75, 0.32, 1.7);
  EXPECT_TRUE(IsOuterRim(rim, lip));
  EXPECT_FALSE(IsOuterRim(lip, rim));                                     // smaller, not outer
  EXPECT_FALSE(IsOuterRim(Make(200, 150, 41, 25.6, 0.3), lip));           // 1.02x: same ellipse
  EXPECT_FALSE(IsOuterRim(Make(200, 150, 62, 39, 0.3), lip));             // 1.55x: another object
  EXPECT_FALSE(IsOuterRim(Make(200, 153, 46, 28.75, 0.3), lip));          // centre 0.12 b away
  EXPECT_FALSE(IsOuterRim(Make(200, 150, 46, 31.5, 0.3), lip));           // b/a 0.68 vs 0.625
  EXPECT_FALSE(IsOuterRim(Make(200, 150, 46, 28.75, 0.6), lip));          // turned 0.3 rad
  EXPECT_TRUE(IsOuterRim(Make(0, 0, 46, 44, 1.5), Make(0, 0, 40, 38, 0.0)));  // round: any theta

  Options o;  // T_s = 25 merges lip and rim into one cluster
  std::vector<Candidate> c(3);
  c[0].ellipse = rim;
  c[1].ellipse = lip;
  c[2].ellipse = Make(201, 150, 40.5, 25.2, 0.3, 1.8);  // a near-duplicate of the lip
  ASSERT_EQ(ClusterCandidates(&c, o), 1);
  EXPECT_DOUBLE_EQ(c[0].ellipse.a, rim.a);
  EXPECT_DOUBLE_EQ(c[0].ellipse.score, rim.score);  // the rim's own score is reported

  // Outside the margin the lip stays.
  o.cluster_outer_margin = 0.1;
  c.assign(2, Candidate{});
  c[0].ellipse = rim;
  c[1].ellipse = lip;
  ASSERT_EQ(ClusterCandidates(&c, o), 1);
  EXPECT_DOUBLE_EQ(c[0].ellipse.a, lip.a);
}

// Options::cluster_recessed_rims: a can seen at an angle, its recessed lid (best score, and the
// edges back it most tightly) and the rim around it, 1.17x along a, 1.25x along b, centred 0.15 b
// higher (fit/recessed_rim.h), in one cluster: the rim represents it.
TEST(FitClustering, RecessedRimRepresentsItsLid) {
  const Ellipse lid = Make(200, 150, 40, 25, 0.0, 2.0);
  const Ellipse rim = Make(200, 146.25, 46.8, 31.25, 0.0, 1.9);  // y down: 3.75 px is up
  EXPECT_TRUE(IsRecessedRimOf(rim, lid));
  EXPECT_FALSE(IsOuterRim(rim, lid));
  struct PreferLid final : CandidateCheck {
    bool Passes(const Candidate&) const override { return true; }
    double FitShare(const Candidate& c, double) const override { return c.ellipse.a == 40 ? 1.0 : 0.85; }
  };
  const PreferLid check;
  auto representative = [&](const std::vector<Ellipse>& members, const Options& o) {
    std::vector<Candidate> c(members.size());
    for (std::size_t i = 0; i < members.size(); ++i) c[i].ellipse = members[i];
    EXPECT_EQ(ClusterCandidates(&c, o, &check), 1);
    return c[0].ellipse;
  };
  Options o;
  EXPECT_DOUBLE_EQ(representative({lid, rim}, o).a, rim.a);
  o.cluster_recessed_rims = false;
  EXPECT_DOUBLE_EQ(representative({lid, rim}, o).a, lid.a) << "without the rule the tighter fit wins";
  o.cluster_recessed_rims = true;

  // The same ellipse centred lower (a jar's shoulder below its lid), or around a nearly round lid
  // (seen from above: no way is up), is not a recessed rim.
  const Ellipse below = Make(200, 153.75, 46.8, 31.25, 0.0, 1.9);
  EXPECT_FALSE(IsRecessedRimOf(below, lid));
  EXPECT_DOUBLE_EQ(representative({lid, below}, o).a, lid.a);
  const Ellipse round_lid = Make(200, 150, 40, 37, 0.0, 2.0);
  const Ellipse round_rim = Make(200, 145.4, 46.8, 46, 0.0, 1.9);
  EXPECT_TRUE(IsRecessedRimOf(round_rim, round_lid));
  EXPECT_DOUBLE_EQ(representative({round_lid, round_rim}, o).a, round_lid.a);

  // A concentric outer rim, though it scores lower than the recessed one, takes precedence.
  const Ellipse concentric = Make(200, 150, 46, 28.75, 0.0, 1.8);
  ASSERT_TRUE(IsOuterRim(concentric, lid));
  EXPECT_DOUBLE_EQ(representative({lid, rim, concentric}, o).a, concentric.a);
}

// A lidded jar seen at an angle: its lid (best score) and the shoulder around it, 1.2x larger and
// centred 0.2 b lower, which fits the edges more tightly (a strong edge against the body). The
// shoulder is a ledge below the lid, never its representative; the same member centred level
// with the lid (a tighter fit of the lid's own outline) still is.
TEST(FitClustering, ALedgeBelowTheTopIsNotItsBestFit) {
  const Ellipse lid = Make(200, 150, 40, 25, 0.0, 2.0);
  const Ellipse shoulder = Make(200, 155, 48, 30, 0.0, 1.9);  // y down: 5 px is lower
  const Ellipse level = Make(200, 150, 41.5, 26, 0.0, 1.9);
  EXPECT_TRUE(IsLedgeBelow(shoulder, lid));
  EXPECT_FALSE(IsLedgeBelow(lid, shoulder));                              // smaller
  EXPECT_FALSE(IsLedgeBelow(Make(200, 145, 48, 30, 0.0), lid));          // higher: a rim
  EXPECT_FALSE(IsLedgeBelow(Make(200, 151.5, 48, 30, 0.0), lid));        // 0.06 b lower
  EXPECT_FALSE(IsLedgeBelow(Make(200, 155, 42, 27, 0.0), lid));          // 1.06x: the same top
  EXPECT_FALSE(IsLedgeBelow(Make(200, 155, 48, 47, 0.0), Make(200, 150, 40, 38, 0.0)));  // round
  EXPECT_FALSE(IsLedgeBelow(Make(200, 151.6, 9.6, 7.2, 0.0), Make(200, 150, 8, 6, 0.0)));  // b 6 px
  struct PreferLarger final : CandidateCheck {
    bool Passes(const Candidate&) const override { return true; }
    double FitShare(const Candidate& c, double) const override { return c.ellipse.a > 40 ? 1.0 : 0.8; }
  };
  const PreferLarger check;
  auto representative = [&](const std::vector<Ellipse>& members) {
    std::vector<Candidate> c(members.size());
    for (std::size_t i = 0; i < members.size(); ++i) c[i].ellipse = members[i];
    EXPECT_EQ(ClusterCandidates(&c, Options{}, &check), 1);
    return c[0].ellipse;
  };
  EXPECT_DOUBLE_EQ(representative({lid, shoulder}).a, lid.a);
  EXPECT_DOUBLE_EQ(representative({lid, level}).a, level.a);
}

TEST(FitClustering, RelativeRule) {
  Options o;
  o.cluster_rule = ClusterRule::kRelative;
  o.cluster_relative = 0.1;
  // Small differences in every parameter (within 10 %): the same ellipse.
  EXPECT_TRUE(SameEllipse(Make(0, 0, 40, 30, 0.2), Make(1, 1, 42, 31, 0.25), o));
  EXPECT_FALSE(SameEllipse(Make(0, 0, 40, 30, 0.2), Make(5, 0, 40, 30, 0.2), o));   // 5 > 0.1 * 30
  EXPECT_FALSE(SameEllipse(Make(0, 0, 40, 30, 0.2), Make(0, 0, 40, 30, 0.5), o));   // angle
  EXPECT_TRUE(SameEllipse(Make(0, 0, 40, 38, 0.2), Make(0, 0, 40, 38, 1.4), o));    // near-circles
  EXPECT_FALSE(SameEllipse(Make(0, 0, 40, 30, 0.2), Make(0, 0, 48, 30, 0.2), o));   // a off by 8 > 4.8
}

// ---- (e) conic conversion and least-squares refinement

void ConicOf(const TrueEllipse& e, double scale, double k[6]) {
  const double c = std::cos(e.theta), s = std::sin(e.theta);
  const double ia = 1 / (e.a * e.a), ib = 1 / (e.b * e.b);
  const double A = c * c * ia + s * s * ib, B = 2 * c * s * (ia - ib), C = s * s * ia + c * c * ib;
  const double D = -2 * A * e.cx - B * e.cy, E = -2 * C * e.cy - B * e.cx;
  const double F = A * e.cx * e.cx + B * e.cx * e.cy + C * e.cy * e.cy - 1;
  const double v[6] = {A, B, C, D, E, F};
  for (int i = 0; i < 6; ++i) k[i] = scale * v[i];
}

TEST(FitRefine, ConicToEllipseRecoversKnownEllipses) {
  const TrueEllipse cases[] = {kRotated, {10, -5, 30, 10, -1.2}, {0, 0, 5, 4, 1.5}, {300, 200, 100, 20, -kPi / 2}};
  for (const TrueEllipse& e : cases) {
    for (double scale : {1.0, -3.5, 1e4}) {
      double k[6];
      ConicOf(e, scale, k);
      Ellipse out;
      ASSERT_TRUE(ConicToEllipse(k, &out));
      EXPECT_NEAR(out.cx, e.cx, 1e-6);
      EXPECT_NEAR(out.cy, e.cy, 1e-6);
      EXPECT_NEAR(out.a, e.a, 1e-6);
      EXPECT_NEAR(out.b, e.b, 1e-6);
      EXPECT_NEAR(AngleDiffModPi(out.theta, e.theta), 0.0, 1e-6);
      EXPECT_GE(out.theta, -kPi / 2);
      EXPECT_LT(out.theta, kPi / 2);
    }
  }
  // A hyperbola (x^2 - y^2 = 1) and a parabola are not ellipses.
  const double hyperbola[6] = {1, 0, -1, 0, 0, -1};
  const double parabola[6] = {1, 0, 0, 0, -1, 0};
  const double imaginary[6] = {1, 0, 1, 0, 0, 1};  // x^2 + y^2 = -1
  Ellipse out;
  EXPECT_FALSE(ConicToEllipse(hyperbola, &out));
  EXPECT_FALSE(ConicToEllipse(parabola, &out));
  EXPECT_FALSE(ConicToEllipse(imaginary, &out));
}

TEST(FitRefine, ShiftedMomentsEqualMomentsTakenAboutTheNewOrigin) {
  std::vector<std::int32_t> x, y;
  std::srand(5);
  for (int i = 0; i < 200; ++i) { x.push_back(400 + std::rand() % 90); y.push_back(300 + std::rand() % 70); }
  const PointMoments direct = MomentsOfPoints(x.data(), y.data(), 0, 199, 0, 0);
  PointMoments shifted;  // about (0, 0), from two halves taken about their own origins
  AddShiftedMoments(MomentsOfPoints(x.data(), y.data(), 0, 99, 440, 330), &shifted);
  AddShiftedMoments(MomentsOfPoints(x.data(), y.data(), 100, 199, 451, 317), &shifted);
  for (int a = 0; a <= kMomentOrder; ++a) {
    for (int b = 0; a + b <= kMomentOrder; ++b) {
      EXPECT_NEAR(shifted.m[a][b], direct.m[a][b], 1e-12 * std::abs(direct.m[a][b])) << a << " " << b;
    }
  }
  EXPECT_EQ(direct.m[0][0], 200);
}

TEST(FitRefine, RefineEllipseRecoversARotatedEllipseFromRoundedPoints) {
  const TrueEllipse& e = kRotated;
  Curves curves;
  curves.clear();
  const Arc a0 = AppendArc(e, 0.1, 1.4, 0.0, &curves);
  const Arc a1 = AppendArc(e, 1.7, 3.0, 0.0, &curves);
  const Arc a2 = AppendArc(e, 3.3, 4.6, 0.0, &curves);
  const Arc* arcs[3] = {&a0, &a1, &a2};
  Ellipse out;
  ASSERT_TRUE(RefineEllipse(arcs, 3, &out));
  EXPECT_NEAR(out.cx, e.cx, 0.2);
  EXPECT_NEAR(out.cy, e.cy, 0.2);
  EXPECT_NEAR(out.a, e.a, 0.3);
  EXPECT_NEAR(out.b, e.b, 0.3);
  EXPECT_LT(AngleDiffModPi(out.theta, e.theta), 0.5 * kPi / 180);
}

TEST(FitRefine, RefineEllipseRefusesCollinearPoints) {
  Curves curves;
  curves.clear();
  for (int i = 0; i < 40; ++i) {
    curves.x.push_back(i);
    curves.y.push_back(2 * i);
    curves.gx.push_back(100);
    curves.gy.push_back(-50);
  }
  curves.offset.push_back(40);
  curves.sign_class.push_back(2);
  Arc a;
  a.begin = 0;
  a.end = 39;
  a.max_x = 39;
  a.max_y = 78;
  SetArcMoments(curves, &a);
  const Arc* arcs[1] = {&a};
  Ellipse out = Make(1, 2, 3, 4, 0.5);
  EXPECT_FALSE(RefineEllipse(arcs, 1, &out));
  EXPECT_EQ(out.cx, 1);  // left alone
  EXPECT_EQ(out.b, 4);
}

// ---- (f) helpers

TEST(FitHelpers, DensestWindowMeanOnALine) {
  std::vector<double> v = {9.0, 5.1, 1.0, 5.0, 5.2, 3.0};
  EXPECT_NEAR(DensestWindowMean(&v, 0.5, 0.0), 5.1, 1e-12);
  std::vector<double> single = {2.5};
  EXPECT_DOUBLE_EQ(DensestWindowMean(&single, 0.1, 0.0), 2.5);
  std::vector<double> none;
  EXPECT_DOUBLE_EQ(DensestWindowMean(&none, 0.1, 0.0), 0.0);
}

TEST(FitHelpers, DensestWindowMeanWrapsOnACircle) {
  // Four values around 0 == pi (two just below pi, two just above 0), one outlier at 1.5.
  std::vector<double> v = {0.01, 1.5, kPi - 0.02, 0.04, 0.03};
  const double m = DensestWindowMean(&v, 0.1, kPi);
  // Mean of -0.02, 0.01, 0.03, 0.04 = 0.015.
  EXPECT_NEAR(m, 0.015, 1e-12);
  // Cluster straddling the wrap but centred below pi.
  std::vector<double> w = {kPi - 0.05, kPi - 0.04, 0.01, 2.0, 2.5};
  EXPECT_NEAR(DensestWindowMean(&w, 0.1, kPi), kPi - 0.08 / 3, 1e-12);
  // Without a period the same values do not wrap: the densest window is the pair near pi.
  std::vector<double> x = {kPi - 0.05, kPi - 0.04, 0.01, 2.0, 2.5};
  EXPECT_NEAR(DensestWindowMean(&x, 0.1, 0.0), kPi - 0.045, 1e-12);
}

TEST(FitHelpers, NormalizeEllipse) {
  Ellipse e = Make(0, 0, 3, 5, 0.2);
  NormalizeEllipse(&e);
  EXPECT_EQ(e.a, 5);
  EXPECT_EQ(e.b, 3);
  EXPECT_NEAR(e.theta, 0.2 + kPi / 2 - kPi, 1e-12);
  for (double t : {-10.0, -kPi / 2, -1.0, 0.0, 1.0, kPi / 2, 2.0, kPi, 7.0, 100.0}) {
    Ellipse f = Make(0, 0, 8, 2, t);
    NormalizeEllipse(&f);
    EXPECT_GE(f.theta, -kPi / 2) << t;
    EXPECT_LT(f.theta, kPi / 2) << t;
    EXPECT_NEAR(AngleDiffModPi(f.theta, t), 0.0, 1e-9) << t;
    EXPECT_EQ(f.a, 8);
  }
  Ellipse g = Make(0, 0, 8, 2, kPi / 2);
  NormalizeEllipse(&g);
  EXPECT_NEAR(g.theta, -kPi / 2, 1e-12);
}

}  // namespace
}  // namespace ellipsekit

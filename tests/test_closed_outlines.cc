// FitClosedOutlines (fit/closed_outlines.h): pieces of an outline joined end to end give one
// ellipse close to the outline; an outline with a piece missing (open ends), a group wider than
// the bound, or too few points give none; two outlines give two.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "fit/closed_outlines.h"

namespace ellipsekit {
namespace {

// The 8-connected pixel chain along e (one point per rounded position, consecutive duplicates
// dropped), cut into `pieces` consecutive curves; piece `skip` (if >= 0) left out.
void AddOutline(const Ellipse& e, int pieces, int skip, Curves* c) {
  std::vector<std::int32_t> xs, ys;
  const double ct = std::cos(e.theta), st = std::sin(e.theta);
  for (int i = 0; i < 2000; ++i) {
    const double t = 2 * M_PI * i / 2000;
    const int x = static_cast<int>(std::lround(e.cx + e.a * std::cos(t) * ct - e.b * std::sin(t) * st));
    const int y = static_cast<int>(std::lround(e.cy + e.a * std::cos(t) * st + e.b * std::sin(t) * ct));
    if (!xs.empty() && xs.back() == x && ys.back() == y) continue;
    xs.push_back(x);
    ys.push_back(y);
  }
  if (xs.size() > 1 && xs.front() == xs.back() && ys.front() == ys.back()) {
    xs.pop_back();
    ys.pop_back();
  }
  const int n = static_cast<int>(xs.size());
  for (int p = 0; p < pieces; ++p) {
    if (p == skip) continue;
    for (int i = n * p / pieces; i < n * (p + 1) / pieces; ++i) {
      c->x.push_back(xs[i]);
      c->y.push_back(ys[i]);
      c->gx.push_back(0);
      c->gy.push_back(0);
    }
    c->sign_class.push_back(1);
    c->offset.push_back(static_cast<std::int32_t>(c->x.size()));
  }
}

Curves Empty() {
  Curves c;
  c.clear();
  return c;
}

TEST(ClosedOutlines, PiecesOfOneOutlineGiveItsEllipse) {
  const Ellipse truth{60.0, 45.0, 11.0, 7.0, 0.4};
  Curves c = Empty();
  AddOutline(truth, 4, -1, &c);
  ClosedOutlineScratch scratch;
  std::vector<Ellipse> fits;
  FitClosedOutlines(c, 80, &scratch, &fits);
  ASSERT_EQ(fits.size(), 1u);
  EXPECT_NEAR(fits[0].cx, truth.cx, 0.3);
  EXPECT_NEAR(fits[0].cy, truth.cy, 0.3);
  EXPECT_NEAR(fits[0].a, truth.a, 0.5);
  EXPECT_NEAR(fits[0].b, truth.b, 0.5);
  EXPECT_NEAR(fits[0].theta, truth.theta, 0.1);
}

TEST(ClosedOutlines, OpenTooWideOrTooSmallGroupsGiveNone) {
  ClosedOutlineScratch scratch;
  std::vector<Ellipse> fits;
  Curves open = Empty();
  AddOutline({60.0, 45.0, 11.0, 7.0, 0.4}, 4, 2, &open);  // a quarter missing: two ends join nothing
  FitClosedOutlines(open, 80, &scratch, &fits);
  EXPECT_TRUE(fits.empty());
  Curves wide = Empty();
  AddOutline({60.0, 45.0, 11.0, 7.0, 0.4}, 4, -1, &wide);
  FitClosedOutlines(wide, 15, &scratch, &fits);  // the outline is ~21 px wide
  EXPECT_TRUE(fits.empty());
  Curves tiny = Empty();
  AddOutline({60.0, 45.0, 2.0, 1.5, 0.0}, 2, -1, &tiny);  // fewer than kClosedMinPoints points
  FitClosedOutlines(tiny, 80, &scratch, &fits);
  EXPECT_TRUE(fits.empty());
  FitClosedOutlines(Empty(), 80, &scratch, &fits);
  EXPECT_TRUE(fits.empty());
}

TEST(ClosedOutlines, TwoOutlinesGiveTwoEllipses) {
  Curves c = Empty();
  AddOutline({30.0, 30.0, 9.0, 6.0, 0.0}, 4, -1, &c);
  AddOutline({90.0, 70.0, 8.0, 8.0, 0.0}, 2, -1, &c);
  ClosedOutlineScratch scratch;
  std::vector<Ellipse> fits;
  FitClosedOutlines(c, 80, &scratch, &fits);
  ASSERT_EQ(fits.size(), 2u);
  EXPECT_NEAR(fits[0].cx, 30.0, 0.3);
  EXPECT_NEAR(fits[1].cx, 90.0, 0.3);
  EXPECT_NEAR(fits[1].a, 8.0, 0.5);
  EXPECT_NEAR(fits[1].b, 8.0, 0.5);
}

}  // namespace
}  // namespace ellipsekit

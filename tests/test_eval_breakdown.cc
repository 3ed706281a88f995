// Recall by kind, size and visibility (tools/eval/breakdown.h) on hand-made truth, metadata and
// detections, against recalls computed by hand; the meta format and the --by list.
#include <cstdio>
#include <filesystem>

#include <gtest/gtest.h>

#include "tools/eval/breakdown.h"
#include "tools/eval/ellipse_io.h"
#include "tools/eval/metrics.h"

namespace ellipsekit::eval {
namespace {

Ellipse E(double cx, double cy, double a, double b) {
  Ellipse e;
  e.cx = cx;
  e.cy = cy;
  e.a = a;
  e.b = b;
  e.theta = 0.3;
  return e;
}

const GroupRecall& Find(const std::vector<GroupRecall>& groups, const std::string& name) {
  for (const GroupRecall& g : groups)
    if (g.group == name) return g;
  static const GroupRecall kNone{"(none)", -1, -1};
  return kNone;
}

TEST(EvalBreakdown, ParsesMeta) {
  std::vector<TruthMeta> m;
  ASSERT_TRUE(ParseTruthMeta("can 1.0000\n\n# comment\njar 0.25  # hidden\n", "m.txt", &m).ok());
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[0].kind, "can");
  EXPECT_EQ(m[1].kind, "jar");
  EXPECT_DOUBLE_EQ(m[1].visible_fraction, 0.25);
  EXPECT_EQ(ParseTruthMeta("can\n", "m.txt", &m).message(), "m.txt:1: expected 2 values (kind visible_fraction), got 1");
  EXPECT_NE(ParseTruthMeta("can 0.5\ncup 1.5\n", "m.txt", &m).message().find("m.txt:2:"), std::string::npos);
  EXPECT_FALSE(ParseTruthMeta("can x\n", "m.txt", &m).ok());
}

TEST(EvalBreakdown, ParsesGroupList) {
  std::vector<GroupBy> by;
  ASSERT_TRUE(ParseGroupBy("all", &by));
  EXPECT_EQ(by.size(), 3u);
  ASSERT_TRUE(ParseGroupBy("size,kind,size", &by));
  ASSERT_EQ(by.size(), 2u);
  EXPECT_EQ(by[0], GroupBy::kSize);
  EXPECT_EQ(by[1], GroupBy::kKind);
  EXPECT_FALSE(ParseGroupBy("colour", &by));
  EXPECT_FALSE(ParseGroupBy("kind,", &by));
  EXPECT_FALSE(ParseGroupBy("", &by));
  EXPECT_STREQ(SizeBin(14.99), "b<15");
  EXPECT_STREQ(SizeBin(15), "15<=b<30");
  EXPECT_STREQ(SizeBin(30), "b>=30");
  EXPECT_STREQ(VisibilityBin(0.5999), "vis<60%");
  EXPECT_STREQ(VisibilityBin(0.6), "vis>=60%");
}

// Image 1: four tops, two found (exact detections), one false detection far away.
// Image 2: one top found. By hand:
//   kind: can 2/2 (tops 0, 2), jar 0/1, wood 0/1, cup 1/1
//   size: b<15 {0: found, 3: missed, } = 1/2; 15<=b<30 {1: missed, image 2: found} = 1/2; b>=30 {2} = 1/1
//   visibility: <60 % {1, 3, image 2} = 1/3; >=60 % {0, 2} = 2/2
TEST(EvalBreakdown, RecallsByHand) {
  const std::vector<Ellipse> truth1 = {E(50, 50, 20, 10), E(150, 50, 30, 20), E(300, 200, 60, 40),
                                       E(50, 200, 14, 12)};
  const std::vector<TruthMeta> meta1 = {{"can", 1.0}, {"jar", 0.5}, {"can", 0.7}, {"wood", 0.3}};
  const std::vector<Ellipse> det1 = {truth1[2], E(500, 400, 20, 10), truth1[0]};
  const std::vector<Ellipse> truth2 = {E(100, 100, 40, 25)};
  const std::vector<TruthMeta> meta2 = {{"cup", 0.4}};
  RecallBreakdown b({GroupBy::kKind, GroupBy::kSize, GroupBy::kVisibility});
  EXPECT_TRUE(b.needs_meta());
  ASSERT_TRUE(b.Add(truth1, MatchEllipses(det1, truth1), meta1).ok());
  ASSERT_TRUE(b.Add(truth2, MatchEllipses(truth2, truth2), meta2).ok());

  const auto kinds = b.Groups(GroupBy::kKind);
  ASSERT_EQ(kinds.size(), 4u);
  EXPECT_EQ(kinds[0].group, "can");  // sorted by name
  EXPECT_DOUBLE_EQ(Find(kinds, "can").recall(), 1.0);
  EXPECT_EQ(Find(kinds, "can").truth, 2);
  EXPECT_DOUBLE_EQ(Find(kinds, "jar").recall(), 0.0);
  EXPECT_DOUBLE_EQ(Find(kinds, "wood").recall(), 0.0);
  EXPECT_DOUBLE_EQ(Find(kinds, "cup").recall(), 1.0);
  const auto sizes = b.Groups(GroupBy::kSize);
  EXPECT_DOUBLE_EQ(Find(sizes, "b<15").recall(), 0.5);
  EXPECT_DOUBLE_EQ(Find(sizes, "15<=b<30").recall(), 0.5);
  EXPECT_DOUBLE_EQ(Find(sizes, "b>=30").recall(), 1.0);
  const auto vis = b.Groups(GroupBy::kVisibility);
  EXPECT_EQ(Find(vis, "vis<60%").truth, 3);
  EXPECT_NEAR(Find(vis, "vis<60%").recall(), 1.0 / 3, 1e-12);
  EXPECT_DOUBLE_EQ(Find(vis, "vis>=60%").recall(), 1.0);
  const std::string text = b.Format();
  EXPECT_NE(text.find("recall by kind:\n  can        truth     2  found     2  recall 1.0000\n"), std::string::npos)
      << text;
  EXPECT_NE(text.find("recall by visibility:"), std::string::npos);
}

TEST(EvalBreakdown, SizeNeedsNoMetaOtherGroupsDo) {
  const std::vector<Ellipse> truth = {E(50, 50, 20, 10)};
  RecallBreakdown size_only({GroupBy::kSize});
  EXPECT_FALSE(size_only.needs_meta());
  ASSERT_TRUE(size_only.AddImage("/nonexistent", "x", truth, MatchEllipses({}, truth)).ok());
  EXPECT_EQ(Find(size_only.Groups(GroupBy::kSize), "b<15").truth, 1);

  RecallBreakdown kind({GroupBy::kKind});
  EXPECT_FALSE(kind.Add(truth, MatchEllipses({}, truth), {}).ok());  // one truth, no meta
  const Status st = kind.AddImage("/nonexistent", "x", truth, MatchEllipses({}, truth));
  EXPECT_NE(st.message().find("meta/x.txt"), std::string::npos) << st.message();

  const std::string dir = testing::TempDir() + "/breakdown_ds";
  std::filesystem::create_directories(dir + "/meta");
  ASSERT_TRUE(WriteFileAtomically(dir + "/meta/x.txt", "cardboard 0.9\n").ok());
  ASSERT_TRUE(kind.AddImage(dir, "x", truth, MatchEllipses(truth, truth)).ok());
  EXPECT_DOUBLE_EQ(Find(kind.Groups(GroupBy::kKind), "cardboard").recall(), 1.0);
  ASSERT_TRUE(WriteFileAtomically(dir + "/meta/x.txt", "cardboard 0.9\ncan 1\n").ok());
  EXPECT_NE(kind.AddImage(dir, "x", truth, MatchEllipses(truth, truth)).message().find("2 entries for 1"),
            std::string::npos);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ellipsekit::eval

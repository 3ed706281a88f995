// Recall per group of ground truth (issue 18): by kind, by size, by visibility.
//
// Per-top metadata sits beside the truth (written by `ellipsekit scenes --hard`,
// tools/scenes/tabletop_scenes.h):
//
//   DIR/meta/<stem>.txt   one "<kind> <visible fraction>" per ground-truth line of gt/<stem>.txt,
//                         in the same order; e.g. "jar 0.8472"
//
// kind: a word (can, cup, jar, wood, cardboard); visible fraction: the share of the top's rim
// inside the frame and not hidden by another object, 0..1. Blank lines and '#' comments are
// skipped, as in gt/ (ellipse_io.h), so the n-th entry belongs to the n-th ellipse.
//
// Groups: kind as written; size by the truth's semi-minor axis b (after eval --scale):
// "b<15" (b < 15 px), "15<=b<30", "b>=30"; visibility: "vis<60%" (fraction < 0.6), "vis>=60%".
// A truth is found when the matching (metrics.h: Jaccard > 0.8, one-to-one, maximum cardinality)
// pairs it with a detection; truth in a don't-care box is left out. Recall = found / truth
// (1 for an empty group, as metrics.h).
#pragma once

#include <array>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "ellipsekit/types.h"
#include "tools/eval/metrics.h"

namespace ellipsekit::eval {

struct TruthMeta {
  std::string kind;
  double visible_fraction = 1;
};

// Parses meta text; `name` is used in "<name>:<line>: <problem>" messages (a line needs exactly a
// kind and a number in [0, 1]).
Status ParseTruthMeta(std::string_view text, const std::string& name, std::vector<TruthMeta>* out);
Status ReadTruthMeta(const std::string& path, std::vector<TruthMeta>* out);
// DIR/meta/<stem>.txt
std::string TruthMetaPath(const std::string& dataset_root, const std::string& stem);

enum class GroupBy { kKind, kSize, kVisibility };
const char* GroupByName(GroupBy by);  // "kind", "size", "visibility"
// "kind", "size", "visibility", a comma-separated list of them, or "all"; false on anything else.
bool ParseGroupBy(const std::string& text, std::vector<GroupBy>* out);

const char* SizeBin(double semi_minor);
const char* VisibilityBin(double visible_fraction);

struct GroupRecall {
  std::string group;
  int truth = 0;
  int found = 0;
  double recall() const { return truth > 0 ? static_cast<double>(found) / truth : 1.0; }
};

class RecallBreakdown {
 public:
  explicit RecallBreakdown(std::vector<GroupBy> by) : by_(std::move(by)) {}

  // Whether kind or visibility is asked (so each image needs its meta file).
  bool needs_meta() const;
  // One image: its truth, the matching of the detections against it, and its meta (one entry per
  // truth; may be empty when !needs_meta()). Error when the counts differ.
  Status Add(const std::vector<Ellipse>& truth, const MatchResult& match, const std::vector<TruthMeta>& meta);
  // Reads DIR/meta/<stem>.txt when needs_meta(), then Add.
  Status AddImage(const std::string& dataset_root, const std::string& stem, const std::vector<Ellipse>& truth,
                  const MatchResult& match);

  // Kinds sorted by name, size bins small to large, visibility bins low to high (empty bins kept).
  std::vector<GroupRecall> Groups(GroupBy by) const;
  // "recall by <group>:" then one "  <group> truth N found M recall R" line per group, per asked grouping.
  std::string Format() const;

 private:
  std::vector<GroupBy> by_;
  std::map<std::string, GroupRecall> kind_;
  std::array<GroupRecall, 3> size_{GroupRecall{"b<15"}, GroupRecall{"15<=b<30"}, GroupRecall{"b>=30"}};
  std::array<GroupRecall, 2> visibility_{GroupRecall{"vis<60%"}, GroupRecall{"vis>=60%"}};
};

}  // namespace ellipsekit::eval

#include "tools/eval/breakdown.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "tools/eval/text_lines.h"

namespace ellipsekit::eval {

Status ParseTruthMeta(std::string_view text, const std::string& name, std::vector<TruthMeta>* out) {
  out->clear();
  return ForEachTextLine(text, [&](int line_number, const std::string& line) {
    std::istringstream in(line);
    std::vector<std::string> tokens;
    for (std::string t; in >> t;) tokens.push_back(t);
    if (tokens.empty()) return Status::Ok();
    if (tokens.size() != 2)
      return LineError(name, line_number, "expected 2 values (kind visible_fraction), got " + std::to_string(tokens.size()));
    char* next = nullptr;
    const double v = std::strtod(tokens[1].c_str(), &next);
    if (next == tokens[1].c_str() || *next != '\0' || !(v >= 0 && v <= 1))
      return LineError(name, line_number, "visible fraction must be a number in [0, 1], got '" + tokens[1] + "'");
    out->push_back({tokens[0], v});
    return Status::Ok();
  });
}

Status ReadTruthMeta(const std::string& path, std::vector<TruthMeta>* out) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return Status(StatusCode::kInvalidArgument, path + ": cannot open (meta/ is written by 'ellipsekit scenes --hard')");
  std::ostringstream s;
  s << f.rdbuf();
  return ParseTruthMeta(s.str(), path, out);
}

std::string TruthMetaPath(const std::string& dataset_root, const std::string& stem) {
  return (std::filesystem::path(dataset_root) / "meta" / (stem + ".txt")).string();
}

const char* GroupByName(GroupBy by) {
  switch (by) {
    case GroupBy::kKind: return "kind";
    case GroupBy::kSize: return "size";
    case GroupBy::kVisibility: return "visibility";
  }
  return "?";
}

bool ParseGroupBy(const std::string& text, std::vector<GroupBy>* out) {
  out->clear();
  if (text == "all") {
    *out = {GroupBy::kKind, GroupBy::kSize, GroupBy::kVisibility};
    return true;
  }
  std::size_t pos = 0;
  while (pos <= text.size()) {
    std::size_t end = text.find(',', pos);
    if (end == std::string::npos) end = text.size();
    const std::string word = text.substr(pos, end - pos);
    bool known = false;
    for (GroupBy g : {GroupBy::kKind, GroupBy::kSize, GroupBy::kVisibility}) {
      if (word == GroupByName(g)) {
        known = true;
        bool seen = false;
        for (GroupBy h : *out) seen |= h == g;
        if (!seen) out->push_back(g);
      }
    }
    if (!known) return false;
    pos = end + 1;
  }
  return !out->empty();
}

const char* SizeBin(double b) { return b < 15 ? "b<15" : (b < 30 ? "15<=b<30" : "b>=30"); }
const char* VisibilityBin(double f) { return f < 0.6 ? "vis<60%" : "vis>=60%"; }

bool RecallBreakdown::needs_meta() const {
  for (GroupBy g : by_)
    if (g != GroupBy::kSize) return true;
  return false;
}

Status RecallBreakdown::Add(const std::vector<Ellipse>& truth, const MatchResult& match,
                            const std::vector<TruthMeta>& meta) {
  if (needs_meta() && meta.size() != truth.size())
    return Status(StatusCode::kInvalidArgument, "meta has " + std::to_string(meta.size()) + " entries for " +
                                                    std::to_string(truth.size()) + " ground-truth ellipses");
  for (std::size_t i = 0; i < truth.size(); ++i) {
    if (i < match.truth_ignored.size() && match.truth_ignored[i]) continue;
    const int found = i < match.detection_of_truth.size() && match.detection_of_truth[i] >= 0 ? 1 : 0;
    auto count = [found](GroupRecall* g) {
      ++g->truth;
      g->found += found;
    };
    const double b = std::min(truth[i].a, truth[i].b);
    count(&size_[b < 15 ? 0 : (b < 30 ? 1 : 2)]);
    if (i < meta.size()) {
      GroupRecall& k = kind_[meta[i].kind];
      k.group = meta[i].kind;
      count(&k);
      count(&visibility_[meta[i].visible_fraction < 0.6 ? 0 : 1]);
    }
  }
  return Status::Ok();
}

Status RecallBreakdown::AddImage(const std::string& dataset_root, const std::string& stem,
                                 const std::vector<Ellipse>& truth, const MatchResult& match) {
  std::vector<TruthMeta> meta;
  if (needs_meta()) {
    const std::string path = TruthMetaPath(dataset_root, stem);
    if (Status st = ReadTruthMeta(path, &meta); !st.ok()) return st;
    if (meta.size() != truth.size())
      return Status(StatusCode::kInvalidArgument, path + ": " + std::to_string(meta.size()) + " entries for " +
                                                      std::to_string(truth.size()) + " ground-truth ellipses");
  }
  return Add(truth, match, meta);
}

std::vector<GroupRecall> RecallBreakdown::Groups(GroupBy by) const {
  switch (by) {
    case GroupBy::kKind: {
      std::vector<GroupRecall> out;
      for (const auto& [name, g] : kind_) out.push_back(g);
      return out;
    }
    case GroupBy::kSize: return {size_.begin(), size_.end()};
    case GroupBy::kVisibility: return {visibility_.begin(), visibility_.end()};
  }
  return {};
}

std::string RecallBreakdown::Format() const {
  std::string s;
  char buf[160];
  for (GroupBy by : by_) {
    s += std::string("recall by ") + GroupByName(by) + ":\n";
    for (const GroupRecall& g : Groups(by)) {
      std::snprintf(buf, sizeof buf, "  %-10s truth %5d  found %5d  recall %.4f\n", g.group.c_str(), g.truth, g.found,
                    g.recall());
      s += buf;
    }
  }
  return s;
}

}  // namespace ellipsekit::eval

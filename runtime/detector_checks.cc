// The back end's last checks on the kept clusters (runtime/detector.cc BackEndAt runs them after
// the clustering): outer-rim completion, with rim contacts between packed tops (fit/rim_search.h),
// exclusive edge support and the stripe test. Private to the library.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "fit/edge_coverage.h"
#include "fit/recessed_rim.h"
#include "fit/rim_search.h"
#include "fit/top_over_side.h"
#include "runtime/detector_impl.h"

namespace ellipsekit {

namespace {

// Built when the library loads: a function-local static would be built on the first frame that
// finds an outer rim, and registering its destructor (__cxa_atexit) can allocate then.
const Options kNearlySameRule = [] {
  Options o;
  o.cluster_rule = ClusterRule::kRelative;
  o.cluster_relative = 0.1;
  return o;
}();

bool NearlySame(const Ellipse& v, const Ellipse& w) { return SameEllipse(v, w, kNearlySameRule); }

// Whether candidates[i] lies inside another of candidates[0, kept): no larger than 0.95 of its a,
// centred within half its semi-axes (a ring of a wooden top's grain, a lid inside its rim).
bool NestedInAnother(const std::vector<Candidate>& candidates, int kept, int i) {
  const Ellipse& e = candidates[i].ellipse;
  for (int j = 0; j < kept; ++j) {
    const Ellipse& o = candidates[j].ellipse;
    if (j == i || !(e.a <= 0.95 * o.a) || !(std::abs(e.cx - o.cx) < o.a && std::abs(e.cy - o.cy) < o.a)) continue;
    const double c = std::cos(o.theta), s = std::sin(o.theta), dx = e.cx - o.cx, dy = e.cy - o.cy;
    const double u = (dx * c + dy * s) / o.a, v = (dy * c - dx * s) / o.b;
    if (u * u + v * v < 0.25) return true;
  }
  return false;
}

// px: a rim point within this of a neighbour's outer rim (either side) lies against it. Points
// deeper inside the neighbour's own ellipse mean the two overlap, which tops side by side on one
// plane never do in the image (a plate on a plate, a lid in front of another): with more than
// kMaxOverlapSectors of them no sector counts as touching. Measured (`ellipsekit eval`): no
// overlap test: edcircles_mini at 3x (`--scale 3`) loses a plate (0.711 -> 0.697); 0 / 4 / 16
// sectors: crowded cups (`--layout cups --count 12 --seed 5`) 0.958 / 0.959 / 0.960, crowded seed 1
// 0.9807 / 0.9813 / 0.9810 (0.9831 without the test), edcircles at 3x kept at each.
constexpr double kContactPx = 2;
constexpr int kMaxOverlapSectors = 4;

// RimContacts over the other kept ellipses: a neighbour's outer rim is its ellipse when it is a
// rim already, else somewhere between that ellipse and the ellipse scaled by the same k (packed
// objects are alike; a neighbour found at its outer edge has no rim flag). reach[j]: a box that
// holds every outer rim neighbour j can have, grown by kContactPx (a cheap first test).
class NeighbourContacts final : public RimContacts {
 public:
  NeighbourContacts(const std::vector<Candidate>& candidates, int kept, const std::vector<Box>& reach, int self)
      : c_(candidates), kept_(kept), reach_(reach), self_(self) {}

  std::uint64_t Touching(const Ellipse& inner, double k) const override {
    const double c = std::cos(inner.theta), s = std::sin(inner.theta);
    const double a = k * inner.a, b = k * inner.b;
    Ellipse rim = inner;
    rim.a = a;
    rim.b = b;
    const Box box = BoundingBox(rim, kContactPx);
    // The middle of each sector: (-u, -v) at angle (sector + 0.5) pi / 32.
    double px[64], py[64];
    for (int sector = 0; sector < 64; ++sector) {
      const double t = (sector + 0.5) * (std::numbers::pi / 32);
      const double u = -std::cos(t), v = -std::sin(t);
      px[sector] = inner.cx + a * u * c - b * v * s;
      py[sector] = inner.cy + a * u * s + b * v * c;
    }
    std::uint64_t touching = 0, overlapping = 0;
    for (int j = 0; j < kept_; ++j) {
      if (j == self_ || !reach_[j].Intersects(box)) continue;
      const Ellipse& o = c_[j].ellipse;
      // Centred inside this top (its other edges, a duplicate): the same object, not a neighbour.
      if (std::hypot(o.cx - inner.cx, o.cy - inner.cy) < 0.5 * inner.b) continue;
      const double scale = c_[j].has_rim ? 1 : k;
      const double oc = std::cos(o.theta), os = std::sin(o.theta);
      // Reciprocal semi-axes of the neighbour's largest rim, grown, and of its own ellipse, shrunk.
      const double ra = 1 / (scale * o.a + kContactPx), rb = 1 / (scale * o.b + kContactPx);
      const double ca = 1 / std::max(o.a - kContactPx, 1.0), cb = 1 / std::max(o.b - kContactPx, 1.0);
      for (int sector = 0; sector < 64; ++sector) {
        const double x = px[sector] - o.cx, y = py[sector] - o.cy;
        const double along = x * oc + y * os, across = y * oc - x * os;
        if (along * along * ca * ca + across * across * cb * cb <= 1) {
          overlapping |= std::uint64_t{1} << sector;
        } else if (along * along * ra * ra + across * across * rb * rb <= 1) {
          touching |= std::uint64_t{1} << sector;
        }
      }
    }
    return std::popcount(overlapping) > kMaxOverlapSectors ? 0 : touching;
  }

 private:
  const std::vector<Candidate>& c_;
  int kept_;
  const std::vector<Box>& reach_;
  int self_;
};

}  // namespace

// Whether e is nearly the same ellipse (NearlySame) as one of candidates[0, kept) other than i.
bool Detector::Impl::DetectedElsewhere(const Ellipse& e, int i, int kept) const {
  for (int j = 0; j < kept; ++j) {
    if (j != i && NearlySame(e, candidates[j].ellipse)) return true;
  }
  return false;
}

// Whether another of candidates[0, kept) lies inside candidates[i] (bounding boxes).
bool Detector::Impl::HoldsAnother(int i, int kept) const {
  const Box own = BoundingBox(candidates[i].ellipse, 0);
  for (int j = 0; j < kept; ++j) {
    const Box b = BoundingBox(candidates[j].ellipse, 0);
    if (j != i && b.x0 > own.x0 && b.y0 > own.y0 && b.x1 < own.x1 && b.y1 < own.y1) return true;
  }
  return false;
}

// Outer-rim completion (fit/rim_search.h) of candidates[0, kept), best first, within a budget of
// two frames' worth of scanned pixels (kCapRimSearch when it runs out).
void Detector::Impl::CompleteOuterRims(int kept, GroupStats* stats) {
  if (!(options.rim_min_coverage <= 1)) return;
  const EdgeMapView in = EdgeView();
  long budget = 2L * width * height;
  boxes.clear();
  for (int i = 0; i < kept; ++i) {
    Ellipse largest = candidates[i].ellipse;
    if (!candidates[i].has_rim) {
      largest.a *= kRimSearchMaxScale;
      largest.b *= kRimSearchMaxScale;
    }
    boxes.push_back(BoundingBox(largest, kContactPx));
  }
  for (int i = 0; i < kept; ++i) {
    Candidate& c = candidates[i];
    if (c.has_rim) continue;  // its cluster already holds the outer rim
    if (budget <= 0) {
      stats->caps_hit |= kCapRimSearch;
      return;
    }
    Ellipse rim;
    long scanned = 0;
    // A search's find replaces c's ellipse unless it is detected already or c holds another.
    auto replaces = [&](bool found) { return found && !DetectedElsewhere(rim, i, kept) && !HoldsAnother(i, kept); };
    // Options::top_over_side: a fit through the top's far arc and its side's lower edge holds the
    // top inside it, which replaces it (unless detected already); the outer-rim search below then
    // runs around the top (a can's lid found this way still gets its rim). Not when another kept
    // ellipse lies inside (a ring's or a cup's inner rim, whose near arc with the outer one's far
    // arc makes such a flatter ellipse), nor around a rescued ellipse (Candidate::rescued), already
    // fitted to the edges along its outline. Measured with and without that exception
    // (docs/hard-tabletop-rules.md, "Second chance"): the same on every generated set; with it,
    // prasad_subset at 2x keeps a calculator key that a flatter fit through the key's face took.
    if (options.top_over_side && !c.rescued) {
      const bool found = FindTopOverSide(in, c.ellipse, &refit_scratch, &rim, &scanned);
      budget -= scanned;
      if (replaces(found)) c.ellipse = rim;
    }
    // Options::lid_inside: a jar's lid inside a fit through the body's top outline replaces it,
    // with the same exceptions; the outline around the lid is the body's, so no rim is sought.
    if (options.lid_inside && !c.rescued) {
      const bool found = FindLidInside(in, c.ellipse, &refit_scratch, &rim, &scanned);
      budget -= scanned;
      if (replaces(found)) {
        c.ellipse = rim;
        continue;
      }
    }
    const NeighbourContacts contacts(candidates, kept, boxes, i);
    bool found = FindOuterRim(in, c.ellipse, options.rim_min_coverage, &rim, &scanned, &contacts);
    budget -= scanned;
    // No concentric rim: a recessed lid's rim (fit/recessed_rim.h), when it runs into no other
    // kept ellipse (a rim found through a neighbour's outline is not this top's).
    if (!found && budget > 0) {
      found = FindRecessedRim(in, c.ellipse, &refit_scratch, &rim, &scanned);
      budget -= scanned;
      const Box reach = found ? BoundingBox(rim, 0) : Box{};
      for (int j = 0; j < kept && found; ++j) found = j == i || !BoundingBox(candidates[j].ellipse, 0).Intersects(reach);
    }
    if (!found) continue;
    // Already detected as an ellipse of its own (then both stay): nearly the same ellipse, by
    // ClusterRule::kRelative at 0.1, not by eq. 17's 25 px, which would also match a different
    // ellipse nearby (a top-and-side fit below the rim).
    if (!DetectedElsewhere(rim, i, kept)) {
      c.ellipse = c.rim = rim;
      c.has_rim = true;
    }
  }
}

// Options::min_exclusive_coverage. Only ellipses whose outlines come near another kept one (boxes
// within kClaimReach px) can share edges; those, in order of edge coverage (best first; ties: the
// clustering's order; the rescued ones, Candidate::rescued, after all the others), claim their
// edges, and one left with too little coverage by unclaimed edges is dropped. Keeps the survivors'
// order; returns how many there are. Work per competing ellipse: 2 coverage passes (at most 256
// samples x 9 pixels) and a scan of the 9 px band along its outline.
int Detector::Impl::KeepExclusivelySupported(int kept) {
  if (!(options.min_exclusive_coverage > 0) || kept < 2) return kept;
  const EdgeMapView in = EdgeView();
  boxes.clear();
  for (int i = 0; i < kept; ++i) boxes.push_back(BoundingBox(candidates[i].ellipse, kClaimReach));
  by_coverage.clear();
  dropped.assign(static_cast<std::size_t>(kept), 0);
  for (int i = 0; i < kept; ++i) {
    bool near_another = false;
    for (int j = 0; j < kept && !near_another; ++j) near_another = j != i && boxes[i].Intersects(boxes[j]);
    if (!near_another) continue;
    const double coverage = EdgeCoverage(in, candidates[i].ellipse);  // in [0, 1]
    by_coverage.push_back({candidates[i].rescued ? 2 - coverage : -coverage, i});
  }
  std::sort(by_coverage.begin(), by_coverage.end());
  for (const auto& [rank, i] : by_coverage) {
    const Ellipse& e = candidates[i].ellipse;
    if (EdgeCoverage(in, e, options.min_exclusive_coverage, &claims) < options.min_exclusive_coverage) {
      dropped[i] = 1;
      continue;
    }
    ClaimEdges(in, e, &claims);
  }
  claims.Clear();
  int n = 0;
  for (int i = 0; i < kept; ++i) {
    if (!dropped[i]) candidates[n++] = candidates[i];
  }
  return n;
}

// Options::max_striped_share and max_nested_striped_share: drops the kept ellipses that are one
// stripe of a pattern (fit/edge_coverage.h StripedShare), held to the nested share when inside
// another kept ellipse; keeps the survivors' order. Work per ellipse: a pass over the kept ones (a
// box test each, for most) and <= 64 x 11 gradient reads (~10 x 7 for a plain rim).
int Detector::Impl::DropStriped(int kept) {
  const double nested_limit = std::min(options.max_striped_share, options.max_nested_striped_share);
  if (!(nested_limit < 1)) return kept;
  const EdgeMapView in = EdgeView();
  int n = 0;
  for (int i = 0; i < kept; ++i) {
    const double limit = NestedInAnother(candidates, kept, i) ? nested_limit : options.max_striped_share;
    if (!(limit < 1) || StripedShare(in, candidates[i].ellipse, limit) <= limit) candidates[n++] = candidates[i];
  }
  return n;
}

}  // namespace ellipsekit

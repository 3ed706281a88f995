#include "fit/clustering.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "fit/edge_refit.h"
#include "fit/recessed_rim.h"

namespace ellipsekit {

namespace {

double OrientationDifference(double t1, double t2) {
  const double d = std::fmod(std::abs(t1 - t2), std::numbers::pi);
  return std::min(d, std::numbers::pi - d);
}

// b / a above this: nearly a circle, whose orientation means little.
constexpr double kRoundAxisRatio = 0.9;

// Both nearly circles: their orientations mean little and are not compared.
bool BothNearlyRound(const Ellipse& v, const Ellipse& w) {
  return v.b > kRoundAxisRatio * v.a && w.b > kRoundAxisRatio * w.a;
}

// Members of a cluster tried as its representative (Options::cluster_pick_best_fit), best score
// first. Measured F on 200 generated scenes, seeds 7 / 11 / 23, tries 4 / 6 / 8 / all: 0.900 /
// 0.898 / 0.920, 0.902 / 0.898 / 0.920, 0.899 / 0.897 / 0.923, 0.899 / 0.896 / 0.922 (shared
// datasets equal): a weakly scoring member is rarely the better fit, and each try costs a
// FineEdgeCoverage.
constexpr int kFitTries = 6;

}  // namespace

double FeatureDistance(const Ellipse& v, const Ellipse& w) {
  const double dr = OrientationDifference(v.theta, w.theta);
  const double dcx = v.cx - w.cx, dcy = v.cy - w.cy, da = v.a - w.a, db = v.b - w.b;
  return std::sqrt(dcx * dcx + dcy * dcy + da * da + db * db + dr * dr);
}

bool SameEllipse(const Ellipse& v, const Ellipse& w, const Options& options) {
  if (options.cluster_rule == ClusterRule::kFeatureDistance) {
    // Our addition to eq. 17: concentric ellipses whose sizes differ by more than an outer rim's
    // largest scale are two ellipses (the two edges of a printed ring, a cap on a large lid) even
    // when their feature distance is below T_s, as it is for small ones. Measured in README.
    const double scale = (v.a + v.b) / (w.a + w.b);
    if ((scale > kRimMaxScale || scale < 1 / kRimMaxScale) &&
        std::hypot(v.cx - w.cx, v.cy - w.cy) < kRimCentreTolerance * std::min(v.b, w.b))
      return false;
    return FeatureDistance(v, w) < options.cluster_distance;
  }
  const double t = options.cluster_relative;
  if (std::hypot(v.cx - w.cx, v.cy - w.cy) > t * std::min(v.b, w.b)) return false;
  if (std::abs(v.a - w.a) > t * std::max(v.a, w.a)) return false;
  if (std::abs(v.b - w.b) > t * std::max(v.b, w.b)) return false;
  return BothNearlyRound(v, w) || OrientationDifference(v.theta, w.theta) <= t;
}

bool SurroundsAsRim(const Ellipse& outer, const Ellipse& inner) {
  if (std::hypot(outer.cx - inner.cx, outer.cy - inner.cy) >= kRimCentreTolerance * inner.b) {
    return false;
  }
  const double scale = (outer.a + outer.b) / (inner.a + inner.b);
  return scale >= kRimMinScale && scale <= kRimMaxScale;
}

bool IsOuterRim(const Ellipse& outer, const Ellipse& inner) {
  if (!SurroundsAsRim(outer, inner)) return false;
  if (std::abs(outer.b / outer.a - inner.b / inner.a) > kRimAxisRatioTolerance) return false;
  return BothNearlyRound(outer, inner) ||
         OrientationDifference(outer.theta, inner.theta) <= kRimOrientationTolerance;
}

bool IsLedgeBelow(const Ellipse& ledge, const Ellipse& top) {
  if (!(top.b < kRoundAxisRatio * top.a)) return false;  // seen from above: no way is up
  if (!(top.b >= kLedgeMinTopB)) return false;
  const double drop = -CentreRise(ledge, top);
  return drop >= kLedgeMinDrop * top.b && ledge.a + ledge.b >= kLedgeMinScale * (top.a + top.b);
}

void ClusterScratch::Reserve(std::size_t candidates) {
  const auto cells = static_cast<std::size_t>((kMaxCells + 1) * (kMaxCells + 1));
  for (CellLists* lists : {&references, &hopeless}) {
    lists->head.reserve(cells);
    lists->next.reserve(candidates);
  }
  failed.reserve(candidates);
}

void ClusterScratch::Start(const std::vector<Candidate>& c) {
  UniformGrid::Box box;
  for (const Candidate& k : c) box.Add(k.ellipse.cx, k.ellipse.cy);
  const double cell =
      box.empty() ? kMinCellPx : std::max({kMinCellPx, (box.x1 - box.x0) / kMaxCells, (box.y1 - box.y0) / kMaxCells});
  grid.Cover(box, cell);
  references.Reset(grid.cells(), c.size());
  failed.clear();
}

void ClusterScratch::CellLists::Reset(int cells, std::size_t candidates) {
  head.assign(static_cast<std::size_t>(cells), -1);
  next.assign(candidates, -1);
}

void ClusterScratch::CellLists::Add(const UniformGrid& grid, int k, const Ellipse& e) {
  const int i = grid.Cell(e.cx, e.cy);
  next[k] = head[i];
  head[i] = k;
}

int ClusterCandidates(std::vector<Candidate>* candidates, const Options& options, const CandidateCheck* check,
                      ClusterScratch* scratch) {
  ClusterScratch local;
  ClusterScratch& work = scratch != nullptr ? *scratch : local;
  auto passes = [&](const Candidate& c) { return check == nullptr || check->Passes(c); };
  const bool second_chances = check != nullptr && options.rescue_min_coverage <= 1;
  const bool pick_best_fit = options.cluster_pick_best_fit && check != nullptr;
  // Best score first; equal scores ordered by the parameters, so the order is total and the
  // result never depends on the sort algorithm.
  std::vector<Candidate>& c = *candidates;
  std::sort(c.begin(), c.end(), [](const Candidate& cx, const Candidate& cy) {
    const Ellipse& x = cx.ellipse;
    const Ellipse& y = cy.ellipse;
    if (x.score != y.score) return x.score > y.score;
    if (x.cx != y.cx) return x.cx < y.cx;
    if (x.cy != y.cy) return x.cy < y.cy;
    if (x.a != y.a) return x.a < y.a;
    if (x.b != y.b) return x.b < y.b;
    return x.theta < y.theta;
  });
  // c[0, kept) are the cluster references (each the best-scoring member that founded its
  // cluster); membership is always tested against the reference, never against the rim or the
  // member chosen to represent it, so a cluster cannot drift.
  std::size_t kept = 0;
  work.Start(c);
  auto first_same = [&](const Ellipse& e) { return work.references.FirstSame(work.grid, c, e, options); };
  auto found_cluster = [&](const Candidate& founder) {  // founder may be c[kept] itself
    c[kept] = founder;
    work.references.Add(work.grid, static_cast<int>(kept), founder.ellipse);
    c[kept].has_rim = false;
    c[kept].rim_recessed = false;
    c[kept].best_fit = founder.ellipse;
    c[kept].best_fit_share = -1;  // measured when a first member is tried (most clusters have none)
    c[kept].fit_tries = 0;
    ++kept;
  };
  for (std::size_t i = 0; i < c.size(); ++i) {
    const int first = first_same(c[i].ellipse);
    const std::size_t k = first < 0 ? kept : static_cast<std::size_t>(first);
    if (k == kept) {
      if (passes(c[i])) {
        found_cluster(c[i]);
      } else if (second_chances) {
        work.failed.push_back({c[i].ellipse, {c[i].arcs[0], c[i].arcs[1], c[i].arcs[2]}, c[i].centres_by_fit});
      }
      continue;
    }
    Candidate& ref = c[k];
    const bool outer = IsOuterRim(c[i].ellipse, ref.ellipse);
    // Options::cluster_recessed_rims: a member where a recessed lid's rim lies around the reference
    // (fit/recessed_rim.h; seen at an angle, so not for a nearly round reference, whose minor axis
    // says nothing of which way is up) is its rim too, until a concentric outer rim is found.
    const bool recessed = options.cluster_recessed_rims && !outer && ref.ellipse.b < kRoundAxisRatio * ref.ellipse.a &&
                          IsRecessedRimOf(c[i].ellipse, ref.ellipse);
    // The best-scoring outer rim of the reference within the margin (members arrive best first).
    if ((outer || recessed) && (!ref.has_rim || (outer && ref.rim_recessed)) &&
        c[i].ellipse.score >= ref.ellipse.score - options.cluster_outer_margin && passes(c[i])) {
      ref.has_rim = true;
      ref.rim_recessed = recessed;
      ref.rim = c[i].ellipse;
    }
    // A member that fits the edges more tightly than the representative so far; rims of the
    // reference, outer or inner, a ledge below it, and members more than kRimMaxScale larger or
    // smaller (the other edge of a printed ring, joined to a slightly off-centre fit of this one
    // by eq. 17) are other ellipses, never its representative; only the kFitTries best-scoring
    // of the others are tried.
    const double scale = (c[i].ellipse.a + c[i].ellipse.b) / (ref.ellipse.a + ref.ellipse.b);
    const bool same_size = scale < kRimMaxScale && scale > 1 / kRimMaxScale;
    if (pick_best_fit && !outer && same_size && !IsOuterRim(ref.ellipse, c[i].ellipse) &&
        !IsLedgeBelow(c[i].ellipse, ref.ellipse) && ref.fit_tries++ < kFitTries) {
      if (ref.best_fit_share < 0) ref.best_fit_share = check->FitShare(ref, -1);
      const double share = check->FitShare(c[i], ref.best_fit_share);
      if (share > ref.best_fit_share && passes(c[i])) {
        ref.best_fit_share = share;
        ref.best_fit = c[i].ellipse;
      }
    }
  }
  // The second chances, none for a candidate that a cluster holds or that is the same ellipse as
  // one whose second chance failed (its refit would gather the same edges). Each failed candidate
  // is a distinct one of c, so kept stays < c.size().
  work.hopeless.Reset(work.grid.cells(), work.failed.size());
  for (std::size_t j = 0; j < work.failed.size(); ++j) {
    const ClusterScratch::Failed& failed = work.failed[j];
    const bool held = first_same(failed.ellipse) >= 0;
    if (held || work.hopeless.FirstSame(work.grid, work.failed, failed.ellipse, options) >= 0) continue;
    Candidate f;
    f.ellipse = failed.ellipse;
    std::copy(failed.arcs, failed.arcs + 3, f.arcs);
    f.centres_by_fit = failed.centres_by_fit;
    if (!check->PassesRefitted(&f)) {
      work.hopeless.Add(work.grid, static_cast<int>(j), failed.ellipse);
    } else if (first_same(f.ellipse) < 0) {
      f.rescued = true;
      found_cluster(f);
    }
  }
  for (std::size_t k = 0; k < kept; ++k) {
    // A member larger than the recessed rim that fits the edges best is the rim itself.
    if (c[k].has_rim && c[k].rim_recessed && c[k].best_fit.a > c[k].rim.a) c[k].has_rim = false;
    if (c[k].has_rim) {
      c[k].ellipse = c[k].rim;
    } else {
      const double score = c[k].ellipse.score;
      c[k].ellipse = c[k].best_fit;
      c[k].ellipse.score = score;
    }
  }
  return static_cast<int>(kept);
}

}  // namespace ellipsekit

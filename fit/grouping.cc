#include "fit/grouping.h"

#include <algorithm>
#include <cmath>

#include "ellipsekit/detector.h"
#include "fit/center.h"
#include "fit/validation.h"

namespace ellipsekit {

namespace {

constexpr int kPositionTolerance = 1;  // px (sec. II-B-3)

int NextQuadrant(int q) { return q == 4 ? 1 : q + 1; }

// prev is in quadrant q, next in quadrant q + 1 (counter-clockwise).
bool RelativePositionHolds(const Arc& prev, const Arc& next) {
  switch (prev.quadrant) {
    case kQuadrantI: return next.max_x <= prev.min_x + kPositionTolerance;
    case kQuadrantII: return prev.max_y <= next.min_y + kPositionTolerance;
    case kQuadrantIII: return prev.max_x <= next.min_x + kPositionTolerance;
    case kQuadrantIV: return next.max_y <= prev.min_y + kPositionTolerance;
  }
  return false;
}

void BuildCsr(int arcs, const std::vector<GroupScratch::Pair>& pairs, bool by_next,
              std::vector<int>* offset, std::vector<int>* items) {
  offset->assign(static_cast<std::size_t>(arcs) + 1, 0);
  for (const auto& p : pairs) ++(*offset)[(by_next ? p.next : p.prev) + 1];
  for (int i = 0; i < arcs; ++i) (*offset)[i + 1] += (*offset)[i];
  items->resize(pairs.size());
  // Fill with a running cursor per arc (offset[i] advanced, then restored below).
  for (int k = 0; k < static_cast<int>(pairs.size()); ++k) {
    const int a = by_next ? pairs[k].next : pairs[k].prev;
    (*items)[(*offset)[a]++] = k;
  }
  for (int i = arcs; i > 0; --i) (*offset)[i] = (*offset)[i - 1];
  (*offset)[0] = 0;
}

double DistanceRatio(const Arc* const* group, int count, const Eigen::Vector2d& c) {
  double lo = HUGE_VAL, hi = 0;
  for (int i = 0; i < count; ++i) {
    const double d = (group[i]->mid - c).norm();
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  return lo > 0 ? hi / lo : HUGE_VAL;
}

// K(tau) > T_l (eq. 13) and psi (eq. 16) on the fitted ellipse; on success e->score = K + psi.
// A refitted ellipse fits the group to the pixel, so psi is held to a much stricter bar (README).
bool Validate(const Curves& curves, const Arc* const* group, int count, bool refined, const Options& options,
              Ellipse* e) {
  if (!(e->b >= 1.0) || e->b < options.min_axis_ratio * e->a) return false;
  const double k = LengthRatio(group, count, *e);
  if (!(k > options.length_ratio)) return false;
  const double min_psi = refined ? options.refined_circumference_ratio : options.circumference_ratio;
  const double psi = CircumferenceRatio(curves, group, count, *e, options.inlier_rule, options.inlier_threshold, min_psi);
  if (!(psi > min_psi)) return false;
  e->score = k + psi;
  return true;
}

// Eq. 13 accepts only a + b < sum(w + h) / (count T_l). An ellipse that passes within 1 px of the
// arcs' endpoints contains their convex hull shrunk by 1 px, so 2 a >= D - 2 (D: the endpoints'
// largest distance) and 2 b >= W - 2 (W: the hull's smallest width, bounded below by the smallest
// altitude of any triangle of endpoints): a group with (D + W) / 2 - 2 >= the bound fails eq. 13
// whatever its fit. A refitted ellipse that passes psi > 0.9 has its arcs' points within T_d of it,
// so this rejects before the refit what K would reject after it: 76 % of the triplets of prasad
// 027_0003, identical ellipses on every shared image and the 200 scenes. (Not on the paper's path,
// whose eqs. 8-12 estimate need not pass near the endpoints.)
bool SpanFailsLengthRatio(const Arc* const* group, int count, double length_ratio) {
  if (!(length_ratio > 0) || count > 3) return false;
  double extent = 0;
  Eigen::Vector2d p[6];
  int n = 0;
  for (int i = 0; i < count; ++i) {
    extent += group[i]->width + group[i]->height;
    p[n++] = group[i]->p0;
    p[n++] = group[i]->p1;
  }
  const double bound = extent / (count * length_ratio);
  double d2 = 0;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) d2 = std::max(d2, (p[i] - p[j]).squaredNorm());
  const double d = std::sqrt(d2);
  if (d / 2 - 1 >= bound) return true;  // b >= 0 suffices
  double w2 = 0;  // the largest smallest-altitude^2 over the triangles
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      for (int k = j + 1; k < n; ++k) {
        const Eigen::Vector2d u = p[j] - p[i], v = p[k] - p[i], t = p[k] - p[j];
        const double twice_area = u.x() * v.y() - u.y() * v.x();
        const double longest2 = std::max({u.squaredNorm(), v.squaredNorm(), t.squaredNorm()});
        if (longest2 > 0) w2 = std::max(w2, twice_area * twice_area / longest2);
      }
    }
  }
  return (d + std::sqrt(w2)) / 2 - 2 >= bound;
}


Candidate MakeCandidate(const Ellipse& e, int first, int second, int third) {
  Candidate c;
  c.ellipse = e;
  c.arcs[0] = first;
  c.arcs[1] = second;
  c.arcs[2] = third;
  return c;
}

// Two arcs of one ellipse that a pair candidate could stand on lie close: their mid-points within
// kPairMidDistance times the largest arc extent (bounding-box side).
constexpr double kPairMidDistance = 3;
bool MidPointsNear(const Arc& u, const Arc& v) {
  const double extent = std::max({u.width, u.height, v.width, v.height});
  return (u.mid - v.mid).squaredNorm() <= kPairMidDistance * kPairMidDistance * extent * extent;
}

// Opposite quadrants where an ellipse puts them: III lies below-left of I, IV below-right of II
// (bounding boxes, 1 px tolerance), mid-points near (MidPointsNear).
bool OppositePositionHolds(const Arc& upper, const Arc& lower) {
  const bool placed = upper.quadrant == kQuadrantI
                          ? lower.min_x <= upper.min_x + kPositionTolerance && lower.max_y + kPositionTolerance >= upper.max_y
                          : lower.max_x + kPositionTolerance >= upper.max_x && lower.max_y + kPositionTolerance >= upper.max_y;
  return placed && MidPointsNear(upper, lower);
}

// A two-arc candidate (Options::pair_candidates): refitted, then Gamma, K and psi as for triplets.
// False when the group fails; true with *e set otherwise.
bool PairCandidate(const Curves& curves, const Arc& first, const Arc& second, const Options& options, Ellipse* e) {
  const Arc* group[2] = {&first, &second};
  if (SpanFailsLengthRatio(group, 2, options.length_ratio)) return false;
  if (!RefineEllipse(group, 2, e)) return false;
  if (!(DistanceRatio(group, 2, Eigen::Vector2d(e->cx, e->cy)) < options.distance_ratio)) return false;
  return Validate(curves, group, 2, /*refined=*/true, options, e);
}

// Triplets: (a, b) and (b, c) share the middle arc b. False when a cap ended the search.
bool AddTripletCandidates(const Curves& curves, const std::vector<Arc>& arcs, const Options& options,
                          GroupScratch* s, std::vector<Candidate>* candidates, GroupStats* stats) {
  const int n = static_cast<int>(arcs.size());
  const double tc2 = options.center_distance * options.center_distance;
  for (int b = 0; b < n; ++b) {
    for (int u = s->as_next_offset[b]; u < s->as_next_offset[b + 1]; ++u) {
      const GroupScratch::Pair& ab = s->pairs[s->as_next[u]];
      for (int v = s->as_prev_offset[b]; v < s->as_prev_offset[b + 1]; ++v) {
        const GroupScratch::Pair& bc = s->pairs[s->as_prev[v]];
        if (ab.prev == bc.next) continue;
        if ((ab.center - bc.center).squaredNorm() >= tc2) continue;
        if (stats->triplets >= options.max_triplets) { stats->caps_hit |= kCapTriplets; return false; }
        ++stats->triplets;
        const Arc* group[3] = {&arcs[ab.prev], &arcs[b], &arcs[bc.next]};
        if (options.refine_fit && SpanFailsLengthRatio(group, 3, options.length_ratio)) continue;
        // The refit (our addition) replaces the centre and parameters of eqs. 3-12 when it
        // succeeds, and its centre is then the one Gamma is measured from; the mean-shift centre
        // (Fig. 7) is computed only for the paper's path, where eqs. 8-12 need it.
        Ellipse e;
        const bool refined = options.refine_fit && RefineEllipse(group, 3, &e);
        Eigen::Vector2d center(e.cx, e.cy);
        if (!refined) {
          bool ms_capped = false;
          center = TripletCenter(*group[0], *group[1], *group[2], ab.center, bc.center, options, &ms_capped);
          if (ms_capped) stats->caps_hit |= kCapMeanShift;
        }
        if (!(DistanceRatio(group, 3, center) < options.distance_ratio)) continue;  // Gamma < T_f
        if (!refined && !EstimateParameters(curves, group, 3, center, &s->params, &e)) continue;
        if (!Validate(curves, group, 3, refined, options, &e)) continue;
        if (static_cast<int>(candidates->size()) >= options.max_candidates) {
          stats->caps_hit |= kCapCandidates;
          return false;
        }
        candidates->push_back(MakeCandidate(e, ab.prev, b, bc.next));
      }
    }
  }
  return true;
}

// Two-arc candidates (Options::pair_candidates): the position-tested pairs of consecutive
// quadrants, then opposite ones (capped like them, a quarter of max_pairs per kind); at most
// max_triplets pairs are examined (a cap of their own, reported as max_triplets).
void AddPairCandidates(const Curves& curves, const std::vector<Arc>& arcs, const Options& options,
                       GroupScratch* s, std::vector<Candidate>* candidates, GroupStats* stats) {
  int examined = 0;
  auto add = [&](int first, int second) {
    if (examined >= options.max_triplets) {
      stats->caps_hit |= kCapTriplets;
      return false;
    }
    ++examined;
    Ellipse e;
    if (!PairCandidate(curves, arcs[first], arcs[second], options, &e)) return true;
    if (static_cast<int>(candidates->size()) >= options.max_candidates) {
      stats->caps_hit |= kCapCandidates;
      return false;
    }
    candidates->push_back(MakeCandidate(e, first, second, -1));
    return true;
  };
  for (const GroupScratch::Pair& p : s->pairs) {
    if (MidPointsNear(arcs[p.prev], arcs[p.next]) && !add(p.prev, p.next)) return;
  }
  const int per_kind = std::max(1, options.max_pairs / 4);
  for (int upper = kQuadrantI; upper <= kQuadrantII; ++upper) {
    int kept = 0;
    for (int i : s->by_quadrant[upper]) {
      for (int j : s->by_quadrant[upper + 2]) {
        if (!OppositePositionHolds(arcs[i], arcs[j])) continue;
        if (kept >= per_kind) {
          stats->caps_hit |= kCapPairs;
          break;
        }
        ++kept;
        ++stats->pairs;
        if (!add(i, j)) return;
      }
      if (kept >= per_kind) break;
    }
  }
}

}  // namespace

void GroupScratch::Reserve(std::size_t pixels, const Options& options) {
  const std::size_t arcs = std::min<std::size_t>(pixels, ReserveFor(options.max_arcs));
  for (auto& q : by_quadrant) q.reserve(arcs);
  const std::size_t max_pairs = ReserveFor(options.max_pairs);
  pairs.reserve(max_pairs);
  as_next.reserve(max_pairs);
  as_prev.reserve(max_pairs);
  as_next_offset.reserve(arcs + 1);
  as_prev_offset.reserve(arcs + 1);
  params.Reserve();
}

void FindCandidates(const Curves& curves, const std::vector<Arc>& arcs, const Options& options,
                    GroupScratch* s, std::vector<Candidate>* candidates, GroupStats* stats) {
  const int n = static_cast<int>(arcs.size());
  for (auto& q : s->by_quadrant) q.clear();
  for (int i = 0; i < n; ++i) s->by_quadrant[arcs[i].quadrant].push_back(i);

  // Pairs. The position test is a few comparisons (bounded by max_arcs squared); the cap counts
  // the pairs that pass it, each of which costs a centre. It is shared evenly by the four kinds,
  // so a capped frame still has pairs of every kind to make triplets from.
  s->pairs.clear();
  const int per_kind = std::max(1, options.max_pairs / 4);
  for (int q = 1; q <= 4; ++q) {
    int kept = 0;
    for (int i : s->by_quadrant[q]) {
      for (int j : s->by_quadrant[NextQuadrant(q)]) {
        if (!RelativePositionHolds(arcs[i], arcs[j])) continue;
        if (kept >= per_kind) { stats->caps_hit |= kCapPairs; break; }
        Eigen::Vector2d c;
        if (PairCenter(arcs[i], arcs[j], options.center_method, &c)) { s->pairs.push_back({i, j, c}); ++kept; }
      }
      if (kept >= per_kind) break;
    }
  }
  stats->pairs = static_cast<int>(s->pairs.size());
  BuildCsr(n, s->pairs, /*by_next=*/true, &s->as_next_offset, &s->as_next);
  BuildCsr(n, s->pairs, /*by_next=*/false, &s->as_prev_offset, &s->as_prev);

  if (!AddTripletCandidates(curves, arcs, options, s, candidates, stats)) return;
  if (options.pair_candidates && options.refine_fit) AddPairCandidates(curves, arcs, options, s, candidates, stats);
}

}  // namespace ellipsekit

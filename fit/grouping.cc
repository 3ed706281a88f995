#include "fit/grouping.h"

#include <algorithm>
#include <cmath>

#include "ellipsekit/detector.h"
#include "fit/center.h"
#include "fit/uniform_grid.h"
#include "fit/validation.h"

namespace ellipsekit {

namespace {

constexpr int kPositionTolerance = 1;  // px (sec. II-B-3)

int NextQuadrant(int q) { return q == 4 ? 1 : q + 1; }

// An arc's size: the longer side of its bounding box, px.
double ArcSize(const Arc& a) { return std::max(a.width, a.height); }

// Pairs an arc takes as the larger of the two, per neighbouring quadrant: a bound for frames
// where many arcs end near each other (200 concentric circles: 12134 pairs with 8, 20000+ without
// a bound). No shared dataset, generated scene or crowded scene changes with 8 or 16 against no
// bound; six nested circles (tests/test_rim_search.cc) lose one to 8, none to 16.
constexpr int kPairsPerArc = 16;

// Calls fn(i, j, d) for arcs i of quadrant qa and j of quadrant qb whose ends lie d <=
// reach * max(ArcSize(i), ArcSize(j)) px from each other (ArcEndIndex::EndDistance) and that
// accept(i, j): each arc asks the index with its own reach and takes the pairs for which it is
// the larger arc, at most kPairsPerArc of them, nearest first (ties: lower index). Each pair at
// most once.
template <class Accept, class Fn>
void ForEachNearPair(const std::vector<Arc>& arcs, GroupScratch* s, int qa, int qb, double reach, Accept accept,
                     Fn fn) {
  auto seed = [&](int k, int other_quadrant, bool k_is_first) {
    const double size_k = ArcSize(arcs[k]);
    s->near.clear();
    s->index.ForEachNear(arcs, arcs[k], other_quadrant, reach * size_k, [&](int m, double d) {
      const double size_m = ArcSize(arcs[m]);
      // Ties in size go to the first arc's side.
      if (k_is_first ? size_m > size_k : size_m >= size_k) return;
      if (k_is_first ? accept(k, m) : accept(m, k)) s->near.push_back({d, m});
    });
    const std::size_t keep = std::min<std::size_t>(s->near.size(), kPairsPerArc);
    std::partial_sort(s->near.begin(), s->near.begin() + keep, s->near.end());
    for (std::size_t t = 0; t < keep; ++t) {
      const auto [d, m] = s->near[t];
      if (k_is_first) fn(k, m, d); else fn(m, k, d);
    }
  };
  for (int i : s->by_quadrant[qa]) seed(i, qb, true);
  for (int j : s->by_quadrant[qb]) seed(j, qa, false);
}

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
// `fit`: the two arcs' RefineEllipse, when already made (a pair of FindCandidates).
bool PairCandidate(const Curves& curves, const Arc& first, const Arc& second, const Options& options,
                   const Ellipse* fit, Ellipse* e) {
  const Arc* group[2] = {&first, &second};
  if (SpanFailsLengthRatio(group, 2, options.length_ratio)) return false;
  if (fit != nullptr) {
    *e = *fit;
  } else if (!RefineEllipse(group, 2, e)) {
    return false;
  }
  if (!(DistanceRatio(group, 2, Eigen::Vector2d(e->cx, e->cy)) < options.distance_ratio)) return false;
  return Validate(curves, group, 2, /*refined=*/true, options, e);
}

// Arcs longest first (ties: lower index): the order pairs are made and, when the triplet budget
// cannot run out, the order middle arcs are visited in.
void LongestFirst(const std::vector<Arc>& arcs, GroupScratch* s) {
  const int n = static_cast<int>(arcs.size());
  s->order.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) s->order[i] = i;
  std::sort(s->order.begin(), s->order.end(), [&arcs](int u, int v) {
    const int pu = arcs[u].points(), pv = arcs[v].points();
    return pu != pv ? pu > pv : u < v;
  });
}

constexpr double kSpreadCellPx = 64;

// s->spread: the arcs of s->order spread over the frame, most salient first: the longest arc of
// every kSpreadCellPx cell, then the second longest of every cell, and so on; within a rank,
// cells in bit-reversed Z order, so that any prefix of the cells is spread evenly over the frame
// (a 2-D van der Corput sequence), where longest first alone would favour the near side of a
// tilted layout. Made only for a frame whose triplet budget may run out.
void SpreadOverFrame(const std::vector<Arc>& arcs, GroupScratch* s) {
  UniformGrid::Box box;
  for (const Arc& a : arcs) box.Add(a.mid.x(), a.mid.y());
  UniformGrid grid;
  grid.Cover(box, kSpreadCellPx);
  s->cell_count.assign(static_cast<std::size_t>(grid.cells()), 0);
  s->rank.resize(arcs.size());
  s->cell_key.resize(arcs.size());
  for (int i : s->order) {
    const auto cx = static_cast<std::uint32_t>(grid.Column(arcs[i].mid.x()));
    const auto cy = static_cast<std::uint32_t>(grid.Row(arcs[i].mid.y()));
    s->rank[i] = s->cell_count[static_cast<std::size_t>(cy) * grid.cols + cx]++;
    std::uint32_t z = 0;
    for (int bit = 0; bit < 16; ++bit) z |= ((cx >> bit) & 1u) << (2 * bit) | ((cy >> bit) & 1u) << (2 * bit + 1);
    std::uint32_t reversed = 0;
    for (int bit = 0; bit < 32; ++bit) reversed |= ((z >> bit) & 1u) << (31 - bit);
    s->cell_key[i] = reversed;
  }
  s->spread = s->order;
  std::sort(s->spread.begin(), s->spread.end(), [s](int u, int v) {
    if (s->rank[u] != s->rank[v]) return s->rank[u] < s->rank[v];
    return s->cell_key[u] < s->cell_key[v];  // one arc per cell and rank: a total order
  });
}

// T_c (sec. II-C-1) by the fits: both pairs were fitted (Options::fit_pair_centers) to ellipses
// with b >= 1 px whose centres lie within sqrt(tc2) px.
bool FitCentresAgree(const GroupScratch::Pair& ab, const GroupScratch::Pair& bc, double tc2) {
  if (!ab.fitted || !bc.fitted || !(ab.fit.b >= 1) || !(bc.fit.b >= 1)) return false;
  const double dx = ab.fit.cx - bc.fit.cx, dy = ab.fit.cy - bc.fit.cy;
  return dx * dx + dy * dy < tc2;
}

// Triplets: (a, b) and (b, c) share the middle arc b; each middle arc's pairs are listed nearest
// first. The budget max_triplets is spread over the frame, never spent in scan order: first each
// middle arc, in the spread order (SpreadOverFrame), examines at most an equal share of it; then the
// arcs that had more go on, in the same order, with what the others left. False when a cap
// (max_triplets, max_candidates) ended the search.
bool AddTripletCandidates(const Curves& curves, const std::vector<Arc>& arcs, const Options& options,
                          GroupScratch* s, std::vector<Candidate>* candidates, GroupStats* stats) {
  const double tc2 = options.center_distance * options.center_distance;
  // Only refitted candidates retire arcs: they fit their arcs to the pixel (psi > 0.9), while on
  // the paper's path (refine_fit=false) the first valid triplet of an arc is often a poor
  // estimate of its ellipse (prasad 0.786 -> 0.680 when it retired arcs too).
  const bool retire = options.retire_found_arcs && options.refine_fit;
  bool candidates_full = false;
  // Examines b's triplets from the done[b]-th on (counting only those within T_c) until done[b]
  // reaches `limit`; true when b has none left.
  auto run = [&](int b, int limit) {
    int seen = 0;
    for (int u = s->as_next_offset[b]; u < s->as_next_offset[b + 1]; ++u) {
      const GroupScratch::Pair& ab = s->pairs[s->as_next[u]];
      for (int v = s->as_prev_offset[b]; v < s->as_prev_offset[b + 1]; ++v) {
        const GroupScratch::Pair& bc = s->pairs[s->as_prev[v]];
        if (ab.prev == bc.next) continue;
        // T_c by eqs. 3-7, else by the pairs' fits (Candidate::centres_by_fit).
        const bool by_fit = (ab.center - bc.center).squaredNorm() >= tc2;
        if (by_fit && !FitCentresAgree(ab, bc, tc2)) continue;
        if (seen++ < s->done[b]) continue;
        if (retire && s->retired[ab.prev] + s->retired[b] + s->retired[bc.next] >= 2) {
          ++s->done[b];
          continue;
        }
        // The share of pass 1 is at least one triplet per middle arc, so the frame's cap is
        // checked too: with more middle arcs than max_triplets it ends pass 1 early.
        if (s->spent[b] >= limit || stats->triplets >= options.max_triplets) return false;
        ++s->done[b];
        ++s->spent[b];
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
          candidates_full = true;
          return true;
        }
        candidates->push_back(MakeCandidate(e, ab.prev, b, bc.next));
        candidates->back().centres_by_fit = by_fit;
        if (retire) s->retired[ab.prev] = s->retired[b] = s->retired[bc.next] = 1;
      }
    }
    return true;
  };
  int middles = 0;
  long most = 0;  // the triplets there could be (before T_c)
  for (int b : s->order) {
    s->done[b] = s->spent[b] = 0;
    s->retired[b] = 0;
    const long in = s->as_next_offset[b + 1] - s->as_next_offset[b], out = s->as_prev_offset[b + 1] - s->as_prev_offset[b];
    middles += in > 0 && out > 0;
    most += in * out;
  }
  // Longest first when the budget cannot run out (retiring arcs favours the arcs visited first);
  // spread over the frame when it may.
  if (most > options.max_triplets) SpreadOverFrame(arcs, s);
  const std::vector<int>& order = most > options.max_triplets ? s->spread : s->order;
  const int share = std::max(1, options.max_triplets / std::max(1, middles));
  bool capped = false;
  for (std::size_t k = 0; k < order.size(); ++k) {
    if (!run(order[k], share)) capped = true;
    if (candidates_full) return false;
    if (stats->triplets >= options.max_triplets) {
      // The frame's cap reached with middle arcs still to visit: pass 2 reports it.
      if (k + 1 < order.size()) capped = true;
      break;
    }
  }
  if (!capped) return true;
  for (int b : order) {
    const int left = options.max_triplets - stats->triplets;
    if (left <= 0 || !run(b, s->spent[b] + left)) {
      stats->caps_hit |= kCapTriplets;
      return false;
    }
    if (candidates_full) return false;
  }
  return true;
}

// Two-arc candidates (Options::pair_candidates): the position-tested pairs of consecutive
// quadrants, then opposite ones (capped like them, a quarter of max_pairs per kind); at most
// max_pairs of them are examined (reported as max_pairs).
void AddPairCandidates(const Curves& curves, const std::vector<Arc>& arcs, const Options& options,
                       GroupScratch* s, std::vector<Candidate>* candidates, GroupStats* stats) {
  int examined = 0;
  // pair: one of FindCandidates' pairs, fitted already (Options::fit_pair_centers): its fit is
  // the candidate's, and there is none when that fit failed. nullptr: fitted here.
  auto add = [&](int first, int second, const GroupScratch::Pair* pair) {
    if (examined >= options.max_pairs) {
      stats->caps_hit |= kCapPairs;
      return false;
    }
    ++examined;
    if (pair != nullptr && !pair->fitted) return true;
    Ellipse e;
    if (!PairCandidate(curves, arcs[first], arcs[second], options, pair ? &pair->fit : nullptr, &e)) return true;
    if (static_cast<int>(candidates->size()) >= options.max_candidates) {
      stats->caps_hit |= kCapCandidates;
      return false;
    }
    candidates->push_back(MakeCandidate(e, first, second, -1));
    return true;
  };
  for (const GroupScratch::Pair& p : s->pairs) {
    if (MidPointsNear(arcs[p.prev], arcs[p.next]) && !add(p.prev, p.next, options.fit_pair_centers ? &p : nullptr))
      return;
  }
  // Mid-points within kPairMidDistance arc sizes put the ends within (kPairMidDistance + 2 sqrt 2)
  // of them (an end lies within a bounding-box diagonal of the mid-point): the index finds a
  // superset, OppositePositionHolds the pairs.
  const int per_kind = std::max(1, options.max_pairs / 4);
  const double reach = kPairMidDistance + 2 * std::sqrt(2.0);
  for (int upper = kQuadrantI; upper <= kQuadrantII; ++upper) {
    int kept = 0;
    bool go_on = true;
    ForEachNearPair(arcs, s, upper, upper + 2, reach,
                    [&](int i, int j) { return OppositePositionHolds(arcs[i], arcs[j]); }, [&](int i, int j, double) {
      if (!go_on) return;
      if (kept >= per_kind) {
        stats->caps_hit |= kCapPairs;
        return;
      }
      ++kept;
      ++stats->pairs;
      go_on = add(i, j, nullptr);
    });
    if (!go_on) return;
  }
}

}  // namespace

void GroupScratch::Reserve(int width, int height, const Options& options) {
  const std::size_t pixels = static_cast<std::size_t>(width) * height;
  const std::size_t arcs = std::min<std::size_t>(pixels, ReserveFor(options.max_arcs));
  for (auto& q : by_quadrant) q.reserve(arcs);
  const std::size_t max_pairs = ReserveFor(options.max_pairs);
  pairs.reserve(max_pairs);
  as_next.reserve(max_pairs);
  as_prev.reserve(max_pairs);
  as_next_offset.reserve(arcs + 1);
  as_prev_offset.reserve(arcs + 1);
  order.reserve(arcs);
  spread.reserve(arcs);
  rank.reserve(arcs);
  cell_key.reserve(arcs);
  cell_count.reserve(static_cast<std::size_t>(width / 64 + 2) * (height / 64 + 2));
  near.reserve(arcs);
  done.reserve(arcs);
  spent.reserve(arcs);
  retired.reserve(arcs);
  index.Reserve(width, height, arcs);
  params.Reserve();
}

void FindCandidates(const Curves& curves, const std::vector<Arc>& arcs, const Options& options,
                    GroupScratch* s, std::vector<Candidate>* candidates, GroupStats* stats) {
  const int n = static_cast<int>(arcs.size());
  LongestFirst(arcs, s);
  for (auto& q : s->by_quadrant) q.clear();
  for (int i : s->order) s->by_quadrant[arcs[i].quadrant].push_back(i);
  s->index.Build(arcs);

  // Pairs of consecutive quadrants whose ends lie near each other (Options::pair_reach), then the
  // paper's position test. The cap counts the pairs that pass it, each of which costs a centre,
  // and is shared evenly by the four kinds, so a capped frame still has pairs of every kind.
  s->pairs.clear();
  const int per_kind = std::max(1, options.max_pairs / 4);
  const bool fit_pairs = options.fit_pair_centers && options.refine_fit;
  for (int q = 1; q <= 4; ++q) {
    int kept = 0;
    ForEachNearPair(arcs, s, q, NextQuadrant(q), options.pair_reach,
                    [&](int i, int j) { return RelativePositionHolds(arcs[i], arcs[j]); },
                    [&](int i, int j, double gap) {
      if (kept >= per_kind) {
        stats->caps_hit |= kCapPairs;
        return;
      }
      GroupScratch::Pair p{i, j, Eigen::Vector2d::Zero(), gap, false, Ellipse{}};
      if (PairCenter(arcs[i], arcs[j], options.center_method, &p.center)) {
        if (fit_pairs) {
          const Arc* group[2] = {&arcs[i], &arcs[j]};
          p.fitted = RefineEllipse(group, 2, &p.fit);
        }
        s->pairs.push_back(p);
        ++kept;
      }
    });
  }
  stats->pairs = static_cast<int>(s->pairs.size());
  BuildCsr(n, s->pairs, /*by_next=*/true, &s->as_next_offset, &s->as_next);
  BuildCsr(n, s->pairs, /*by_next=*/false, &s->as_prev_offset, &s->as_prev);
  // Each arc's pairs nearest first (ties: creation order), so a budget takes the likeliest.
  auto nearest_first = [s](int p, int q) {
    return s->pairs[p].gap != s->pairs[q].gap ? s->pairs[p].gap < s->pairs[q].gap : p < q;
  };
  for (int i = 0; i < n; ++i) {
    std::sort(s->as_next.begin() + s->as_next_offset[i], s->as_next.begin() + s->as_next_offset[i + 1], nearest_first);
    std::sort(s->as_prev.begin() + s->as_prev_offset[i], s->as_prev.begin() + s->as_prev_offset[i + 1], nearest_first);
  }
  s->done.resize(static_cast<std::size_t>(n));
  s->spent.resize(static_cast<std::size_t>(n));
  s->retired.resize(static_cast<std::size_t>(n));

  // A frame whose triplet budget ran out is pathological (200 concentric circles): its two-arc
  // candidates would cost as much again, so they are skipped.
  if (!AddTripletCandidates(curves, arcs, options, s, candidates, stats)) return;
  if (options.pair_candidates && options.refine_fit) AddPairCandidates(curves, arcs, options, s, candidates, stats);
}

}  // namespace ellipsekit

// Arc grouping and candidate generation (sec. II-B-3 to II-D-2).
//
// Pairs come from consecutive quadrants counter-clockwise on screen — (I, II), (II, III),
// (III, IV), (IV, I) — and must sit where an ellipse puts them (1 px tolerance, sec. II-B-3):
//   (I, II):   II.max_x <= I.min_x + 1      II lies left of I
//   (II, III): II.max_y <= III.min_y + 1    II lies above III
//   (III, IV): III.max_x <= IV.min_x + 1    III lies left of IV
//   (IV, I):   I.max_y <= IV.min_y + 1      I lies above IV
// and must give a centre (center.h). A triplet is two pairs sharing their middle arc, which yields
// exactly the paper's four kinds (I,II,III), (II,III,IV), (III,IV,I), (IV,I,II); its two pair
// centres must lie within T_c. Then: the triplet centre, Gamma < T_f (midpoint distances),
// parameters (eqs. 8-12), optionally refitted (conic_refine.h), K(tau) > T_l and psi > T_psi
// (refined_circumference_ratio for a refitted ellipse).
// Our addition, Options::pair_candidates (with the refit): after the triplets, each position-tested
// pair, and each pair of opposite quadrants placed as an ellipse puts them (III below-left of I,
// IV below-right of II, 1 px tolerance), both with mid-points within 3 arc extents, is refitted
// and validated the same way (Gamma, K, psi) as a two-arc candidate (Candidate::FromPair).
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "ellipsekit/options.h"
#include "ellipsekit/types.h"
#include "fit/arc.h"
#include "fit/arc_index.h"
#include "fit/conic_refine.h"
#include "fit/parameters.h"

namespace ellipsekit {

// Buffers bounded by a cap are reserved up to min(cap, kMaxReserved) on the first frame: with
// the default caps (all below it) no later frame allocates; a caller who raises a cap past it
// trades that guarantee for the headroom instead of reserving gigabytes up front.
inline constexpr int kMaxReserved = 1 << 16;
std::size_t ReserveFor(int cap);

struct GroupScratch {
  struct Pair {
    int prev, next;  // arc indices; prev is the earlier quadrant counter-clockwise
    Eigen::Vector2d center;  // eqs. 3-7 (Options::center_method)
    double gap;      // ArcEndIndex::EndDistance of the two arcs, px
    // Options::fit_pair_centers: the two arcs' conic fit (RefineEllipse; `fitted` when it gave an
    // ellipse), whose centre T_c may compare too; the pair's two-arc candidate starts from it.
    bool fitted = false;
    Ellipse fit;
  };
  std::vector<int> by_quadrant[5];
  std::vector<Pair> pairs;
  std::vector<int> as_next_offset, as_next;  // CSR: pairs in which arc i is `next`
  std::vector<int> as_prev_offset, as_prev;  // CSR: pairs in which arc i is `prev`
  std::vector<int> order;                    // arc indices, longest first
  std::vector<int> spread;                   // the same, spread over the frame (SpreadOverFrame)
  std::vector<int> rank, cell_count;         // SpreadOverFrame's scratch
  std::vector<std::uint32_t> cell_key;
  std::vector<std::pair<double, int>> near;  // one arc's pairing partners: (end distance, arc)
  std::vector<int> done;                     // per middle arc: its triplets visited so far
  std::vector<int> spent;                    // per middle arc: its triplets examined so far
  std::vector<std::uint8_t> retired;         // per arc: part of a found candidate
  ArcEndIndex index;
  ParameterScratch params;

  // Sizes every buffer for the worst case of a width x height frame under `options`' caps, so
  // no later frame of that size grows them.
  void Reserve(int width, int height, const Options& options);
};

// The edge coverage (fit/edge_coverage.h) a triplet that passed T_c only by its pairs' fits
// (Candidate::centres_by_fit) must reach, where min_edge_coverage asks less: between a triplet's
// 0.7 and a pair's 0.9. Measured (correct / detected, `ellipsekit eval`), 0.7 (none) / 0.8 / 0.9:
// su2019_coin 69/81, 67/78, 66/77; edcircles_mini 36/38, 35/36, 34/35; scenes seed 11 538/600,
// 538/591, 535/582, seed 23 530/573, 530/567, 528/563; hard tabletop seed 1 708/825, 698/810,
// 689/796. At 0.8 every set is within one detection of the paper's T_c or above it
// (docs/detection.md).
inline constexpr double kCentresByFitMinEdgeCoverage = 0.8;

struct GroupStats {
  int pairs = 0, triplets = 0;
  unsigned caps_hit = 0;  // CapFlags
};

// Appends validated candidates (score = K(tau) + psi) to `candidates`.
void FindCandidates(const Curves& curves, const std::vector<Arc>& arcs, const Options& options,
                    GroupScratch* scratch, std::vector<Candidate>* candidates, GroupStats* stats);

}  // namespace ellipsekit

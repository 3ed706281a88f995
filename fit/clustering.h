// Clustering of duplicate candidates (sec. II-D-3, eq. 17): candidates ranked by score
// (K(tau) + psi(tau), best first); each joins the first kept ellipse whose feature distance
//   D = sqrt(dcx^2 + dcy^2 + dA^2 + dB^2 + drho^2)      (px, px, px, px, rad; drho wrapped mod pi)
// is below T_s (or, with ClusterRule::kRelative, is within a tolerance relative to its size), or
// else is kept as a new cluster reference. Our addition: a cluster whose members include the
// reference's outer rim (IsOuterRim) within cluster_outer_margin of its score is represented by
// the best such rim: a can, cup or cap top shows a lip as two nested similar ellipses, and the
// outer one is the object's boundary, which a grasp needs (see Options).
#pragma once

#include <vector>

#include "ellipsekit/options.h"
#include "ellipsekit/types.h"
#include "fit/arc.h"
#include "fit/uniform_grid.h"

namespace ellipsekit {

// Nested-rim geometry, our addition: `outer` is concentric with `inner` (centres within
// kRimCentreTolerance * inner.b), larger by a factor (a + b) in [kRimMinScale, kRimMaxScale], and
// of the same shape (b/a within kRimAxisRatioTolerance, orientation within
// kRimOrientationTolerance rad unless both are nearly round).
inline constexpr double kRimCentreTolerance = 0.1;
inline constexpr double kRimMinScale = 1.08;
inline constexpr double kRimMaxScale = 1.45;
inline constexpr double kRimAxisRatioTolerance = 0.05;
inline constexpr double kRimOrientationTolerance = 0.2;
bool IsOuterRim(const Ellipse& outer, const Ellipse& inner);
// The first two of those, whatever the shapes: concentric and larger by a factor in [kRimMinScale,
// kRimMaxScale]. The closed outlines (runtime/detector_crowd.cc) drop a fit inside such a rim: a
// cup's inner lip differs from its rim by 0.05-0.07 in b / a.
bool SurroundsAsRim(const Ellipse& outer, const Ellipse& inner);

// A ledge below a top, our addition: `ledge` is at least kLedgeMinScale larger than `top` (a + b)
// and centred at least kLedgeMinDrop * top.b lower along top's minor axis (fit/edge_refit.h
// MinorAxisUp); top is not nearly round and at least kLedgeMinTopB px in b. A lidded jar's
// shoulder around its lid is such a ledge; a can's rim around its recessed lid sits higher, a
// cup's lip level with its inner edge. The ledge often fits the edges more tightly than the top
// (a strong edge against the body) but is another ellipse, never the top's representative
// (ClusterCandidates). Measured (correct, `ellipsekit eval DIR`), without the rule -> with it:
// hard tabletop seed 1 701 -> 702, held-out seed 2 721 -> 726, its 1280x720 frames 820 -> 825,
// with bottles seeds 1 / 2 688 / 645 -> 692 / 654, scenes seeds 7 / 11 / 23 524 / 538 / 530 ->
// 525 / 539 / 531, can layout 1800 -> 1801; the crowded and cluttered sets, the other layouts and
// 150 small rings unchanged; the shared sets at 0.5x-3x keep every correct detection
// (prasad_subset at 3x one false one more).
// Scale 1.05 instead of 1.1: crowded seeds 1 / 2 -5 / -18, clutter seed 2 -20, ring layout -13.
// No bound on b: 150 small rings (b 4-8 px, docs/crowded-scenes.md) 3970 -> 3898, their fits'
// centres err by as much as the drop; 15 px instead of 10: hard seed 1 701, bottles 688 / 649.
inline constexpr double kLedgeMinScale = 1.1;
inline constexpr double kLedgeMinDrop = 0.1;
inline constexpr double kLedgeMinTopB = 10.0;
bool IsLedgeBelow(const Ellipse& ledge, const Ellipse& top);

double FeatureDistance(const Ellipse& v, const Ellipse& w);

// True when v and w are the same ellipse under options.cluster_rule.
bool SameEllipse(const Ellipse& v, const Ellipse& w, const Options& options);

// The edge-map checks of the clustering (the detector's edge coverage), asked lazily: only of
// candidates that would found or represent a cluster, so most duplicates are never checked.
// Leaving failing candidates out this way gives the same result as removing them first.
class CandidateCheck {
 public:
  // Whether c may found or represent a cluster.
  virtual bool Passes(const Candidate& c) const = 0;
  // How tightly the edge map backs c's outline (higher is better): ranks the members of a cluster
  // under Options::cluster_pick_best_fit. May return any value <= to_beat once it cannot beat it.
  virtual double FitShare(const Candidate& c, double to_beat) const = 0;
  // A candidate that failed Passes, given a second chance: true when its ellipse refitted to the
  // edges along its outline passes; the refit then replaces c->ellipse. False leaves c as it was
  // (and is all a check without a second chance answers).
  virtual bool PassesRefitted(Candidate* c) const {
    (void)c;
    return false;
  }

 protected:
  ~CandidateCheck() = default;
};

// The clustering's scratch: cluster references by the grid cell of their centres, so each
// candidate is compared with the references near it only (identical result to comparing it with
// all of them, in time that grows with the candidates, not candidates x clusters). Sized from the
// candidates' spread: at most kMaxCells x kMaxCells cells of >= kMinCellPx px.
struct ClusterScratch {
  static constexpr double kMinCellPx = 32;
  static constexpr double kMaxCells = 256;
  // Candidates linked by the grid cell of their centres: per cell the last one added, per
  // candidate the one added before it in its cell.
  struct CellLists {
    std::vector<int> head, next;
    void Reset(int cells, std::size_t candidates);
    void Add(const UniformGrid& grid, int k, const Ellipse& e);
    // The smallest k linked here with SameEllipse(e, items[k].ellipse), or -1. SameEllipse(v, w)
    // implies centres within `reach` (eq. 17: D >= the centre distance; kRelative: within
    // cluster_relative * b), so the smallest match among the cells near e is the smallest of all.
    template <typename WithEllipse>
    int FirstSame(const UniformGrid& grid, const std::vector<WithEllipse>& items, const Ellipse& e,
                  const Options& options) const {
      const double reach = options.cluster_rule == ClusterRule::kFeatureDistance ? options.cluster_distance
                                                                                 : options.cluster_relative * e.b;
      const int cx0 = grid.Column(e.cx - reach), cx1 = grid.Column(e.cx + reach);
      const int cy0 = grid.Row(e.cy - reach), cy1 = grid.Row(e.cy + reach);
      int first = -1;
      for (int y = cy0; y <= cy1; ++y) {
        for (int x = cx0; x <= cx1; ++x) {
          for (int k = head[static_cast<std::size_t>(y) * grid.cols + x]; k >= 0; k = next[k]) {
            if ((first < 0 || k < first) && SameEllipse(e, items[k].ellipse, options)) first = k;
          }
        }
      }
      return first;
    }
  };
  // What a second chance needs of a candidate that failed (a Candidate is ~3x larger).
  struct Failed {
    Ellipse ellipse;
    int arcs[3];
    bool centres_by_fit;
  };
  UniformGrid grid;
  CellLists references;         // indices into the candidates: the cluster references
  std::vector<Failed> failed;   // would-be references that failed the check, best score first
  CellLists hopeless;           // indices into `failed`: those whose second chance failed

  // Room for `candidates` candidates on the finest grid, so no later frame grows a buffer.
  void Reserve(std::size_t candidates);
  void Start(const std::vector<Candidate>& candidates);
};

// Sorts `candidates` by score (in place) and moves the cluster references to its front;
// returns how many there are. With `check`, candidates failing it are left out, and with
// options.cluster_pick_best_fit each cluster is represented by the member (outer and inner rims of
// its reference aside) with the highest FitShare, keeping the reference's score; an outer rim
// chosen for the cluster (see above) still takes precedence.
// Then, with `check` and options.rescue_min_coverage <= 1, each candidate that would have founded
// a cluster but failed the check, and that no cluster holds, gets a second chance
// (CandidateCheck::PassesRefitted), best score first: the refitted ellipse founds a cluster of
// its own (Candidate::rescued) unless a cluster holds it. A rescued cluster never takes a member
// or the place of one that passed as it was.
// `scratch` (optional) keeps the buffers between frames.
int ClusterCandidates(std::vector<Candidate>* candidates, const Options& options,
                      const CandidateCheck* check = nullptr, ClusterScratch* scratch = nullptr);

}  // namespace ellipsekit

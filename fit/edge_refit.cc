#include "fit/edge_refit.h"

#include <cstddef>

#include "fit/arc.h"
#include "fit/clustering.h"
#include "fit/conic_refine.h"
#include "fit/point_moments.h"

namespace ellipsekit {

namespace {
constexpr int kMinPoints = 12;
}  // namespace

void EdgeRefitScratch::Reserve(int width, int height) {
  const std::size_t room = 8 * (static_cast<std::size_t>(width) + height);
  x.reserve(room);
  y.reserve(room);
}

bool FitToEdgesNear(const EdgeMapView& in, double distance, EdgeRefitScratch* scratch, Ellipse* e) {
  const int n = EdgePointsNear(in, *e, distance, &scratch->x, &scratch->y);
  if (n < kMinPoints) return false;
  Arc points;  // RefineEllipse reads only the moments
  points.moments = MomentsOfPoints(scratch->x.data(), scratch->y.data(), 0, n - 1, scratch->x[0], scratch->y[0]);
  const Arc* group[1] = {&points};
  return RefineEllipse(group, 1, e);
}

bool RefitToEdges(const EdgeMapView& in, Ellipse* e, EdgeRefitScratch* scratch) {
  const double share = FineEdgeCoverage(in, *e);
  if (share < kEdgeRefitMinShare) return false;
  Ellipse refit = *e;
  if (!FitToEdgesNear(in, kEdgeRefitDistance, scratch, &refit)) return false;
  if (!(FeatureDistance(refit, *e) < 0.2 * e->b + 1)) return false;
  if (FineEdgeCoverage(in, refit) < share) return false;
  *e = refit;
  return true;
}

}  // namespace ellipsekit

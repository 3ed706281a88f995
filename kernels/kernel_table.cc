#include "kernels/kernel_table.h"

#include "kernels/arc_stats.h"
#include "kernels/canny_thresholds.h"
#include "kernels/edge_sign.h"
#include "kernels/gaussian.h"
#include "kernels/hysteresis.h"
#include "kernels/nms.h"
#include "kernels/sobel.h"

namespace ellipsekit {

const KernelTable& ScalarKernels() {
  static const KernelTable table = [] {
    KernelTable t;
    t.backend = Backend::kScalar;
    t.gaussian = scalar::Gaussian;
    t.sobel = scalar::Sobel;
    t.magnitude_histogram = scalar::MagnitudeHistogram;
    t.nms = scalar::Nms;
    t.hysteresis = scalar::Hysteresis;
    t.edge_sign = scalar::EdgeSign;
    t.polyline = scalar::Polyline;
    t.arc_split = scalar::ArcSplit;
    t.arc_stats = scalar::ArcStatsFromSplits;
    return t;
  }();
  return table;
}

}  // namespace ellipsekit

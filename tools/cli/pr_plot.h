// `ellipsekit eval --curve FILE.png`: the precision-recall curve drawn as a PNG (and the points
// as CSV beside it).
#pragma once

#include <string>

#include "tools/eval/pr_curve.h"

namespace ellipsekit::cli {

// Writes `png` (640x480: recall on x, precision on y, both 0..1; the curve, the operating point
// of the full detection list marked, AP in the title) and `csv` (threshold,precision,recall per
// point), each atomically. False and *error on failure.
bool WritePrCurve(const eval::PrCurve& curve, const std::string& title, const std::string& png,
                  const std::string& csv, std::string* error);

}  // namespace ellipsekit::cli

// End to end: detect/<backend>/<prasad|photos|scenes>/<image>, opencv_canny_image/<set>/<image>,
// detect/<backend>/scenes200 and opencv_canny_image/scenes200 (names in ellipsekit_bench.cc).
#pragma once

#include <vector>

#include <opencv2/core.hpp>

namespace ellipsekit::bench {

void RegisterEndToEndBenchmarks();

// The 200 scenes of `ellipsekit scenes --count 200 --seed 7` (640x480), rendered on first use;
// empty in a build without tools/scenes.
const std::vector<cv::Mat>& GeneratedScenes200();

}  // namespace ellipsekit::bench

// End to end: detect/<backend>/<prasad|photos|scenes>/<image>, opencv_canny_image/<set>/<image>,
// detect/<backend>/scenes200 and opencv_canny_image/scenes200 (names in ellipsekit_bench.cc).
#pragma once

namespace ellipsekit::bench {

void RegisterEndToEndBenchmarks();

}  // namespace ellipsekit::bench

// stream/<backend>/scenes200/depth:<d>: a Stream (include/ellipsekit/stream.h) over the 200
// generated scenes, against detect/<backend>/scenes200 one frame after another.
#pragma once

namespace ellipsekit::bench {

// Registers stream/<scalar|simd|vulkan>/scenes200/depth:<2|3>.
void RegisterStreamBenchmarks();

}  // namespace ellipsekit::bench

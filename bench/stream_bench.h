// stream/<backend>/scenes200/depth:<d>: a Stream (include/ellipsekit/stream.h) over the 200
// generated scenes; stream/<backend>/scenes200/detect: detect() over them one frame after another,
// with the same counters, so `--benchmark_filter='^stream/'` runs a stream and its baseline together.
#pragma once

namespace ellipsekit::bench {

// Registers stream/<scalar|simd|vulkan>/scenes200/<detect|depth:2|depth:3>.
void RegisterStreamBenchmarks();

}  // namespace ellipsekit::bench

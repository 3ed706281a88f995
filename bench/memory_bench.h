// memory/<backend>/<W>x<H>: the heap a Detector holds after its first frame of a size, per pixel
// (issue "Figures a reviewer can trust": <= 32 bytes per pixel plus what the caps need).
#pragma once

namespace ellipsekit::bench {

// Registers memory/<scalar|simd|vulkan>/<640x480|1920x1080>.
void RegisterMemoryBenchmarks();

}  // namespace ellipsekit::bench

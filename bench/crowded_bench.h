// detect/crowded/<n>: Detector::detect (best backend: SIMD) on crowded 1280x720 frames of n
// objects, for the flat-cost claim of the crowded-scene grouping (README "Crowded scenes").
#pragma once

namespace ellipsekit::bench {

// Registers detect/crowded/<n> for n = 25, 100, 300 (no-op in a build without tools/scenes).
void RegisterCrowdedBenchmarks();

}  // namespace ellipsekit::bench

// One iteration detects four 1280x720 crowded frames of n objects each — a dot grid, a crate of
// can tops, a tray of caps and a tray of open cups (RenderCrowdedScene(1, ...)), one truth ellipse
// per object — on one Detector (kAuto). Counters: ms_per_ellipse (wall time per truth ellipse),
// found (truth ellipses matched by a detection's centre within 0.2 b and axes within 10 %: a
// cheap sanity figure; `ellipsekit eval` scores by Jaccard overlap) and truth.
#include "bench/crowded_bench.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <string>
#include <vector>

#include "ellipsekit/detector.h"
#ifdef ELLIPSEKIT_BENCH_HAVE_SCENES
#include "tools/scenes/crowded_scenes.h"
#endif

namespace ellipsekit::bench {

#ifdef ELLIPSEKIT_BENCH_HAVE_SCENES
namespace {

struct CrowdedSet {
  std::vector<scenes::Scene> frames;
  int truth = 0;
};

const CrowdedSet& Frames(int n) {
  static std::vector<std::pair<int, CrowdedSet>> cache;
  for (const auto& [k, set] : cache)
    if (k == n) return set;
  CrowdedSet set;
  for (scenes::CrowdedLayout layout : {scenes::CrowdedLayout::kDotGrid, scenes::CrowdedLayout::kCanCrate,
                                       scenes::CrowdedLayout::kCapTray, scenes::CrowdedLayout::kCupTray}) {
    scenes::CrowdedSceneOptions o;
    o.width = 1280;
    o.height = 720;
    o.layout = layout;
    o.objects = n;
    set.frames.push_back(scenes::RenderCrowdedScene(1, o));
    set.truth += static_cast<int>(set.frames.back().truth.size());
  }
  cache.emplace_back(n, std::move(set));
  return cache.back().second;
}

int Found(const std::vector<Ellipse>& detected, const std::vector<Ellipse>& truth) {
  int found = 0;
  for (const Ellipse& t : truth) {
    for (const Ellipse& d : detected) {
      if (std::hypot(d.cx - t.cx, d.cy - t.cy) < 0.2 * t.b && std::abs(d.a - t.a) < 0.1 * t.a &&
          std::abs(d.b - t.b) < 0.1 * t.b) {
        ++found;
        break;
      }
    }
  }
  return found;
}

void BM_DetectCrowded(benchmark::State& st, int n) {
  const CrowdedSet& set = Frames(n);
  Detector detector;
  if (!detector.status().ok()) {
    st.SkipWithError(detector.status().message().c_str());
    return;
  }
  DetectionResult r;
  int found = 0;
  for (auto _ : st) {
    found = 0;
    for (const scenes::Scene& s : set.frames) {
      const ImageView view{s.gray.data, s.gray.cols, s.gray.rows, static_cast<std::ptrdiff_t>(s.gray.step[0])};
      if (!detector.detect(view, &r).ok()) {
        st.SkipWithError("detect failed");
        return;
      }
      found += Found(r.ellipses, s.truth);
    }
  }
  using C = benchmark::Counter;
  st.counters["ms_per_ellipse"] = C(set.truth / 1e3, C::kIsIterationInvariantRate | C::kInvert);
  st.counters["found"] = found;
  st.counters["truth"] = set.truth;
}

}  // namespace
#endif

void RegisterCrowdedBenchmarks() {
#ifdef ELLIPSEKIT_BENCH_HAVE_SCENES
  for (int n : {25, 100, 300}) {
    benchmark::RegisterBenchmark(("detect/crowded/" + std::to_string(n)).c_str(),
                                 [n](benchmark::State& st) { BM_DetectCrowded(st, n); })
        ->UseRealTime()
        ->Unit(benchmark::kMillisecond);
  }
#endif
}

}  // namespace ellipsekit::bench

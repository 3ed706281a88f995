// The pyramid around one level's detection (Options::pyramid_level, coarse_levels): the working
// level and its reduction before the pixel stage; the coarser levels and the frame's coordinates
// after the back end.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "fit/image_refit.h"
#include "kernels/pyramid_down.h"
#include "runtime/detector_impl.h"

namespace ellipsekit {

namespace {

using Clock = std::chrono::steady_clock;

double Ms(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

}  // namespace

// Options::pyramid_level (-1: the first level of at most pyramid_max_pixels), never one whose
// shorter side is below kMinPyramidSide px.
int Detector::Impl::PyramidLevel(const ImageView& input) const {
  auto pixels = [&](int l) { return static_cast<long long>(input.width >> l) * (input.height >> l); };
  int level = 0;
  while (level < kMaxPyramidLevel && std::min(input.width, input.height) >> (level + 1) >= kMinPyramidSide &&
         (options.pyramid_level < 0 ? pixels(level) > options.pyramid_max_pixels : level < options.pyramid_level))
    ++level;
  return level;
}

// Level `level` of the input's pyramid (the input itself at 0), in Impl::pyramid.
ImageView Detector::Impl::Reduce(const ImageView& input, int level) {
  ImageView v = input;
  for (int l = 0; l < level; ++l) {
    const std::size_t n = static_cast<std::size_t>(v.width / 2) * (v.height / 2);
    if (pyramid[l].size() < n) pyramid[l].resize(n);  // on the first frame of a size, or a larger one
    scalar::PyramidDown(v.data, v.stride, v.width, v.height, pyramid[l].data(), v.width / 2);
    v = {pyramid[l].data(), v.width / 2, v.height / 2, v.width / 2};
  }
  return v;
}

namespace {

// Ellipses of level `from` in the coordinates of level `to` (< from).
void ScaleUp(int from, int to, std::vector<Ellipse>* ellipses) {
  if (from == to) return;
  for (Ellipse& e : *ellipses) {
    e.cx = PyramidUp(e.cx, from - to);
    e.cy = PyramidUp(e.cy, from - to);
    e.a *= 1 << (from - to);
    e.b *= 1 << (from - to);
  }
}

}  // namespace

Status Detector::Impl::PixelStage(const ImageView& input) {
  const auto start = Clock::now();
  front.input = input;
  front.level = PyramidLevel(input);
  front.image = Reduce(input, front.level);
  const double reduce_ms = Ms(start, Clock::now());
  const Status st = PixelStageAt(front.image);
  front.total_ms = reduce_ms;
  return st;
}

Status Detector::Impl::BackEnd(DetectionResult* r) {
  const auto start = Clock::now();
  const double front_ms = front.total_ms;  // the reduction; BackEndAt counts the level's stages
  // Arcs run in the pixel stage on the device, else inside BackEndAt (and so inside `start`'s span).
  const bool arcs_in_front = front.arcs_done;
  BackEndAt(r);
  AddCrowdPass(r);
  const int level = front.level;
  ImageView image = front.image;
  claimed_near.clear();
  // r->ellipses[found_by[l - 1], found_by[l]) were found on level `level` + l, l < levels.
  int found_by[kMaxPyramidLevel + 1] = {static_cast<int>(r->ellipses.size())};
  int levels = 1;
  // Options::coarse_levels: the next levels too, each by a Detector of its own (its buffers keep
  // their size), their ellipses added unless one of the finer levels already holds them. Not on a
  // frame whose working level reached a cap: that frame has done the most work a frame may cost.
  // Coarse level c + 1 runs on a working frame of at least coarse_min_pixels x 4^c pixels (measured
  // in docs/resolution.md: a second level on 1280x720 frames cost 8 % and added nothing).
  const long long pixels = static_cast<long long>(image.width) * image.height;
  for (int c = 0; r->caps_hit == kCapNone && c < options.coarse_levels &&
                  pixels >= (static_cast<long long>(options.coarse_min_pixels) << (2 * c)) &&
                  std::min(image.width, image.height) / 2 >= kMinPyramidSide;
       ++c) {
    if (!coarse[c]) {
      coarse[c] = std::make_unique<Impl>();
      coarse[c]->options = options;
      coarse[c]->kernels = kernels;
      coarse[c]->coarse_level = true;
      coarse[c]->options.pyramid_level = 1;  // it reduces the level above it once (Reduce)
      coarse[c]->options.coarse_levels = 0;
      // Budgets follow the level's pixels (a quarter per level): the caps bound the work of the
      // whole pyramid at ~4/3 of the working level's, not twice it.
      for (int* cap : {&coarse[c]->options.max_arcs, &coarse[c]->options.max_pairs, &coarse[c]->options.max_triplets,
                       &coarse[c]->options.max_candidates}) {
        *cap = std::max(1, *cap >> (2 * (c + 1)));
      }
    }
    const Status st = coarse[c]->PixelStage(image);
    if (!st.ok()) return st;
    image = coarse[c]->front.image;
    coarse[c]->BackEndAt(&coarse_result);
    ScaleUp(level + c + 1, level, &coarse_result.ellipses);
    // Added only when level `level`'s edges, less those of the ellipses found so far, back it
    // along min_edge_coverage of its outline: the finer levels' checks (exclusive support, outer
    // rims) never saw it, and a coarse ellipse through a top and the side below it shares the top's
    // edges. Measured in docs/resolution.md.
    // Only the ellipses near a new one claim their edges (each once): claims farther away than
    // kClaimReach cannot touch its coverage.
    claimed_near.resize(r->ellipses.size(), 0);
    for (const Ellipse& e : coarse_result.ellipses) {
      if (FoundAlready(r->ellipses.data(), r->ellipses.size(), e)) continue;
      const Box reach = BoundingBox(e, kClaimReach);
      for (std::size_t i = 0; i < r->ellipses.size(); ++i) {
        if (claimed_near[i] || !reach.Intersects(BoundingBox(r->ellipses[i], kClaimReach))) continue;
        ClaimEdges(EdgeView(), r->ellipses[i], &claims);
        claimed_near[i] = 1;
      }
      if (EdgeCoverage(EdgeView(), e, options.min_edge_coverage, &claims) < options.min_edge_coverage) continue;
      r->ellipses.push_back(e);
      claimed_near.push_back(1);
      ClaimEdges(EdgeView(), e, &claims);
    }
    found_by[levels++] = static_cast<int>(r->ellipses.size());
  }
  ScaleUp(level, 0, &r->ellipses);
  claims.Clear();
  // Options::refit_to_image: what a reduced level found, refitted to the frame itself.
  for (int l = 0, begin = 0; options.refit_to_image && l < levels; begin = found_by[l++]) {
    for (int i = begin; level + l > 0 && i < found_by[l]; ++i) RefitToImage(front.input, level + l, &r->ellipses[i]);
  }
  // The reduction, the level's pixel stage, and everything since (back end, coarser levels).
  const StageTimings& t = r->timings;
  r->timings.total_ms =
      front_ms + t.edges_ms + t.curves_ms + (arcs_in_front ? t.arcs_ms : 0.0) + Ms(start, Clock::now());
  return Status::Ok();
}

}  // namespace ellipsekit

// The arc stage on a Vulkan compute device: polyline -> arc_split -> arc_stats over every curve of a
// frame, bit-identical to the scalar references (kernels/polyline.h, arc_split.h, arc_stats.h: all
// integer, the products in int64, so the device needs the shaderInt64 feature).
//
// Work split: one shader invocation per curve in each of the three shaders (a curve's
// Ramer-Douglas-Peucker recursion and its arc walk are sequential; curves are independent), in
// workgroups of 8 (measured on lavapipe, 2 cores: 64 per group left one core with the longest
// curves; 8 took the scene-0 frame's device time from 4.9 to 3.2 ms).
// Storage: struct-of-arrays storage buffers mirroring Curves / Polylines / Splits / ArcStats. Output
// sizes are not known before the shaders run, so every per-curve output has a slot range bounded by
// the curve's own points: curve c (points [offset[c], offset[c + 1]), non-empty) writes its
// vertices, splits and arcs at slots offset[c] + 0, 1, ... (vertices <= length, splits <
// length, arcs <= max(1, vertices - 2) <= length), its RDP stack at 2 * offset[c] .. 2 * offset[c + 1],
// and its three counts to a counts buffer. So the three dispatches chain with no host round trip.
// Compaction: after the last submit, the host prefix-sums the per-curve counts into the offsets of
// Polylines / Splits and copies each curve's run out of the downloaded slots (last_compact_ms():
// measured 0.02-0.04 ms for 496 curves / 15.7k points, about 1% of the device time on lavapipe, so
// a device-side scan would not pay for its extra dispatches here).
//
// Bounded work per dispatch: each shader runs at most kStepsPerDispatch steps per curve in one flat
// loop and keeps its place in a per-curve state record (lavapipe ends a loop nest after 65535
// iterations; GPU drivers reset dispatches that run too long). A curve moves through phases
// polyline -> arc_split -> arc_stats -> done; a round is the three dispatches with barriers, and a
// shader leaves curves in other phases alone (a curve not yet in its phase is "pending").
// Invocations take the curves longest first (a host sort of the curve indices), so the invocations
// of one SIMD group loop about equally long.
// Per Run: one host-visible staging upload (x, y, packed gx|gy, offset, sign_class, order), one command
// buffer: upload copies -> kRoundsPerSubmit rounds -> downloads of the counts and slot arrays into
// one host-visible buffer; one fence wait. Device timestamps around each submit only when asked for
// (set_timing): on lavapipe a timestamp costs about what a dispatch does (docs/vulkan.md). Only when a curve is still pending after that (RDP is
// O(length^2) steps in the worst case; every dataset frame finishes in the first submit) does a
// second command buffer run kRoundsPerSubmit more rounds + the downloads, as often as needed
// (bounded: each round advances every pending curve by kStepsPerDispatch steps).
// Buffers grow (to the next power of two of points and of curves) only when a frame has more than
// any before, and are reused otherwise: no allocation after the first frame of that size. Outputs are
// appended with insert/push_back into the caller's vectors, which allocate only if their capacity is
// short (the Detector reserves them for the frame's worst case).
// Not thread-safe: one thread at a time per instance (like a Detector).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "ellipsekit/types.h"
#include "kernels/arc_split.h"
#include "kernels/arc_types.h"
#include "kernels/polyline.h"
#include "runtime/vulkan_context.h"
#include "runtime/vulkan_program.h"

namespace ellipsekit {

class VulkanArcStage {
 public:
  static constexpr int kRoundsPerSubmit = 1;
  static constexpr std::uint32_t kStepsPerDispatch = 32768;  // per curve and shader; < 65535 (lavapipe)

  // kUnavailable with the reason when there is no Vulkan loader or usable device, or the device
  // lacks shaderInt64. ELLIPSEKIT_VK_DISABLE_INT64=1 makes it answer as if the device lacked it
  // (to test the fallback on machines whose device has it). With `ctx` (e.g. the edge stage's
  // context()), the stage runs on that instance/device and shares ownership of it; without, it
  // opens its own. Either way the same thread must drive every stage of one context.
  static Status Create(std::unique_ptr<VulkanArcStage>* out, std::shared_ptr<VulkanContext> ctx = nullptr);
  ~VulkanArcStage();
  VulkanArcStage(const VulkanArcStage&) = delete;
  VulkanArcStage& operator=(const VulkanArcStage&) = delete;

  // The three kernels on `curves` (every curve non-empty, offsets consistent: else
  // kInvalidArgument): *polylines and *splits are replaced, as scalar::Polyline / ArcSplit do;
  // the arcs are appended to *stats, as scalar::ArcStatsFromSplits does. kUnavailable when the
  // frame's buffers exceed the device's storage-buffer range (the caller may run the CPU kernels).
  Status Run(const Curves& curves, std::int32_t tol_q16, std::int64_t tan_q16, int min_points, Polylines* polylines,
             Splits* splits, std::vector<ArcStats>* stats);

  // Device timestamps around each submit, off by default: on lavapipe they cost time of their own
  // (docs/vulkan.md), so only a caller that reads last_device_ms() turns them on.
  void set_timing(bool on) { timing_ = on; }
  // Device time of the last Run (GPU timestamps, transfers included); -1 when timing is off or
  // the queue has no timestamps.
  double last_device_ms() const { return last_device_ms_; }
  // Host time of the last Run's prefix sum + compaction into the output structs.
  double last_compact_ms() const { return last_compact_ms_; }
  // Rounds (polyline, arc_split, arc_stats dispatches) the last Run recorded: a multiple of
  // kRoundsPerSubmit, more than kRoundsPerSubmit only when a curve needed more steps.
  int last_rounds() const { return last_rounds_; }
  const std::string& device_name() const { return ctx_->device_name(); }

 private:
  enum Pipeline { kPolyline, kArcSplit, kArcStats, kNumPipelines };
  static constexpr int kNumBindings = 13;

  VulkanArcStage() = default;
  Status Init();
  Status Reserve(std::int64_t points, std::int64_t curves);
  void ReleaseBuffers();
  void Dispatch(VkCommandBuffer cb, Pipeline p, std::uint32_t curves);
  void RecordRoundsAndDownload(VkCommandBuffer cb);
  Status Submit(VkCommandBuffer cb, double* device_ms);
  Status Compact(const Curves& curves, Polylines* polylines, Splits* splits, std::vector<ArcStats>* stats);

  std::shared_ptr<VulkanContext> ctx_;
  // Layouts, pipelines (indexed by Pipeline), the set, command buffers 0 (first submit) and 1
  // (more rounds), fence, timestamps. Declared after ctx_, so it is released before it.
  VulkanProgram program_;

  // Bindings 0..11: x, y, g (gx | gy << 16), offset, sign_class, stack, vertex slots, split slots,
  // arc slots (17 planes of `points` words), counts (3 planes of `curves` words), per-curve state
  // (16 words each), all device-local; pending flags (one per round of a submit, host-visible);
  // order (invocation -> curve, longest curve first).
  VulkanBuffer buffers_[kNumBindings];
  VulkanBuffer upload_, download_;
  std::int64_t cap_points_ = 0, cap_curves_ = 0;
  std::uint32_t push_[8] = {};
  std::vector<std::int32_t> order_;  // sized with the buffers (Reserve), sorted per Run
  double last_device_ms_ = -1, last_compact_ms_ = 0;
  int last_rounds_ = 0;
  bool timing_ = false;
};

}  // namespace ellipsekit

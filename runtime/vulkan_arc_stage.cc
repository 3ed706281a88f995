#include "runtime/vulkan_arc_stage.h"

#include <stdint.h>  // the generated SPIR-V headers use ::uint32_t

#include <algorithm>
#include <bit>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <string>

#include "shaders/arc_split.spv.h"
#include "shaders/arc_stats.spv.h"
#include "shaders/polyline.spv.h"

namespace ellipsekit {

namespace {

enum Binding : int {
  kX, kY, kG, kOffset, kSignClass, kStack, kVertex, kSplit, kArcs, kCounts, kState, kPending, kOrder
};

// Fields of an arc slot, one plane each, in the order of arc_stats.comp's kField* constants.
enum ArcField : int {
  kBegin, kEnd, kX0, kY0, kX1, kY1, kXm, kYm, kMinX, kMinY, kMaxX, kMaxY, kG0x, kG0y, kG1x, kG1y,
  kQuadrantAndClass, kNumArcFields
};

constexpr std::uint32_t kGroup = 8;         // local_size_x of the three shaders: curves per workgroup
constexpr std::uint32_t kMaxGroups = 65535;  // guaranteed maxComputeWorkGroupCount per axis
constexpr std::int64_t kMinPoints = 4096, kMinCurves = 256;  // smallest capacities
constexpr std::uint32_t kStateWords = 16;    // per curve (the shaders' kStateWords)

std::uint32_t CeilDiv(std::uint64_t a, std::uint64_t b) { return static_cast<std::uint32_t>((a + b - 1) / b); }

}  // namespace

Status VulkanArcStage::Create(std::unique_ptr<VulkanArcStage>* out, std::shared_ptr<VulkanContext> ctx) {
  std::unique_ptr<VulkanArcStage> stage(new VulkanArcStage());
  Status st = Status::Ok();
  if (ctx) {
    stage->ctx_ = std::move(ctx);
  } else {
    std::unique_ptr<VulkanContext> own;
    st = VulkanContext::Create(&own);
    if (!st.ok()) return st;
    stage->ctx_ = std::move(own);
  }
  const char* disable = std::getenv("ELLIPSEKIT_VK_DISABLE_INT64");
  const bool disabled = disable != nullptr && std::string(disable) == "1";
  if (!stage->ctx_->shader_int64() || disabled) {
    return {StatusCode::kUnavailable, "Vulkan arc stage unavailable: device '" + stage->ctx_->device_name() +
                                          "' lacks shaderInt64 (64-bit integers in shaders)" +
                                          (disabled ? " (ELLIPSEKIT_VK_DISABLE_INT64=1)" : "")};
  }
  st = stage->Init();
  if (!st.ok()) return st;
  *out = std::move(stage);
  return Status::Ok();
}

Status VulkanArcStage::Init() {
  const VulkanProgram::Shader shaders[kNumPipelines] = {
      {kPolylineSpv, sizeof(kPolylineSpv)}, {kArcSplitSpv, sizeof(kArcSplitSpv)}, {kArcStatsSpv, sizeof(kArcStatsSpv)}};
  return program_.Create(ctx_.get(), kNumBindings, sizeof(push_), shaders, kNumPipelines);
}

void VulkanArcStage::ReleaseBuffers() {
  for (VulkanBuffer& b : buffers_) ctx_->DestroyBuffer(&b);
  ctx_->DestroyBuffer(&upload_);
  ctx_->DestroyBuffer(&download_);
  cap_points_ = cap_curves_ = 0;
}

VulkanArcStage::~VulkanArcStage() {
  if (!ctx_) return;
  ctx_->vk().vkDeviceWaitIdle(ctx_->device());
  ReleaseBuffers();
  // program_ releases its objects next, then ctx_ (if no other stage shares it).
}

// Capacities: the next power of two of the need (at least kMinPoints / kMinCurves), cut back to what
// the device's storage-buffer range allows for the largest binding (the 17 arc planes).
Status VulkanArcStage::Reserve(std::int64_t points, std::int64_t curves) {
  if (points <= cap_points_ && curves <= cap_curves_) return Status::Ok();
  const std::int64_t range = ctx_->properties().limits.maxStorageBufferRange;
  const std::int64_t max_points = range / (4 * kNumArcFields);
  if (points > max_points || curves + 1 > range / 4)
    return {StatusCode::kUnavailable, "Vulkan arc stage: " + std::to_string(points) + " curve points exceed the device's storage buffer range (" +
                                          std::to_string(range) + " bytes)"};
  const std::int64_t cap_p = std::min<std::int64_t>(
      std::max(static_cast<std::int64_t>(std::bit_ceil(static_cast<std::uint64_t>(points))), std::max(cap_points_, kMinPoints)),
      max_points);
  const std::int64_t cap_c = std::min<std::int64_t>(
      std::max(static_cast<std::int64_t>(std::bit_ceil(static_cast<std::uint64_t>(curves))), std::max(cap_curves_, kMinCurves)),
      range / 4 - 1);
  ctx_->vk().vkDeviceWaitIdle(ctx_->device());
  ReleaseBuffers();
  const VkDeviceSize p = static_cast<VkDeviceSize>(cap_p), c = static_cast<VkDeviceSize>(cap_c);
  const VkDeviceSize words[kNumBindings] = {p, p, p, c + 1, c, 2 * p, p, p, kNumArcFields * p, 3 * c,
                                            kStateWords * c, kRoundsPerSubmit, c};
  for (int b = 0; b < kNumBindings; ++b) {
    Status st = ctx_->CreateBuffer(4 * words[b], b == kPending, &buffers_[b]);
    if (!st.ok()) return st;
  }
  Status st = ctx_->CreateBuffer(4 * (3 * p + 3 * c + 1), true, &upload_);
  if (!st.ok()) return st;
  st = ctx_->CreateBuffer(4 * (3 * c + (2 + kNumArcFields) * p), true, &download_);
  if (!st.ok()) return st;

  program_.BindBuffers(buffers_);
  order_.resize(static_cast<std::size_t>(cap_c));
  cap_points_ = cap_p;
  cap_curves_ = cap_c;
  return Status::Ok();
}

// One invocation per curve, spread over a 2-D grid: invocation = gid.y * (groups.x * kGroup) + gid.x.
void VulkanArcStage::Dispatch(VkCommandBuffer cb, Pipeline p, std::uint32_t curves) {
  const std::uint32_t groups = CeilDiv(curves, kGroup);
  const std::uint32_t gx = std::min(groups, kMaxGroups);
  program_.Dispatch(cb, p, sizeof(push_), push_, gx, CeilDiv(groups, gx));
}

// Pending flags cleared; kRoundsPerSubmit x (polyline, arc_split, arc_stats) with a barrier after
// each; downloads of counts | vertex slots | split slots | arc planes (plane stride = this frame's
// points); the closing timestamp (with timing on). The caller begins the command buffer; Submit ends it.
void VulkanArcStage::RecordRoundsAndDownload(VkCommandBuffer cb) {
  const VulkanFunctions& vk = ctx_->vk();
  constexpr VkPipelineStageFlags kCompute = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
  constexpr VkPipelineStageFlags kTransfer = VK_PIPELINE_STAGE_TRANSFER_BIT;
  constexpr VkAccessFlags kRW = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
  vk.vkCmdFillBuffer(cb, buffers_[kPending].buffer, 0, 4 * kRoundsPerSubmit, 0u);
  program_.Barrier(cb, kTransfer, VK_ACCESS_TRANSFER_WRITE_BIT, kCompute, kRW);
  const std::uint32_t nc = push_[0];
  for (int round = 0; round < kRoundsPerSubmit; ++round) {
    push_[6] = static_cast<std::uint32_t>(round);
    for (Pipeline p : {kPolyline, kArcSplit, kArcStats}) {
      Dispatch(cb, p, nc);
      program_.Barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kRW);
    }
  }
  program_.Barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kTransfer, VK_ACCESS_TRANSFER_READ_BIT);
  const VkDeviceSize c = nc, p = push_[1];
  const VkBufferCopy downs[4] = {{0, 0, 12 * c}, {0, 12 * c, 4 * p}, {0, 12 * c + 4 * p, 4 * p},
                                 {0, 12 * c + 8 * p, 4 * kNumArcFields * p}};
  const Binding down_src[4] = {kCounts, kVertex, kSplit, kArcs};
  for (int i = 0; i < 4; ++i) vk.vkCmdCopyBuffer(cb, buffers_[down_src[i]].buffer, download_.buffer, 1, &downs[i]);
  program_.Barrier(cb, kTransfer | kCompute, VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
          VK_ACCESS_HOST_READ_BIT);
  if (timing_) program_.Timestamp(cb, 1);
}

// Ends, submits and waits for `cb`; adds its device time to *device_ms (with timing on).
Status VulkanArcStage::Submit(VkCommandBuffer cb, double* device_ms) {
  const VkResult r = ctx_->vk().vkEndCommandBuffer(cb);
  if (r != VK_SUCCESS) return VulkanFailure("vkEndCommandBuffer", r);
  Status st = program_.SubmitAndWait(cb);
  if (!st.ok()) return st;
  if (timing_) program_.AddDeviceMs(device_ms);
  return Status::Ok();
}

Status VulkanArcStage::Run(const Curves& curves, std::int32_t tol_q16, std::int64_t tan_q16, int min_points,
                           Polylines* polylines, Splits* splits, std::vector<ArcStats>* stats) {
  if (polylines == nullptr || splits == nullptr || stats == nullptr)
    return {StatusCode::kInvalidArgument, "VulkanArcStage::Run: null output"};
  const int nc = curves.size();
  const std::size_t np = curves.x.size();
  if (curves.y.size() != np || curves.gx.size() != np || curves.gy.size() != np ||
      curves.sign_class.size() != static_cast<std::size_t>(nc) || (nc > 0 && (curves.offset[0] != 0 ||
      static_cast<std::size_t>(curves.offset[nc]) != np)))
    return {StatusCode::kInvalidArgument, "VulkanArcStage::Run: inconsistent Curves arrays"};
  for (int c = 0; c < nc; ++c) {
    if (curves.offset[c + 1] <= curves.offset[c])
      return {StatusCode::kInvalidArgument, "VulkanArcStage::Run: curve " + std::to_string(c) + " is empty"};
  }
  polylines->clear();
  splits->clear();
  if (nc == 0) return Status::Ok();
  Status st = Reserve(static_cast<std::int64_t>(np), nc);
  if (!st.ok()) return st;
  const VulkanFunctions& vk = ctx_->vk();
  const VkDeviceSize p = np, c = static_cast<VkDeviceSize>(nc);

  // Upload: x | y | g | offset | sign_class | order, 32-bit words.
  auto* up = static_cast<std::uint32_t*>(upload_.mapped);
  std::memcpy(up, curves.x.data(), 4 * p);
  std::memcpy(up + p, curves.y.data(), 4 * p);
  std::uint32_t* g = up + 2 * p;
  for (std::size_t i = 0; i < np; ++i)
    g[i] = static_cast<std::uint16_t>(curves.gx[i]) | (static_cast<std::uint32_t>(static_cast<std::uint16_t>(curves.gy[i])) << 16);
  std::memcpy(up + 3 * p, curves.offset.data(), 4 * (c + 1));
  std::uint32_t* sign = up + 3 * p + c + 1;
  for (int i = 0; i < nc; ++i) sign[i] = curves.sign_class[i];
  // Invocation -> curve, longest first (ties by index, so the order is deterministic); outputs go
  // to each curve's own slots, so the order changes only which invocation does which curve.
  for (int i = 0; i < nc; ++i) order_[i] = i;
  const std::int32_t* off = curves.offset.data();
  std::sort(order_.begin(), order_.begin() + nc, [off](std::int32_t a, std::int32_t b) {
    const std::int32_t la = off[a + 1] - off[a], lb = off[b + 1] - off[b];
    return la != lb ? la > lb : a < b;
  });
  std::memcpy(sign + c, order_.data(), 4 * c);
  ctx_->FlushHostWrites(upload_);

  push_[0] = static_cast<std::uint32_t>(nc);
  push_[1] = static_cast<std::uint32_t>(np);
  push_[2] = static_cast<std::uint32_t>(tol_q16);
  push_[3] = static_cast<std::uint32_t>(static_cast<std::uint64_t>(tan_q16));
  push_[4] = static_cast<std::uint32_t>(static_cast<std::uint64_t>(tan_q16) >> 32);
  push_[5] = static_cast<std::uint32_t>(min_points);
  push_[6] = 0;  // round: set per dispatch
  push_[7] = kStepsPerDispatch;

  constexpr VkPipelineStageFlags kCompute = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
  constexpr VkPipelineStageFlags kTransfer = VK_PIPELINE_STAGE_TRANSFER_BIT;
  constexpr VkAccessFlags kRW = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
  VkCommandBufferBeginInfo begin{};
  begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  const VkCommandBuffer cb = program_.command_buffer(0), more_rounds_cb = program_.command_buffer(1);
  vk.vkResetCommandBuffer(cb, 0);
  vk.vkBeginCommandBuffer(cb, &begin);
  if (timing_) program_.StartTimestamps(cb, 0, 2);
  // Upload, and every curve to phase 0 (not started). The previous Run's reads are done (fence),
  // so no WAR barrier is needed.
  const VkBufferCopy ups[6] = {{0, 0, 4 * p}, {4 * p, 0, 4 * p}, {8 * p, 0, 4 * p}, {12 * p, 0, 4 * (c + 1)},
                               {4 * (3 * p + c + 1), 0, 4 * c}, {4 * (3 * p + 2 * c + 1), 0, 4 * c}};
  const Binding up_dst[6] = {kX, kY, kG, kOffset, kSignClass, kOrder};
  for (int i = 0; i < 6; ++i) vk.vkCmdCopyBuffer(cb, upload_.buffer, buffers_[up_dst[i]].buffer, 1, &ups[i]);
  vk.vkCmdFillBuffer(cb, buffers_[kState].buffer, 0, 4 * kStateWords * c, 0u);
  program_.Barrier(cb, kTransfer, VK_ACCESS_TRANSFER_WRITE_BIT, kCompute, kRW);
  RecordRoundsAndDownload(cb);
  double device_ms = 0;
  st = Submit(cb, &device_ms);
  if (!st.ok()) return st;

  // More rounds while a curve is pending. Each round advances every pending curve by
  // kStepsPerDispatch steps, and a curve needs at most length^2 + 8 * length + 8 steps in all.
  std::uint64_t longest = 0;
  for (int i = 0; i < nc; ++i) longest = std::max<std::uint64_t>(longest, curves.offset[i + 1] - curves.offset[i]);
  const std::uint64_t max_rounds = (longest * longest + 8 * longest + 8) / kStepsPerDispatch + 2 * kRoundsPerSubmit;
  const auto* pending = static_cast<const volatile std::uint32_t*>(buffers_[kPending].mapped);
  for (std::uint64_t rounds = kRoundsPerSubmit;; rounds += kRoundsPerSubmit) {
    ctx_->InvalidateForHostReads(buffers_[kPending]);
    last_rounds_ = static_cast<int>(rounds);
    if (pending[kRoundsPerSubmit - 1] == 0) break;
    if (rounds >= max_rounds) return {StatusCode::kInternal, "Vulkan arc stage did not finish within its step bound"};
    vk.vkResetCommandBuffer(more_rounds_cb, 0);
    vk.vkBeginCommandBuffer(more_rounds_cb, &begin);
    if (timing_) program_.StartTimestamps(more_rounds_cb, 0, 2);
    RecordRoundsAndDownload(more_rounds_cb);
    st = Submit(more_rounds_cb, &device_ms);
    if (!st.ok()) return st;
  }
  last_device_ms_ = timing_ && program_.timed() ? device_ms : -1;

  ctx_->InvalidateForHostReads(download_);
  const auto t0 = std::chrono::steady_clock::now();
  st = Compact(curves, polylines, splits, stats);
  last_compact_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return st;
}

// The CPU prefix sum: each curve's run of slots, in curve order, appended to the output structs.
// The counts are checked against the slot bounds, so a device fault cannot make us read past them.
Status VulkanArcStage::Compact(const Curves& curves, Polylines* polylines, Splits* splits,
                               std::vector<ArcStats>* stats) {
  const int nc = curves.size();
  const std::size_t np = curves.x.size();
  const auto* down = static_cast<const std::uint32_t*>(download_.mapped);
  const std::uint32_t* num_vertices = down;
  const std::uint32_t* num_splits = down + nc;
  const std::uint32_t* num_arcs = down + 2 * static_cast<std::size_t>(nc);
  const auto* vertex = reinterpret_cast<const std::int32_t*>(down + 3 * static_cast<std::size_t>(nc));
  const std::int32_t* split = vertex + np;
  const std::int32_t* arcs = split + np;
  for (int c = 0; c < nc; ++c) {
    const std::int32_t base = curves.offset[c];
    const std::uint32_t length = static_cast<std::uint32_t>(curves.offset[c + 1] - base);
    if (num_vertices[c] > length || num_splits[c] >= length || num_arcs[c] > length)
      return {StatusCode::kInternal, "Vulkan arc stage: curve " + std::to_string(c) + " reported more outputs than points"};
    polylines->vertex.insert(polylines->vertex.end(), vertex + base, vertex + base + num_vertices[c]);
    polylines->offset.push_back(static_cast<std::int32_t>(polylines->vertex.size()));
    splits->index.insert(splits->index.end(), split + base, split + base + num_splits[c]);
    splits->offset.push_back(static_cast<std::int32_t>(splits->index.size()));
    for (std::uint32_t m = 0; m < num_arcs[c]; ++m) {
      const std::size_t s = static_cast<std::size_t>(base) + m;
      auto field = [&](ArcField f) { return arcs[static_cast<std::size_t>(f) * np + s]; };
      ArcStats a;
      a.curve = c;
      a.begin = field(kBegin); a.end = field(kEnd);
      a.x0 = field(kX0); a.y0 = field(kY0); a.x1 = field(kX1); a.y1 = field(kY1);
      a.xm = field(kXm); a.ym = field(kYm);
      a.min_x = field(kMinX); a.min_y = field(kMinY); a.max_x = field(kMaxX); a.max_y = field(kMaxY);
      a.g0x = field(kG0x); a.g0y = field(kG0y); a.g1x = field(kG1x); a.g1y = field(kG1y);
      const std::uint32_t qc = static_cast<std::uint32_t>(field(kQuadrantAndClass));
      a.quadrant = static_cast<std::int8_t>(qc & 0xff);
      a.sign_class = static_cast<std::uint8_t>(qc >> 8);
      stats->push_back(a);
    }
  }
  return Status::Ok();
}

}  // namespace ellipsekit

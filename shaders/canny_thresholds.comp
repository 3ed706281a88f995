// canny_thresholds: the gradient-magnitude histogram and the automatic thresholds
// (kernels/canny_thresholds.h). Integer only. One SPIR-V module, two pipelines (spec constant MODE):
//
// MODE 0, histogram: hist[m] += #{pixels with mag == m}. Each workgroup counts kPixelsPerGroup
//   pixels into a shared histogram and adds its non-zero bins to binding 5 with atomics, so the
//   counts are exact whatever the order. Binding 5 must be zeroed before (vkCmdFillBuffer).
// MODE 1, select (one workgroup): the scalar rule
//     high = max(min_high, smallest h with 1000 * #{mag <= h} >= high_permille * N),
//     low  = high * low_permille / 1000,
//   with the 64-bit product moved to the host: pc.a = need = ceil(high_permille * N / 1000), and
//   1000 * below >= high_permille * N  <=>  below >= need  for integer below. No h qualifies -> 2040,
//   as in the scalar walk. Writes params[0] = low, params[1] = high (binding 6) for nms.comp.
#version 450
layout(local_size_x = 256) in;
layout(constant_id = 0) const uint MODE = 0u;

const uint kBins = 2041u;            // kMaxMagnitude + 1
const uint kPixelsPerThread = 16u;   // a workgroup counts 256 * 16 pixels per shared histogram
const uint kBinsPerThread = 8u;      // 256 * 8 >= 2041

layout(std430, set = 0, binding = 4) readonly buffer Mag { uint mag[]; };
layout(std430, set = 0, binding = 5) buffer Hist { uint hist[]; };
layout(std430, set = 0, binding = 6) buffer Thresholds { uint params[]; };
layout(push_constant) uniform Params { uint width; uint height; uint a; uint b; uint c; uint d; } pc;

shared uint local_hist[kBins];
shared uint partial[256];

void Histogram() {
  uint lid = gl_LocalInvocationID.x;
  for (uint b = lid; b < kBins; b += 256u) local_hist[b] = 0u;
  barrier();
  uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  uint base = group * 256u * kPixelsPerThread;
  uint n = pc.width * pc.height;
  for (uint j = 0u; j < kPixelsPerThread; ++j) {
    uint i = base + j * 256u + lid;
    if (i < n) atomicAdd(local_hist[min(mag[i], kBins - 1u)], 1u);
  }
  barrier();
  for (uint b = lid; b < kBins; b += 256u) {
    uint v = local_hist[b];
    if (v != 0u) atomicAdd(hist[b], v);
  }
}

void Select() {
  uint lid = gl_LocalInvocationID.x;
  uint sum = 0u;
  for (uint k = 0u; k < kBinsPerThread; ++k) {
    uint b = lid * kBinsPerThread + k;
    if (b < kBins) sum += hist[b];
  }
  partial[lid] = sum;
  barrier();
  if (lid != 0u) return;
  uint need = pc.a;
  uint below = 0u;
  uint h = kBins - 1u;
  bool found = false;
  for (uint t = 0u; t < 256u && !found; ++t) {
    if (below + partial[t] < need) { below += partial[t]; continue; }
    for (uint k = 0u; k < kBinsPerThread; ++k) {
      uint b = t * kBinsPerThread + k;
      if (b >= kBins) break;
      below += hist[b];
      if (below >= need) { h = b; found = true; break; }
    }
  }
  uint high = max(h, pc.c);
  params[0] = high * pc.b / 1000u;
  params[1] = high;
}

void main() {
  if (MODE == 0u) Histogram(); else Select();
}

// canny_thresholds: the gradient-magnitude histogram and the automatic thresholds
// (kernels/canny_thresholds.h), in one dispatch. Integer only.
//
// Histogram: hist[m] += #{pixels with mag == m}, over the in-row pixels of every kRowStep-th row
//   (kHistogramRowStep) of gaussian_sobel.comp's packed int16 dx, dy (rows of pc.d uvec4; mag = |dx| + |dy|).
//   Each workgroup counts 256 * 64 pixels into a shared histogram and adds its non-zero bins to
//   binding 3 with atomics, so the counts are exact whatever the order. Binding 3 (the bins and,
//   after them, the count of finished workgroups) must be zeroed before (vkCmdFillBuffer).
// Select, by the workgroup that finishes last (it counts itself in hist[kBins] after its bins,
//   and the one that sees the count of all the others sees all their bins): the scalar rule
//     high = max(min_high, smallest h with 1000 * #{mag <= h} >= high_permille * N),
//     low  = high * low_permille / 1000,
//   with the 64-bit product moved to the host: pc.a = need = ceil(high_permille * N / 1000), and
//   1000 * below >= high_permille * N  <=>  below >= need  for integer below. No h qualifies -> 2040,
//   as in the scalar walk. Writes params[0] = low, params[1] = high (binding 4) for nms.comp.
//   One dispatch instead of a histogram and a select dispatch: on lavapipe a dispatch costs a
//   wake-up of the driver's worker threads, more than a small frame's whole histogram.
#version 450
layout(local_size_x = 256) in;

const uint kBins = 2041u;            // kMaxMagnitude + 1
const uint kWordsPerThread = 8u;     // a workgroup counts 256 * 8 * 8 pixels per shared histogram
const uint kBinsPerThread = 8u;      // 256 * 8 >= 2041
const uint kRowStep = 4u;            // kHistogramRowStep (kernels/canny_thresholds.h)

layout(std430, set = 0, binding = 1) readonly buffer Dx { uvec4 dx[]; };  // gaussian_sobel.comp layout
layout(std430, set = 0, binding = 2) readonly buffer Dy { uvec4 dy[]; };
// coherent: the last workgroup reads the bins the others added (their atomics) after it saw
// their count.
layout(std430, set = 0, binding = 3) coherent buffer Hist { uint hist[]; };
layout(std430, set = 0, binding = 4) buffer Thresholds { uint params[]; };
layout(push_constant) uniform Params { uint width; uint height; uint a; uint b; uint c; uint d; } pc;

shared uint local_hist[kBins];
shared uint partial[256];
shared bool last_group;

// Signed 16-bit values 0..3 / 4..7 of eight packed in a uvec4 (value 2k in the low half of word k).
ivec4 Lo16(uvec4 v) { return ivec4(uvec4(v.xxyy) << uvec4(16u, 0u, 16u, 0u)) >> 16; }
ivec4 Hi16(uvec4 v) { return ivec4(uvec4(v.zzww) << uvec4(16u, 0u, 16u, 0u)) >> 16; }

void Histogram() {
  uint lid = gl_LocalInvocationID.x;
  for (uint b = lid; b < kBins; b += 256u) local_hist[b] = 0u;
  barrier();
  uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  uint per_row = pc.d;  // uvec4 (8 pixels) per row
  uint total = per_row * ((pc.height + kRowStep - 1u) / kRowStep);  // uvec4 on the counted rows
  for (uint j = 0u; j < kWordsPerThread; ++j) {
    uint q = (group * kWordsPerThread + j) * 256u + lid;
    if (q >= total) continue;
    uint r = q / per_row, col = q - r * per_row;  // counted row r is row kRowStep * r
    int inside = int(pc.width) - int(8u * col);   // pixels of this uvec4 in the row
    // mag = |dx| + |dy| of pixels 0..3 (lo) and 4..7 (hi); pixels past the row end are skipped.
    uint at = kRowStep * r * per_row + col;
    uvec4 gx = dx[at], gy = dy[at];
    uvec4 lo = uvec4(abs(Lo16(gx)) + abs(Lo16(gy))), hi = uvec4(abs(Hi16(gx)) + abs(Hi16(gy)));
    bvec4 in_lo = lessThan(ivec4(0, 1, 2, 3), ivec4(inside)), in_hi = lessThan(ivec4(4, 5, 6, 7), ivec4(inside));
    if (in_lo.x) atomicAdd(local_hist[lo.x], 1u);
    if (in_hi.x) atomicAdd(local_hist[hi.x], 1u);
    if (in_lo.y) atomicAdd(local_hist[lo.y], 1u);
    if (in_hi.y) atomicAdd(local_hist[hi.y], 1u);
    if (in_lo.z) atomicAdd(local_hist[lo.z], 1u);
    if (in_hi.z) atomicAdd(local_hist[hi.z], 1u);
    if (in_lo.w) atomicAdd(local_hist[lo.w], 1u);
    if (in_hi.w) atomicAdd(local_hist[hi.w], 1u);
  }
  barrier();
  for (uint b = lid; b < kBins; b += 256u) {
    uint v = local_hist[b];
    if (v != 0u) atomicAdd(hist[b], v);
  }
  // This group's bins, then its count (release); the group whose count completes the total reads
  // every bin after it (acquire).
  memoryBarrierBuffer();
  barrier();
  if (lid == 0u) {
    uint groups = gl_NumWorkGroups.x * gl_NumWorkGroups.y;
    last_group = atomicAdd(hist[kBins], 1u) == groups - 1u;
  }
  barrier();
  memoryBarrierBuffer();
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
  Histogram();
  if (last_group) Select();  // the same value in every invocation of the group
}

// gaussian_sobel_thresholds: three kernels in one dispatch: the optional 3x3 Gaussian
// (kernels/gaussian.h), the 3x3 Sobel (kernels/sobel.h), and the automatic Canny thresholds
// (kernels/canny_thresholds.h: the magnitude histogram, then the threshold choice by the
// workgroup that finishes last). Integer only, replicate border at both filters, so bit-identical
// to the scalar gaussian -> sobel -> canny_thresholds:
//   G = BLUR ? gaussian(src) : src, G(x, y) = G(clamp(x, 0, w-1), clamp(y, 0, h-1)) outside;
//   gaussian(x, y) = (sum w_i w_j src(x+i, y+j) + 8) >> 4 with w = [1 2 1], src replicated;
//   dx = sum_j w_j (G(x+1, y+j) - G(x-1, y+j)),  dy = sum_i w_i (G(x+i, y+1) - G(x+i, y-1)),
//   |dx|, |dy| <= 1020, mag = |dx| + |dy| <= 2040 (not stored: nms recomputes it, cheaper than a
//   third plane of stores on lavapipe);
//   hist[m] = #{pixels with mag == m on rows y % kRowStep == 0} (kHistogramRowStep), N = w * those rows;
//   Q(p) = smallest h with 1000 * #{mag <= h} >= p * N, 2040 if none;
//   floor = min_high when contrast_ref == 0 or Q(995) >= contrast_ref,
//           else min(min_high, max(min_high * Q(995) / contrast_ref, min_high / 4, 3 * Q(500)));
//   high = max(floor, Q(high_permille)), low = high * low_permille / 1000,
//   M[t] = max mag of tile t (2^pc.j px square, pc.k per row, pc.l in all) on the histogram rows,
//   high_t = min(high, max(high * M[t] / Q(995), high / 4, 3 * Q(500))) when high <= M[t] < Q(995),
//            high otherwise,
//   low_t = high_t * low_permille / 1000,
// with the 64-bit products moved to the host: pc.a = ceil(high_permille * N / 1000), pc.g =
// ceil(995 * N / 1000), pc.i = ceil(500 * N / 1000), and 1000 * below >= p * N  <=>
// below >= ceil(p * N / 1000) for integer below.
// BLUR: specialisation constant 0 (1: Gaussian first, 0: Sobel of the frame as uploaded). A
// constant, not a push constant: lavapipe runs both sides of a branch (masked).
// One dispatch, not three: on lavapipe every dispatch wakes the driver's worker threads, which
// costs more than a small frame's whole work.
//
// In (binding 0), "padded frame": packed bytes, rows of pc.b uvec4 = 16 pad bytes, then pc.c
// chunks of 16 pixels, then 16 pad bytes; h + 2 rows, row r (-1..h) at uvec4 (r + 1) * pc.b. The
// host fills the pads by replication (rows -1 / h, pixels -16..-1 and past the end), so no read
// needs a border test. The blurred frame's own replicate border (G(-1, y) = G(0, y), not the blur
// of the replicated pixel -1) is applied to the blurred values in registers.
// Out: bindings 1 / 2: dx / dy (int16), packed two per uint (pixel 2k in the low half), rows of
// pc.d uvec4 = 8 * pc.d elements (a whole number of 32-pixel hysteresis mask words, >= the pc.c
// chunks written here; elements past the row end are don't-care). dx and dy are what the host
// downloads. Binding 4: params[2 t] = low_t, params[2 t + 1] = high_t, for nms_edge_sign.comp.
// Binding 3: the histogram, kBins counts, then the count of finished workgroups, then the pc.l
// tiles' maxima; zero before the dispatch (vkCmdFillBuffer). Each workgroup counts into a shared
// histogram and adds its non-zero bins with atomics (exact whatever the order), each invocation
// takes its tile's maximum with one atomicMax (its chunk's 16 x kRows pixels lie in one tile: tiles
// are >= 32 px), then the group counts itself; the workgroup whose count completes the total has
// seen every other group's bins and maxima and selects, its invocations sharing the tiles.
// One invocation: one 16-pixel chunk of kRows rows; the input rows it needs (three per output
// row) are carried in registers, each loaded once (one uvec4 and two single words per row): wide
// accesses matter on lavapipe, where each buffer access is a loop over the SIMD lanes.
#version 450
layout(local_size_x = 64) in;  // kGroupSize

layout(std430, set = 0, binding = 0) readonly buffer Image { uvec4 image[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Dx { uvec4 dx[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Dy { uvec4 dy[]; };
// coherent: the last workgroup reads the bins the others added (their atomics) after it saw
// their count.
layout(std430, set = 0, binding = 3) coherent buffer Hist { uint hist[]; };
layout(std430, set = 0, binding = 4) writeonly buffer Thresholds { uint params[]; };
// e = low_permille, f = min_high, g = Q(995)'s count, h = contrast_ref, i = Q(500)'s count,
// j = tile shift, k = tiles per row, l = tiles.
layout(push_constant) uniform Params {
  uint width; uint height; uint a; uint b; uint c; uint d; uint e; uint f; uint g; uint h; uint i; uint j; uint k;
  uint l;
} pc;

layout(constant_id = 0) const uint BLUR = 1u;
const uint kRows = 8u;               // a multiple of kRowStep
const uint kGroupSize = 64u;
const uint kBins = 2041u;            // kMaxMagnitude + 1
const uint kBinsPerThread = 32u;     // kGroupSize * 32 >= kBins
const uint kRowStep = 4u;            // kHistogramRowStep (kernels/canny_thresholds.h)

shared uint local_hist[kBins];
shared uint partial[kGroupSize];
shared bool last_group;
shared uint frame_high, frame_contrast, frame_noise;

uint chunk_max = 0u;  // this invocation's largest magnitude on the histogram rows

// 16 pixels of a row chunk (p0 = pixels 0..3, ...) and the pixels just left (l) and right (r) of
// it; l2 / r2: the pixels two to the left / right (read only where BLUR needs them).
struct Chunk { ivec4 p0, p1, p2, p3; int l2, l, r, r2; };

ivec4 Bytes(uint word) { return ivec4((uvec4(word) >> uvec4(0u, 8u, 16u, 24u)) & 255u); }

// Row `row` (-1..h) of the padded frame.
Chunk Load(int row, uint cx) {
  uint i = uint(row + 1) * pc.b + 1u + cx;
  uvec4 q = image[i];
  uint lw = image[i - 1u].w, rw = image[i + 1u].x;
  Chunk c;
  c.p0 = Bytes(q.x); c.p1 = Bytes(q.y); c.p2 = Bytes(q.z); c.p3 = Bytes(q.w);
  c.l2 = int((lw >> 16u) & 255u);
  c.l = int(lw >> 24u);
  c.r = int(rw & 255u);
  c.r2 = int((rw >> 8u) & 255u);
  return c;
}

// The Gaussian of the middle row b (a above, c below) at pixels -1..16 of the chunk, with the
// blurred frame's replicate border applied: pixel -1 of chunk 0 is pixel 0, pixels past w - 1
// are pixel w - 1 (last_k: pixel w - 1 within the chunk; > 15 when the row goes on).
Chunk Blur(Chunk a, Chunk b, Chunk c, uint cx, int last_k) {
  ivec4 v0 = a.p0 + 2 * b.p0 + c.p0, v1 = a.p1 + 2 * b.p1 + c.p1;
  ivec4 v2 = a.p2 + 2 * b.p2 + c.p2, v3 = a.p3 + 2 * b.p3 + c.p3;
  int vl2 = a.l2 + 2 * b.l2 + c.l2, vl = a.l + 2 * b.l + c.l;
  int vr = a.r + 2 * b.r + c.r, vr2 = a.r2 + 2 * b.r2 + c.r2;
  Chunk o;
  o.p0 = (ivec4(vl, v0.xyz) + 2 * v0 + ivec4(v0.yzw, v1.x) + 8) >> 4;
  o.p1 = (ivec4(v0.w, v1.xyz) + 2 * v1 + ivec4(v1.yzw, v2.x) + 8) >> 4;
  o.p2 = (ivec4(v1.w, v2.xyz) + 2 * v2 + ivec4(v2.yzw, v3.x) + 8) >> 4;
  o.p3 = (ivec4(v2.w, v3.xyz) + 2 * v3 + ivec4(v3.yzw, vr) + 8) >> 4;
  o.l = cx == 0u ? o.p0.x : (vl2 + 2 * vl + v0.x + 8) >> 4;
  o.r = (v3.w + 2 * vr + vr2 + 8) >> 4;
  o.l2 = 0;
  o.r2 = 0;
  if (last_k <= 15) {
    // The row ends inside this chunk: pixels past it repeat pixel w - 1.
    ivec4 k0 = ivec4(0, 1, 2, 3);
    ivec4 at = mix(ivec4(0), o.p0, equal(k0, ivec4(last_k))) + mix(ivec4(0), o.p1, equal(k0 + 4, ivec4(last_k))) +
               mix(ivec4(0), o.p2, equal(k0 + 8, ivec4(last_k))) + mix(ivec4(0), o.p3, equal(k0 + 12, ivec4(last_k)));
    int end = at.x + at.y + at.z + at.w;
    o.p0 = mix(o.p0, ivec4(end), greaterThan(k0, ivec4(last_k)));
    o.p1 = mix(o.p1, ivec4(end), greaterThan(k0 + 4, ivec4(last_k)));
    o.p2 = mix(o.p2, ivec4(end), greaterThan(k0 + 8, ivec4(last_k)));
    o.p3 = mix(o.p3, ivec4(end), greaterThan(k0 + 12, ivec4(last_k)));
    o.r = end;
  }
  return o;
}

// [1 2 1] along the row: 16 values from the chunk and its two neighbours.
void Smooth(Chunk c, out ivec4 s0, out ivec4 s1, out ivec4 s2, out ivec4 s3) {
  s0 = ivec4(c.l, c.p0.xyz) + 2 * c.p0 + ivec4(c.p0.yzw, c.p1.x);
  s1 = ivec4(c.p0.w, c.p1.xyz) + 2 * c.p1 + ivec4(c.p1.yzw, c.p2.x);
  s2 = ivec4(c.p1.w, c.p2.xyz) + 2 * c.p2 + ivec4(c.p2.yzw, c.p3.x);
  s3 = ivec4(c.p2.w, c.p3.xyz) + 2 * c.p3 + ivec4(c.p3.yzw, c.r);
}

// Eight 16-bit values (two ivec4) packed into a uvec4, value 2k in the low half of word k.
uvec4 Pack16(ivec4 a, ivec4 b) {
  uvec4 lo = uvec4(a.x, a.z, b.x, b.z) & 0xffffu, hi = uvec4(a.y, a.w, b.y, b.w) & 0xffffu;
  return lo | (hi << 16u);
}

// Counts the magnitudes of 4 pixels (k0..k0+3 of the chunk) that lie inside the row, and keeps
// their maximum.
void Count(ivec4 gx, ivec4 gy, int k0, int inside) {
  uvec4 m = uvec4(abs(gx) + abs(gy));
  if (k0 < inside) atomicAdd(local_hist[m.x], 1u);
  if (k0 + 1 < inside) atomicAdd(local_hist[m.y], 1u);
  if (k0 + 2 < inside) atomicAdd(local_hist[m.z], 1u);
  if (k0 + 3 < inside) atomicAdd(local_hist[m.w], 1u);
  uvec4 kept = mix(uvec4(0u), m, lessThan(ivec4(k0) + ivec4(0, 1, 2, 3), ivec4(inside)));
  chunk_max = max(chunk_max, max(max(kept.x, kept.y), max(kept.z, kept.w)));
}

// dx, dy of output row y from the Sobel input rows a (y - 1), b (y), c (y + 1); row y's
// magnitudes counted when it is a histogram row.
void Store(int y, uint cx, Chunk a, Chunk b, Chunk c) {
  ivec4 sa0, sa1, sa2, sa3, sc0, sc1, sc2, sc3;
  Smooth(a, sa0, sa1, sa2, sa3);
  Smooth(c, sc0, sc1, sc2, sc3);
  // Column sums [1 2 1]^T, then their difference one pixel right minus one pixel left.
  ivec4 v0 = a.p0 + 2 * b.p0 + c.p0, v1 = a.p1 + 2 * b.p1 + c.p1;
  ivec4 v2 = a.p2 + 2 * b.p2 + c.p2, v3 = a.p3 + 2 * b.p3 + c.p3;
  int vl = a.l + 2 * b.l + c.l, vr = a.r + 2 * b.r + c.r;
  ivec4 gx0 = ivec4(v0.yzw, v1.x) - ivec4(vl, v0.xyz);
  ivec4 gx1 = ivec4(v1.yzw, v2.x) - ivec4(v0.w, v1.xyz);
  ivec4 gx2 = ivec4(v2.yzw, v3.x) - ivec4(v1.w, v2.xyz);
  ivec4 gx3 = ivec4(v3.yzw, vr) - ivec4(v2.w, v3.xyz);
  uint o = uint(y) * pc.d + 2u * cx;
  dx[o] = Pack16(gx0, gx1);
  dx[o + 1u] = Pack16(gx2, gx3);
  ivec4 gy0 = sc0 - sa0, gy1 = sc1 - sa1, gy2 = sc2 - sa2, gy3 = sc3 - sa3;
  dy[o] = Pack16(gy0, gy1);
  dy[o + 1u] = Pack16(gy2, gy3);
  if ((uint(y) % kRowStep) == 0u) {
    int inside = int(pc.width) - int(16u * cx);  // pixels of this chunk in the row
    Count(gx0, gy0, 0, inside);
    Count(gx1, gy1, 4, inside);
    Count(gx2, gy2, 8, inside);
    Count(gx3, gy3, 12, inside);
  }
}

// Q: the smallest bin b with #{mag <= b} >= need, kBins - 1 if none (from the per-thread sums
// `partial`, then the bins of the one thread's range that reaches need).
uint Quantile(uint need) {
  uint below = 0u;
  for (uint t = 0u; t < kGroupSize; ++t) {
    if (below + partial[t] < need) { below += partial[t]; continue; }
    for (uint k = 0u; k < kBinsPerThread; ++k) {
      uint b = t * kBinsPerThread + k;
      if (b >= kBins) break;
      below += hist[b];
      if (below >= need) return b;
    }
  }
  return kBins - 1u;
}

// The thresholds from the complete histogram and tiles' maxima (the last workgroup; every
// invocation calls it): the frame's pair by invocation 0, then the tiles' pairs by all.
void Select() {
  uint lid = gl_LocalInvocationID.x;
  uint sum = 0u;
  for (uint k = 0u; k < kBinsPerThread; ++k) {
    uint b = lid * kBinsPerThread + k;
    if (b < kBins) sum += hist[b];
  }
  partial[lid] = sum;
  barrier();
  if (lid == 0u) {
    uint contrast = Quantile(pc.g), noise = 3u * Quantile(pc.i);
    uint floor_high = pc.f;
    if (pc.h != 0u && contrast < pc.h) floor_high = min(pc.f, max(max(pc.f * contrast / pc.h, pc.f / 4u), noise));
    frame_high = max(Quantile(pc.a), floor_high);
    frame_contrast = contrast;
    frame_noise = noise;
  }
  barrier();
  uint high = frame_high, contrast = frame_contrast;
  for (uint t = lid; t < pc.l; t += kGroupSize) {
    uint m = hist[kBins + 1u + t];
    // m >= contrast whenever contrast is 0: the max() only keeps the unused division defined.
    bool lowered = m < contrast && m >= high;
    uint tile_high = lowered ? min(high, max(max(high * m / max(contrast, 1u), high / 4u), frame_noise)) : high;
    params[2u * t] = tile_high * pc.e / 1000u;
    params[2u * t + 1u] = tile_high;
  }
}

// The Gaussian (when BLUR) and the Sobel of this invocation's chunk and rows, counting the
// histogram rows.
void Gradients(uint cx, int y0, int y1, int h) {
  if (BLUR == 1u) {
    int last_k = int(pc.width) - 1 - int(16u * cx);
    // Frame rows i1..i3 (clamped to the padded rows -1..h) give the blurred rows ga, gb, gc =
    // y - 1, y, y + 1 (clamped to 0..h-1: the blurred frame's replicate border).
    Chunk i1 = Load(max(y0 - 2, -1), cx), i2 = Load(y0 - 1, cx), i3 = Load(y0, cx);
    Chunk ga = Blur(i1, i2, i3, cx, last_k);  // blurred row y0 - 1 (when y0 > 0)
    i1 = i2;
    i2 = i3;
    i3 = Load(y0 + 1, cx);
    Chunk gb = Blur(i1, i2, i3, cx, last_k);  // blurred row y0
    if (y0 == 0) ga = gb;
    for (int y = y0; y < y1; ++y) {
      // Blurred row y + 1 from frame rows y .. y + 2; past the last row it repeats row h - 1.
      i1 = i2;
      i2 = i3;
      i3 = Load(min(y + 2, h), cx);
      Chunk gc = y + 1 < h ? Blur(i1, i2, i3, cx, last_k) : gb;
      Store(y, cx, ga, gb, gc);
      ga = gb;
      gb = gc;
    }
  } else {
    // The padded frame's rows -1..h are the replicate border: rows y - 1, y, y + 1 as they are.
    Chunk a = Load(y0 - 1, cx), b = Load(y0, cx);
    for (int y = y0; y < y1; ++y) {
      Chunk c = Load(y + 1, cx);
      Store(y, cx, a, b, c);
      a = b;
      b = c;
    }
  }
}

void main() {
  uint lid = gl_LocalInvocationID.x;
  for (uint b = lid; b < kBins; b += kGroupSize) local_hist[b] = 0u;
  barrier();
  uint id = gl_GlobalInvocationID.y * (gl_NumWorkGroups.x * gl_WorkGroupSize.x) + gl_GlobalInvocationID.x;
  uint cx = id % pc.c, block = id / pc.c;
  int h = int(pc.height);
  int y0 = int(block * kRows);
  if (y0 < h) {
    Gradients(cx, y0, min(y0 + int(kRows), h), h);  // no return: barriers follow
    atomicMax(hist[kBins + 1u + (uint(y0) >> pc.j) * pc.k + ((16u * cx) >> pc.j)], chunk_max);
  }
  barrier();
  for (uint b = lid; b < kBins; b += kGroupSize) {
    uint v = local_hist[b];
    if (v != 0u) atomicAdd(hist[b], v);
  }
  // This group's bins, then its count (release); the group whose count completes the total reads
  // every bin after it (acquire).
  memoryBarrierBuffer();
  barrier();
  if (lid == 0u) last_group = atomicAdd(hist[kBins], 1u) == gl_NumWorkGroups.x * gl_NumWorkGroups.y - 1u;
  barrier();
  memoryBarrierBuffer();
  if (last_group) Select();  // the same value in every invocation of the group
}

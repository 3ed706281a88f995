// polyline: Ramer-Douglas-Peucker per curve, bit-identical to scalar::Polyline (kernels/polyline.h).
// One invocation per curve (a curve's recursion is sequential; curves are independent).
//   chord (i, j): the farthest point k maximises |cross(p_j - p_i, p_k - p_i)|, FIRST k on ties
//   (strict '>' while k increases, as the scalar loop); split at k when
//     16 * cross^2 > tol_q16 * |p_j - p_i|^2,
//   else halve (by index) while |dx| or |dy| > kMaxSegmentComponent and j - i >= 2,
//   else emit vertex j. The right half is pushed below the left half, so vertices come out in
//   increasing order. All products in int64 (coordinates < 2^14, see kernels/polyline.h).
// The halving test compares the int32 differences (exact: |difference| < 2^31), not int64 against
// the constant 1024: Mesa 22.3 lavapipe miscompiles some int64-versus-constant compares (measured:
// int64 2 > 3 came out true), so here int64 values are compared only with each other or with 0.
//
// Resumable (runtime/vulkan_arc_stage.h): one dispatch runs at most pc.budget steps per curve in
// ONE flat loop (a step = pop a chord, test one point, or decide a chord) and keeps its place in
// state[]; the host dispatches rounds until no curve is pending. (lavapipe ends any loop nest
// after 65535 iterations, and a GPU watchdog ends long dispatches; a bounded step count per
// dispatch suits both.) The curve's phase word moves 0 (polyline) -> 1 (arc_split.comp) when done.
// Storage: curve c owns points [offset[c], offset[c + 1]) (non-empty), its explicit stack
//   stack[2 * offset[c] .. 2 * offset[c + 1]) (at most 2 * (length - 1) entries live: pending
//   chords are disjoint and at least one point long), and its vertices vertex[offset[c] ..) (at
//   most length); counts[c] = its vertex count.
#version 450
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
layout(local_size_x = 8) in;

const int kMaxSegmentComponent = 1024;
const uint kStateWords = 16u;
// state[c * kStateWords + ...]: phase, started, then this shader's place:
const uint kPhase = 0u, kStarted = 1u, kTop = 2u, kNv = 3u, kI = 4u, kJ = 5u, kK = 6u, kBestLo = 7u, kBestHi = 8u,
           kBestK = 9u;

layout(std430, set = 0, binding = 0) readonly buffer X { int px[]; };
layout(std430, set = 0, binding = 1) readonly buffer Y { int py[]; };
layout(std430, set = 0, binding = 3) readonly buffer Offset { int offset[]; };
layout(std430, set = 0, binding = 5) buffer Stack { int stack_[]; };
layout(std430, set = 0, binding = 6) writeonly buffer Vertex { int vertex[]; };
layout(std430, set = 0, binding = 9) writeonly buffer Counts { uint counts[]; };
layout(std430, set = 0, binding = 10) buffer State { int state[]; };
layout(std430, set = 0, binding = 11) writeonly buffer Pending { uint pending[]; };
// Curves by decreasing length (host-sorted), so the invocations of a SIMD group do similar work.
layout(std430, set = 0, binding = 12) readonly buffer Order { uint order[]; };
layout(push_constant) uniform Params {
  uint num_curves; uint num_points; int tol_q16; uint tan_lo; uint tan_hi; int min_points; uint round; uint budget;
} pc;

int64_t Abs64(int64_t v) { return v < 0l ? -v : v; }

void main() {
  uint invocation = gl_GlobalInvocationID.y * (gl_NumWorkGroups.x * gl_WorkGroupSize.x) + gl_GlobalInvocationID.x;
  if (invocation >= pc.num_curves) return;
  uint c = order[invocation];
  uint s0 = c * kStateWords;
  if (state[s0 + kPhase] != 0) return;
  int first = offset[c], last = offset[c + 1] - 1;
  int base = 2 * first;
  int top, nv, i, j, k, best_k;
  int64_t best;
  if (state[s0 + kStarted] == 0) {
    nv = 0;
    vertex[first + nv++] = first;
    top = 0;
    if (last > first) {
      stack_[base + top++] = first;
      stack_[base + top++] = last;
    }
    i = j = best_k = -1;
    k = 0;  // 0: no chord being scanned (a scan has k >= i + 1 >= 1)
    best = -1l;
  } else {
    top = state[s0 + kTop]; nv = state[s0 + kNv];
    i = state[s0 + kI]; j = state[s0 + kJ]; k = state[s0 + kK]; best_k = state[s0 + kBestK];
    best = int64_t(uint64_t(uint(state[s0 + kBestLo])) | (uint64_t(uint(state[s0 + kBestHi])) << 32));
  }
  // The chord being scanned: p_i and p_j - p_i (reloaded on resume and on each pop).
  int xi = 0, yi = 0;
  int64_t cx = 0l, cy = 0l;
  if (k != 0) {
    xi = px[i]; yi = py[i];
    cx = int64_t(px[j] - xi); cy = int64_t(py[j] - yi);
  }
  bool done = false;
  for (uint step = 0u; step < pc.budget; ++step) {
    if (k == 0) {
      if (top == 0) { done = true; break; }
      j = stack_[base + --top];
      i = stack_[base + --top];
      k = i + 1;
      best = -1l;
      best_k = -1;
      xi = px[i]; yi = py[i];
      cx = int64_t(px[j] - xi); cy = int64_t(py[j] - yi);
    } else if (k < j) {
      int64_t cr = Abs64(cx * int64_t(py[k] - yi) - cy * int64_t(px[k] - xi));
      if (cr > best) { best = cr; best_k = k; }
      ++k;
    } else {
      int64_t len2 = cx * cx + cy * cy;
      int split = -1;
      if (best_k >= 0 && 16l * best * best > int64_t(pc.tol_q16) * len2) {
        split = best_k;
      } else if ((abs(px[j] - xi) > kMaxSegmentComponent || abs(py[j] - yi) > kMaxSegmentComponent) &&
                 j - i >= 2) {
        split = i + (j - i) / 2;
      }
      if (split >= 0) {
        stack_[base + top++] = split; stack_[base + top++] = j;
        stack_[base + top++] = i;     stack_[base + top++] = split;
      } else {
        vertex[first + nv++] = j;
      }
      k = 0;
    }
  }
  if (done) {
    counts[c] = uint(nv);
    state[s0 + kPhase] = 1;
    state[s0 + kStarted] = 0;
  } else {
    state[s0 + kStarted] = 1;
    state[s0 + kTop] = top; state[s0 + kNv] = nv;
    state[s0 + kI] = i; state[s0 + kJ] = j; state[s0 + kK] = k; state[s0 + kBestK] = best_k;
    state[s0 + kBestLo] = int(uint(uint64_t(best) & 0xffffffffUL));
    state[s0 + kBestHi] = int(uint(uint64_t(best) >> 32));
    pending[pc.round] = 1u;
  }
}

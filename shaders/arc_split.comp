// arc_split: split points of each curve's polyline, bit-identical to scalar::ArcSplit
// (kernels/arc_split.h). One invocation per curve. For interior vertex pairs (k, k + 1),
// z = conj(a) * b = (a.b, a x b) at each vertex (int64), then
//   inflection  sign(Im z_k) * sign(Im z_{k+1}) < 0  -> v_k + (v_{k+1} - v_k) / 2
//   turning     w = z_{k+1} * conj(z_k): Re w <= 0 or 2^16 |Im w| > tan_q16 * Re w
//               -> v_{k+1} when Re z_k * |Im z_{k+1}| - |Im z_k| * Re z_{k+1} > 0, else v_k
// and a split equal to the previous one of the curve is dropped. Integer only (|Re w|, |Im w| < 2^43);
// int64 values are compared only with each other or with 0 (see polyline.comp: lavapipe).
// Resumable like polyline.comp: at most pc.budget vertex pairs per dispatch in one flat loop; the
// curve's phase word moves 1 -> 2 (arc_stats.comp) when done. A curve still in phase 0 is pending.
// Storage: vertices of curve c at vertex[offset[c] ..), counts[c] of them (polyline.comp); its
//   splits go to split[offset[c] ..) (at most length - 1: one per vertex pair), and
//   counts[num_curves + c] = how many. tan_q16 = int64(tan_hi, tan_lo).
#version 450
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
layout(local_size_x = 8) in;

const uint kStateWords = 16u;
const uint kPhase = 0u, kStarted = 1u, kK = 2u, kNs = 3u, kPrevious = 4u;

layout(std430, set = 0, binding = 0) readonly buffer X { int px[]; };
layout(std430, set = 0, binding = 1) readonly buffer Y { int py[]; };
layout(std430, set = 0, binding = 3) readonly buffer Offset { int offset[]; };
layout(std430, set = 0, binding = 6) readonly buffer Vertex { int vertex[]; };
layout(std430, set = 0, binding = 7) writeonly buffer Split { int split[]; };
layout(std430, set = 0, binding = 9) buffer Counts { uint counts[]; };
layout(std430, set = 0, binding = 10) buffer State { int state[]; };
layout(std430, set = 0, binding = 11) writeonly buffer Pending { uint pending[]; };
// Curves by decreasing length (host-sorted), so the invocations of a SIMD group do similar work.
layout(std430, set = 0, binding = 12) readonly buffer Order { uint order[]; };
layout(push_constant) uniform Params {
  uint num_curves; uint num_points; int tol_q16; uint tan_lo; uint tan_hi; int min_points; uint round; uint budget;
} pc;

int64_t Abs64(int64_t v) { return v < 0l ? -v : v; }
int Sign64(int64_t v) { return int(v > 0l) - int(v < 0l); }

// z = conj(a) * b for a = p1 - p0, b = p2 - p1: (re, im) = (a.b, a x b).
i64vec2 TurnAt(int p0, int p1, int p2) {
  int64_t ax = int64_t(px[p1] - px[p0]), ay = int64_t(py[p1] - py[p0]);
  int64_t bx = int64_t(px[p2] - px[p1]), by = int64_t(py[p2] - py[p1]);
  return i64vec2(ax * bx + ay * by, ax * by - ay * bx);
}

void main() {
  uint invocation = gl_GlobalInvocationID.y * (gl_NumWorkGroups.x * gl_WorkGroupSize.x) + gl_GlobalInvocationID.x;
  if (invocation >= pc.num_curves) return;
  uint c = order[invocation];
  uint s0 = c * kStateWords;
  int phase = state[s0 + kPhase];
  if (phase > 1) return;
  if (phase < 1) { pending[pc.round] = 1u; return; }
  int v0 = offset[c];  // this curve's vertices start at vertex[v0]
  int nv = int(counts[c]);
  int64_t tan_q16 = int64_t(uint64_t(pc.tan_lo) | (uint64_t(pc.tan_hi) << 32));
  int k = 1, ns = 0, previous = -1;
  if (state[s0 + kStarted] != 0) {
    k = state[s0 + kK]; ns = state[s0 + kNs]; previous = state[s0 + kPrevious];
  }
  bool done = false;
  for (uint step = 0u; step < pc.budget; ++step) {
    if (k + 2 >= nv) { done = true; break; }
    int vk0 = vertex[v0 + k - 1], vk = vertex[v0 + k], vk1 = vertex[v0 + k + 1], vk2 = vertex[v0 + k + 2];
    i64vec2 z0 = TurnAt(vk0, vk, vk1);
    i64vec2 z1 = TurnAt(vk, vk1, vk2);
    int s = -1;
    if (Sign64(z0.y) * Sign64(z1.y) < 0) {
      s = vk + (vk1 - vk) / 2;
    } else {
      int64_t wre = z1.x * z0.x + z1.y * z0.y;
      int64_t wim = z1.y * z0.x - z1.x * z0.y;
      if (wre <= 0l || 65536l * Abs64(wim) > tan_q16 * wre) {
        bool second_turns_more = z0.x * Abs64(z1.y) - Abs64(z0.y) * z1.x > 0l;
        s = second_turns_more ? vk1 : vk;
      }
    }
    if (s >= 0 && (ns == 0 || previous != s)) {
      split[v0 + ns++] = s;
      previous = s;
    }
    ++k;
  }
  if (done) {
    counts[pc.num_curves + c] = uint(ns);
    state[s0 + kPhase] = 2;
    state[s0 + kStarted] = 0;
  } else {
    state[s0 + kStarted] = 1;
    state[s0 + kK] = k; state[s0 + kNs] = ns; state[s0 + kPrevious] = previous;
    pending[pc.round] = 1u;
  }
}

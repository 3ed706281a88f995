// arc_stats: per-arc statistics, bit-identical to scalar::ArcStatsFromSplits (kernels/arc_stats.h).
// One invocation per curve; it walks the curve's arcs [begin, end] between {first, splits.., last}
// and keeps those with end - begin + 1 >= min_points:
//   end points, middle point (index begin + (end - begin) / 2), bounding box, gradient sums over
//   the first / last k = clamp(n / 4, 1, 4) points, and the quadrant from the int64 bulge
//   b = sum (2 p_i - (first + last)) read along the diagonal of the gradient class.
// Resumable like polyline.comp: at most pc.budget steps per dispatch in one flat loop (a step = start
// an arc, add one point, or finish an arc; the <= 4 gradient terms are unrolled by hand so that no
// loop nests); the curve's phase word moves 2 -> 3 (done). A curve in an earlier phase is pending.
// Storage: splits of curve c at split[offset[c] ..), counts[C + c] of them (arc_split.comp). Its
//   arcs go to slots offset[c] + m (a non-empty curve has at most max(1, vertices - 2) <= length
//   arcs), struct-of-arrays: field f of slot s at arcs[f * num_points + s], fields in kField* order
//   below; counts[2 C + c] = its arc count. Gradients: g[i] = (gx & 0xffff) | (gy << 16), int16 each.
#version 450
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
layout(local_size_x = 8) in;

const uint kFieldBegin = 0u, kFieldEnd = 1u, kFieldX0 = 2u, kFieldY0 = 3u, kFieldX1 = 4u, kFieldY1 = 5u,
           kFieldXm = 6u, kFieldYm = 7u, kFieldMinX = 8u, kFieldMinY = 9u, kFieldMaxX = 10u, kFieldMaxY = 11u,
           kFieldG0x = 12u, kFieldG0y = 13u, kFieldG1x = 14u, kFieldG1y = 15u,
           kFieldQuadrantAndClass = 16u;  // quadrant (int8, low byte) | sign_class << 8

const uint kStateWords = 16u;
const uint kPhase = 0u, kStarted = 1u, kS = 2u, kBegin = 3u, kNa = 4u, kI = 5u, kEnd = 6u, kMinX = 7u, kMaxX = 8u,
           kMinY = 9u, kMaxY = 10u, kBxLo = 11u, kBxHi = 12u, kByLo = 13u, kByHi = 14u;

const uint kEdgeMinus = 2u;
const int kQuadrantNone = 0, kQuadrantI = 1, kQuadrantII = 2, kQuadrantIII = 3, kQuadrantIV = 4;

layout(std430, set = 0, binding = 0) readonly buffer X { int px[]; };
layout(std430, set = 0, binding = 1) readonly buffer Y { int py[]; };
layout(std430, set = 0, binding = 2) readonly buffer G { uint g[]; };
layout(std430, set = 0, binding = 3) readonly buffer Offset { int offset[]; };
layout(std430, set = 0, binding = 4) readonly buffer SignClass { uint sign_class[]; };
layout(std430, set = 0, binding = 7) readonly buffer Split { int split[]; };
layout(std430, set = 0, binding = 8) writeonly buffer Arcs { int arcs[]; };
layout(std430, set = 0, binding = 9) buffer Counts { uint counts[]; };
layout(std430, set = 0, binding = 10) buffer State { int state[]; };
layout(std430, set = 0, binding = 11) writeonly buffer Pending { uint pending[]; };
// Curves by decreasing length (host-sorted), so the invocations of a SIMD group do similar work.
layout(std430, set = 0, binding = 12) readonly buffer Order { uint order[]; };
layout(push_constant) uniform Params {
  uint num_curves; uint num_points; int tol_q16; uint tan_lo; uint tan_hi; int min_points; uint round; uint budget;
} pc;

int Gx(int i) { return bitfieldExtract(int(g[i]), 0, 16); }
int Gy(int i) { return bitfieldExtract(int(g[i]), 16, 16); }

void Put(uint field, uint slot, int value) { arcs[field * pc.num_points + slot] = value; }

int64_t Load64(uint at) { return int64_t(uint64_t(uint(state[at])) | (uint64_t(uint(state[at + 1u])) << 32)); }
void Store64(uint at, int64_t v) {
  state[at] = int(uint(uint64_t(v) & 0xffffffffUL));
  state[at + 1u] = int(uint(uint64_t(v) >> 32));
}

void main() {
  uint invocation = gl_GlobalInvocationID.y * (gl_NumWorkGroups.x * gl_WorkGroupSize.x) + gl_GlobalInvocationID.x;
  if (invocation >= pc.num_curves) return;
  uint c = order[invocation];
  uint s0 = c * kStateWords;
  int phase = state[s0 + kPhase];
  if (phase > 2) return;
  if (phase < 2) { pending[pc.round] = 1u; return; }
  int first = offset[c], last = offset[c + 1] - 1;
  int ns = int(counts[pc.num_curves + c]);
  uint cls = sign_class[c];
  // s: index of the arc's end among {splits.., last}; i: next point of the arc being summed, or -1.
  int s = 0, begin = first, na = 0, i = -1, end = 0, min_x = 0, max_x = 0, min_y = 0, max_y = 0;
  int64_t bx = 0l, by = 0l;
  if (state[s0 + kStarted] != 0) {
    s = state[s0 + kS]; begin = state[s0 + kBegin]; na = state[s0 + kNa]; i = state[s0 + kI]; end = state[s0 + kEnd];
    min_x = state[s0 + kMinX]; max_x = state[s0 + kMaxX]; min_y = state[s0 + kMinY]; max_y = state[s0 + kMaxY];
    bx = Load64(s0 + kBxLo); by = Load64(s0 + kByLo);
  }
  bool done = false;
  for (uint step = 0u; step < pc.budget; ++step) {
    if (i < 0) {
      if (s > ns) { done = true; break; }
      end = s < ns ? split[first + s] : last;
      if (end - begin + 1 >= pc.min_points) {
        i = begin;
        min_x = max_x = px[begin];
        min_y = max_y = py[begin];
        bx = by = 0l;
      } else {
        begin = end;
        ++s;
      }
    } else if (i <= end) {
      int x = px[i], y = py[i];
      min_x = min(min_x, x); max_x = max(max_x, x);
      min_y = min(min_y, y); max_y = max(max_y, y);
      bx += int64_t(2 * x - (px[begin] + px[end]));
      by += int64_t(2 * y - (py[begin] + py[end]));
      ++i;
    } else {
      uint slot = uint(first + na++);
      int n = end - begin + 1;
      int k = clamp(n / 4, 1, 4);
      int g0x = Gx(begin), g0y = Gy(begin), g1x = Gx(end), g1y = Gy(end);
      if (k > 1) { g0x += Gx(begin + 1); g0y += Gy(begin + 1); g1x += Gx(end - 1); g1y += Gy(end - 1); }
      if (k > 2) { g0x += Gx(begin + 2); g0y += Gy(begin + 2); g1x += Gx(end - 2); g1y += Gy(end - 2); }
      if (k > 3) { g0x += Gx(begin + 3); g0y += Gy(begin + 3); g1x += Gx(end - 3); g1y += Gy(end - 3); }
      int quadrant;
      if (cls == kEdgeMinus) {
        int64_t d = bx - by;
        quadrant = d > 0l ? kQuadrantI : (d < 0l ? kQuadrantIII : kQuadrantNone);
      } else {
        int64_t d = bx + by;
        quadrant = d < 0l ? kQuadrantII : (d > 0l ? kQuadrantIV : kQuadrantNone);
      }
      int mid = begin + (end - begin) / 2;
      Put(kFieldBegin, slot, begin); Put(kFieldEnd, slot, end);
      Put(kFieldX0, slot, px[begin]); Put(kFieldY0, slot, py[begin]);
      Put(kFieldX1, slot, px[end]); Put(kFieldY1, slot, py[end]);
      Put(kFieldXm, slot, px[mid]); Put(kFieldYm, slot, py[mid]);
      Put(kFieldMinX, slot, min_x); Put(kFieldMinY, slot, min_y);
      Put(kFieldMaxX, slot, max_x); Put(kFieldMaxY, slot, max_y);
      Put(kFieldG0x, slot, g0x); Put(kFieldG0y, slot, g0y); Put(kFieldG1x, slot, g1x); Put(kFieldG1y, slot, g1y);
      Put(kFieldQuadrantAndClass, slot, quadrant | int(cls << 8));
      begin = end;
      ++s;
      i = -1;
    }
  }
  if (done) {
    counts[2u * pc.num_curves + c] = uint(na);
    state[s0 + kPhase] = 3;
    state[s0 + kStarted] = 0;
  } else {
    state[s0 + kStarted] = 1;
    state[s0 + kS] = s; state[s0 + kBegin] = begin; state[s0 + kNa] = na; state[s0 + kI] = i; state[s0 + kEnd] = end;
    state[s0 + kMinX] = min_x; state[s0 + kMaxX] = max_x; state[s0 + kMinY] = min_y; state[s0 + kMaxY] = max_y;
    Store64(s0 + kBxLo, bx); Store64(s0 + kByLo, by);
    pending[pc.round] = 1u;
  }
}

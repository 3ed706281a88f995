// hysteresis_sweep: the body of hysteresis.comp and hysteresis_rmw.comp, which define the atomic
// accessors NeighbourEdges(index) and StoreEdges(index, word) of binding 6, include this file,
// then define SetFlag(index) of binding 7.
//
// Canny edge tracking (kernels/hysteresis.h) on bit masks, in few dispatches.
//
// Contract reached: a pixel is an edge exactly when it is weak or strong and 8-connected through
// weak/strong pixels to a strong one. Binding 6 holds, per row y and 32-pixel word s (row-major,
// pc.b words per row), uvec2(candidate, edge): bit k of a word is pixel x = 32 s + k;
// candidate = weak or strong (nms.comp), edge = strong or reached. Padding bits are 0.
//
// One invocation owns one column of words (a 32-pixel strip, all rows) and sweeps it down, then
// up, repeating until a down+up pair changes nothing (one sweep carries an edge along the whole
// strip; see Sweep). 8-connectivity inside one row is plain left/right adjacency, so a row's
// candidate runs are flooded with a Kogge-Stone fill. The only write is "candidate becomes edge"
// with an edge neighbour, which is monotone, so stale reads of a neighbour strip (written concurrently)
// only delay a promotion, never make a wrong one; and a dispatch in which no invocation changes
// anything read only final values, so it is a fixed point of the global rule, i.e. the contract.
// The edge words are the only memory one invocation writes while others read it: those accesses
// are atomic (NeighbourEdges / StoreEdges), so there is no data race. hysteresis.comp does them as
// relaxed atomic loads and stores under the Vulkan memory model (plain loads and stores on most
// hardware); hysteresis_rmw.comp, for devices without vulkanMemoryModel, as atomicOr.
// Each invocation's loop is bounded by 32 * height + 1 sweep pairs (every pair that continues
// promotes a pixel of its strip); it then reports "changed", so the host still decides.
//
// Binding 7: dispatch pc.a runs only when flags[pc.a] != 0 (the previous one changed something)
// and sets flags[pc.a + 1] = 1 when it changed anything; the host reads the last flag. Every
// dispatch that does not end the iteration promotes a pixel, so width * height + 1 dispatches
// bound it.
// Workgroups of 8 invocations: lavapipe runs 8 lanes per SIMD group and one workgroup per CPU
// thread, so small groups spread the few strips over all threads.
layout(std430, set = 0, binding = 7) buffer Flags { uint flags[]; };
// Sets flags[index] to 1 atomically (defined by the including shader, after this file).
void SetFlag(uint index);

layout(push_constant) uniform Params { uint width; uint height; uint a; uint b; uint c; uint d; } pc;

// Bits of `seed` grown along the runs of `cand` that contain them (seed is a subset of cand),
// both directions, in log2(32) steps per direction.
uint FillRuns(uint seed, uint cand) {
  uint up = seed, gu = cand, dn = seed, gd = cand;
  up |= gu & (up << 1u);  gu &= gu << 1u;   dn |= gd & (dn >> 1u);  gd &= gd >> 1u;
  up |= gu & (up << 2u);  gu &= gu << 2u;   dn |= gd & (dn >> 2u);  gd &= gd >> 2u;
  up |= gu & (up << 4u);  gu &= gu << 4u;   dn |= gd & (dn >> 4u);  gd &= gd >> 4u;
  up |= gu & (up << 8u);  gu &= gu << 8u;   dn |= gd & (dn >> 8u);  gd &= gd >> 8u;
  up |= gu & (up << 16u);                   dn |= gd & (dn >> 16u);
  return up | dn;
}

// One sweep over the strip's rows, from row `start` in direction `dir` (+1 down, -1 up). A row
// step promotes the candidates touching an edge pixel in the row before (already updated), the
// row itself or the row after, the neighbour strips' bits 31 / 0 included, then floods the row's
// candidate runs. Loads run one row ahead and are carried, so a step does three loads and no
// data-dependent ones (lavapipe executes both sides of a branch, masked, so "rare" loads cost
// as much as common ones). ls / rs: the neighbour strips (clamped), lm / rm: ~0 when they exist.
void Sweep(int start, int dir, uint s, uint ls, uint rs, uint lm, uint rm, uint wpr, int h, inout bool changed) {
  uvec2 cur = masks[uint(start) * wpr + s];
  uint lcur = NeighbourEdges(uint(start) * wpr + ls) & lm, rcur = NeighbourEdges(uint(start) * wpr + rs) & rm;
  uint prev = 0u, lprev = 0u, rprev = 0u;
  for (int i = 0; i < h; ++i) {
    int y = start + i * dir, ya = y + dir;
    uint inside = (ya >= 0 && ya < h) ? ~0u : 0u;
    uint row = uint(clamp(ya, 0, h - 1)) * wpr;
    uvec2 nxt = masks[row + s] & uvec2(inside);
    uint lnx = NeighbourEdges(row + ls) & lm & inside, rnx = NeighbourEdges(row + rs) & rm & inside;
    uint v = prev | cur.y | nxt.y;
    uint reach = v | (v << 1u) | (v >> 1u) | ((lprev | lcur | lnx) >> 31u) | (((rprev | rcur | rnx) & 1u) << 31u);
    uint grown = cur.x & ~cur.y & reach;
    uint e = cur.y;
    if (grown != 0u) {
      e = FillRuns(e | grown, cur.x);
      StoreEdges(uint(y) * wpr + s, e);
      changed = true;
    }
    prev = e;
    lprev = lcur; lcur = lnx;
    rprev = rcur; rcur = rnx;
    cur = nxt;
  }
}

void main() {
  uint s = gl_GlobalInvocationID.x;
  uint wpr = pc.b;
  if (s >= wpr || flags[pc.a] == 0u) return;
  int h = int(pc.height);
  uint ls = s > 0u ? s - 1u : s, rs = s + 1u < wpr ? s + 1u : s;
  uint lm = s > 0u ? ~0u : 0u, rm = s + 1u < wpr ? ~0u : 0u;
  bool any = false;
  for (uint pass = 0u; pass <= 32u * pc.height; ++pass) {
    bool changed = false;
    Sweep(0, 1, s, ls, rs, lm, rm, wpr, h, changed);
    Sweep(h - 1, -1, s, ls, rs, lm, rm, wpr, h, changed);
    if (!changed) break;
    any = true;
  }
  if (any) SetFlag(pc.a + 1u);  // several invocations may set it: atomically
}

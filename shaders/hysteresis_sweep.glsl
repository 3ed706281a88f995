// hysteresis_sweep: the body of hysteresis.comp, hysteresis_rmw.comp and hysteresis_blocks.comp,
// which define the atomic accessors NeighbourEdges(index) and StoreEdges(index, word) of binding 5
// and PassBarrier() (a workgroup barrier that makes the buffer and shared writes before it visible
// after it), include this file, then define SetPassChanged(slot). hysteresis_blocks.comp defines
// HYSTERESIS_BLOCKS first and gets the blocks' entry point instead of the finishing one.
//
// Canny edge tracking (kernels/hysteresis.h) on bit masks to its global fixed point in one
// dispatch of ONE workgroup (a workgroup barrier is the only device-wide synchronisation a shader
// has): no host loop, no second submit, no flags. Then the edge map that nms_edge_sign.comp wrote
// (the sign class of every weak or strong pixel) keeps the classes of the edge pixels only.
//
// Contract reached: a pixel is an edge exactly when it is weak or strong and 8-connected through
// weak/strong pixels to a strong one. Binding 5 holds, per row y and 32-pixel word s (row-major,
// pc.b words per row), uvec2(candidate, edge): bit k of a word is pixel x = 32 s + k;
// candidate = weak or strong (nms_edge_sign.comp), edge = strong or reached. Padding bits are 0.
//
// Invocation i owns the columns of words (32-pixel strips, all rows) s = i, i + 64, ... and, in
// each pass, sweeps each of them down, then up, until that strip changes no more (one sweep
// carries an edge along the whole strip; see Sweep; every repeat promotes a pixel of the strip,
// so 32 * height + 1 repeats bound it). 8-connectivity inside one row is plain left/right
// adjacency, so a row's candidate runs are flooded with a Kogge-Stone fill. The only write is
// "candidate becomes edge" with an edge neighbour, which is monotone, so stale reads of a
// neighbour strip (written concurrently in the same pass) only delay a promotion, never make a
// wrong one. After each pass a barrier makes every write visible to the whole workgroup; a pass
// in which no invocation changed anything read only final values, so it is a fixed point of the
// global rule, i.e. the contract, and the loop ends (the decision is read from shared memory
// after the barrier, so it is uniform). Every pass that does not end the loop promotes a pixel,
// so width * height + 1 passes bound it.
// The edge words are the only memory one invocation writes while others read it: those accesses
// are atomic (NeighbourEdges / StoreEdges), so there is no data race. hysteresis.comp does them
// as relaxed atomic loads and stores under the Vulkan memory model (plain loads and stores on
// most hardware); hysteresis_rmw.comp, for devices without vulkanMemoryModel, as atomicOr.
//
// The blocks' passes (hysteresis_blocks.comp, dispatched before this one on GPUs with the memory
// model; runtime/vulkan_edge_stage.cc says how many): one invocation per strip and block of
// kBlockRows rows, all workgroups at once, each block swept down and up to its own fixed point given
// what it reads of the others. Its promotions are the same monotone rule, so the result is
// unchanged (the one workgroup still proves the fixed point); they only leave it less to do. A
// chain that crosses a strip's side costs the one workgroup a pass of every strip, and the one
// workgroup runs on one of a GPU's many multiprocessors: an H200 spent 1.2 of the 1.4 ms of a
// 640x480 frame's device time here, 0.36 ms after one blocks' pass (docs/vulkan.md).
//
// Edge map (binding 6): packed bytes (4 pixels per uint, little-endian), rows of 32 * pc.b bytes;
// the bytes of the candidates that did not become edges are cleared (only words that hold one
// are read and written).
//
// 64 invocations: lavapipe runs one workgroup on one CPU thread, 8 lanes per SIMD instruction.
layout(local_size_x = 64) in;

layout(std430, set = 0, binding = 6) buffer Edges { uvec4 edges[]; };
layout(push_constant) uniform Params { uint width; uint height; uint a; uint b; uint c; uint d; } pc;

// Per pass p, slot p % 3: non-zero when an invocation changed something in pass p. Slot
// (p + 1) % 3 is cleared during pass p (its last readers passed the barrier of pass p - 1, its
// next writers run after the barrier of pass p).
shared uint pass_changed[3];
// Sets pass_changed[slot] to 1 atomically (defined by the including shader, after this file).
void SetPassChanged(uint slot);

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

// The (candidate, edge) words of the swept strip at `index`, a row the sweep may not own: in the
// one workgroup an invocation owns every row of its strips (a plain load), in a block the rows
// before and after it are another invocation's (the edge word by NeighbourEdges).
uvec2 StripWords(uint index) {
#ifdef HYSTERESIS_BLOCKS
  return uvec2(masks[index].x, NeighbourEdges(index));
#else
  return masks[index];
#endif
}

// One sweep over `count` rows of the strip, from row `start` in direction `dir` (+1 down, -1 up). A
// row step promotes the candidates touching an edge pixel in the row before (already updated), the
// row itself or the row after, the neighbour strips' bits 31 / 0 included, then floods the row's
// candidate runs. The rows before and after the swept ones (StripWords) and the neighbour strips
// (NeighbourEdges) may belong to other invocations. Loads run one row ahead and are carried, so a
// step does three loads (four in a block) and no data-dependent ones (lavapipe executes both
// sides of a branch, masked, so "rare" loads cost as much as common ones). ls / rs: the neighbour
// strips (clamped), lm / rm: ~0 when they exist.
void Sweep(int start, int dir, int count, uint s, uint ls, uint rs, uint lm, uint rm, uint wpr, int h,
           inout bool changed) {
  int yb = start - dir;
  uint before = (yb >= 0 && yb < h) ? ~0u : 0u;
  uint rowb = uint(clamp(yb, 0, h - 1)) * wpr;
  uint prev = StripWords(rowb + s).y & before;
  uint lprev = NeighbourEdges(rowb + ls) & lm & before, rprev = NeighbourEdges(rowb + rs) & rm & before;
  uvec2 cur = masks[uint(start) * wpr + s];
  uint lcur = NeighbourEdges(uint(start) * wpr + ls) & lm, rcur = NeighbourEdges(uint(start) * wpr + rs) & rm;
  for (int i = 0; i < count; ++i) {
    int y = start + i * dir, ya = y + dir;
    uint inside = (ya >= 0 && ya < h) ? ~0u : 0u;
    uint row = uint(clamp(ya, 0, h - 1)) * wpr;
    uvec2 nxt = StripWords(row + s) & uvec2(inside);
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

// Rows y0 .. y0 + count - 1 of strip s swept down and up until they change no more, given what
// is read of the other rows and strips; whether anything changed. Every repeat promotes a pixel of
// those rows, so 32 * count + 1 repeats bound it.
bool SweepToFixedPoint(uint s, int y0, int count, uint wpr, int h) {
  uint ls = s > 0u ? s - 1u : s, rs = s + 1u < wpr ? s + 1u : s;
  uint lm = s > 0u ? ~0u : 0u, rm = s + 1u < wpr ? ~0u : 0u;
  bool changed = false;
  for (uint local = 0u; local <= 32u * uint(count); ++local) {
    bool again = false;
    Sweep(y0, 1, count, s, ls, rs, lm, rm, wpr, h, again);
    Sweep(y0 + count - 1, -1, count, s, ls, rs, lm, rm, wpr, h, again);
    if (!again) break;
    changed = true;
  }
  return changed;
}

#ifndef HYSTERESIS_BLOCKS

// ~(0xff in the bytes of the pixels whose bit is set), for 4 pixels (bits 0..3 of each word of
// `bits`).
uvec4 KeepMask(uvec4 bits) {
  uvec4 m = (bits & 1u) * 0xffu | ((bits >> 1u) & 1u) * 0xff00u | ((bits >> 2u) & 1u) * 0xff0000u |
            ((bits >> 3u) & 1u) * 0xff000000u;
  return ~m;
}

// Clears the classes of the pixels of word (y, s) whose bit is set in `drop`.
void DropClasses(uint y, uint s, uint drop) {
  uint o = 2u * (y * pc.b + s);
  edges[o] &= KeepMask((uvec4(drop) >> uvec4(0u, 4u, 8u, 12u)) & 15u);
  edges[o + 1u] &= KeepMask((uvec4(drop) >> uvec4(16u, 20u, 24u, 28u)) & 15u);
}

void main() {
  uint lid = gl_LocalInvocationID.x;
  uint wpr = pc.b;
  int h = int(pc.height);
  if (lid < 3u) pass_changed[lid] = 0u;
  barrier();
  uint bound = pc.width * pc.height;  // passes that continue each promote a pixel
  for (uint pass = 0u; pass <= bound; ++pass) {
    bool changed = false;
    for (uint s = lid; s < wpr; s += gl_WorkGroupSize.x) {
      // The strip to its own fixed point (given what it reads of its neighbours) before the
      // barrier: a chain along one strip costs sweeps of that strip only, not passes of all.
      if (SweepToFixedPoint(s, 0, h, wpr, h)) changed = true;
    }
    if (changed) SetPassChanged(pass % 3u);
    if (lid == 0u) pass_changed[(pass + 1u) % 3u] = 0u;
    PassBarrier();
    if (pass_changed[pass % 3u] == 0u) break;  // the same value for every invocation
  }
  // Final edge words (this invocation's own strips): candidates that are not edges lose their class.
  for (uint s = lid; s < wpr; s += gl_WorkGroupSize.x) {
    for (uint y = 0u; y < pc.height; ++y) {
      uvec2 m = masks[y * wpr + s];
      uint drop = m.x & ~m.y;
      if (drop != 0u) DropClasses(y, s, drop);
    }
  }
}

#else  // HYSTERESIS_BLOCKS

const uint kBlockRows = 64u;  // rows per block; runtime/vulkan_edge_stage.cc kHysteresisBlockRows

// Invocation id: strip s = id % pc.b, rows kBlockRows * (id / pc.b) ... to its block's fixed point
// given what it reads of the others.
void main() {
  uint id = gl_GlobalInvocationID.y * (gl_NumWorkGroups.x * gl_WorkGroupSize.x) + gl_GlobalInvocationID.x;
  int h = int(pc.height);
  int y0 = int((id / pc.b) * kBlockRows);
  if (y0 >= h) return;
  SweepToFixedPoint(id % pc.b, y0, min(int(kBlockRows), h - y0), pc.b, h);
}

#endif  // HYSTERESIS_BLOCKS

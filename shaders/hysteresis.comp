// hysteresis: one round of Canny edge tracking (kernels/hysteresis.h), run repeatedly by the host.
//
// Contract reached: a pixel is an edge exactly when it is weak or strong and 8-connected through
// weak/strong pixels to a strong one. Map (binding 7, one uint per pixel): 0 none, 1 weak,
// 2 edge (strong, or weak already reached). The only write is weak -> edge for a weak pixel with an
// edge neighbour, which is monotone, so races between invocations only change how fast, not where,
// the iteration ends.
//
// One round: each 16x16 tile loads itself plus a one-pixel halo into shared memory and promotes
// "weak with an edge neighbour" inside the tile until the tile stops changing (at most 16 * 16
// inner steps: each step that continues promotes at least one of the tile's 256 pixels), then
// writes the promoted pixels back and sets flags[pc.a + 1] = 1 if it promoted any.
// Round r runs only when flags[r] != 0 (the previous round changed something); the host sets
// flags[0] = 1 and the rest to 0 before a batch of rounds and reads the last flag after it.
// A round in which no tile changes anything (halos included) is a fixed point of the global rule,
// i.e. the contract. Every round that does not end the iteration promotes at least one weak pixel,
// so there are at most width * height + 1 rounds (in practice a few: one per tile crossing).
#version 450
layout(local_size_x = 16, local_size_y = 16) in;

layout(std430, set = 0, binding = 7) buffer Map { uint map[]; };
layout(std430, set = 0, binding = 8) buffer Flags { uint flags[]; };
layout(push_constant) uniform Params { uint width; uint height; uint a; uint b; uint c; uint d; } pc;

const int kTile = 16;
const int kSide = kTile + 2;
const uint kWeak = 1u;
const uint kEdge = 2u;

shared uint tile[kSide * kSide];
shared uint tile_changed;

void main() {
  if (flags[pc.a] == 0u) return;  // uniform: written by the previous dispatch, read by all
  int w = int(pc.width), h = int(pc.height);
  int lx = int(gl_LocalInvocationID.x), ly = int(gl_LocalInvocationID.y);
  int ox = int(gl_WorkGroupID.x) * kTile - 1, oy = int(gl_WorkGroupID.y) * kTile - 1;
  uint lid = gl_LocalInvocationIndex;
  for (uint t = lid; t < uint(kSide * kSide); t += 256u) {
    int gx = ox + int(t % uint(kSide)), gy = oy + int(t / uint(kSide));
    uint v = 0u;
    if (gx >= 0 && gy >= 0 && gx < w && gy < h) v = map[uint(gy) * pc.width + uint(gx)];
    tile[t] = v;
  }
  int x = ox + 1 + lx, y = oy + 1 + ly;
  int me = (ly + 1) * kSide + (lx + 1);
  barrier();
  uint initial = tile[me];
  // Bounded: a step that does not exit promotes >= 1 of the 256 tile pixels, so <= 257 steps.
  for (int step = 0; step <= kTile * kTile; ++step) {
    if (lid == 0u) tile_changed = 0u;
    barrier();
    if (tile[me] == kWeak) {
      bool reach = tile[me - kSide - 1] == kEdge || tile[me - kSide] == kEdge || tile[me - kSide + 1] == kEdge ||
                   tile[me - 1] == kEdge || tile[me + 1] == kEdge ||
                   tile[me + kSide - 1] == kEdge || tile[me + kSide] == kEdge || tile[me + kSide + 1] == kEdge;
      if (reach) {
        tile[me] = kEdge;
        tile_changed = 1u;
      }
    }
    barrier();
    uint changed = tile_changed;
    barrier();  // everyone has read tile_changed before thread 0 clears it again
    if (changed == 0u) break;
  }
  if (x < w && y < h && tile[me] != initial) {
    map[uint(y) * pc.width + uint(x)] = kEdge;
    flags[pc.a + 1u] = 1u;
  }
}

// gaussian: 3x3 binomial smoothing, [1 2 1]^T [1 2 1] / 16, replicate border (kernels/gaussian.h).
//   dst(x, y) = (sum w_i w_j src(x+i, y+j) + 8) >> 4; integer only, so bit-identical to the scalar path.
//
// Layout (in and out alike, "padded frame"): packed bytes, rows of pc.b uvec4 = 16 pad bytes, then
// pc.c chunks of 16 pixels, then 16 pad bytes; h + 2 rows, row r (-1..h) at uvec4 (r + 1) * pc.b.
// In (binding 0): the host fills the pads by replication (rows -1 / h, pixels -16..-1 / past the
// end), so no read here needs a border test. Out (binding 1): the blurred frame, its pads filled
// the same way (pixel -1 = pixel 0, pixels past the end = pixel w - 1, rows -1 / h = rows 0 /
// h - 1), which is exactly the replicate border sobel.comp needs, so it reads it without tests.
//
// One invocation: one 16-pixel chunk of kRows rows, keeping the three input rows in registers
// (one uvec4 and two single-word loads per row). Wide accesses matter on lavapipe, where each
// buffer access is a loop over the SIMD lanes; arithmetic runs on all lanes at once.
#version 450
layout(local_size_x = 64) in;

layout(std430, set = 0, binding = 0) readonly buffer Image { uvec4 image[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Blurred { uvec4 blurred[]; };
layout(push_constant) uniform Params { uint width; uint height; uint a; uint b; uint c; uint d; } pc;

const uint kRows = 8u;

// 16 pixels of a row chunk (p0 = pixels 0..3, ...) and the pixels just left and right of it.
struct Chunk { uvec4 p0, p1, p2, p3; uint l, r; };

uvec4 Bytes(uint word) { return (uvec4(word) >> uvec4(0u, 8u, 16u, 24u)) & 255u; }
uint PackBytes(uvec4 v) { return v.x | (v.y << 8u) | (v.z << 16u) | (v.w << 24u); }

Chunk Load(int row, uint cx) {
  uint i = uint(row + 1) * pc.b + 1u + cx;
  uvec4 q = image[i];
  Chunk c;
  c.p0 = Bytes(q.x); c.p1 = Bytes(q.y); c.p2 = Bytes(q.z); c.p3 = Bytes(q.w);
  c.l = image[i - 1u].w >> 24u;
  c.r = image[i + 1u].x & 255u;
  return c;
}

void Store(int row, uint cx, uvec4 packed, uint first, uint last) {
  uint i = uint(row + 1) * pc.b + 1u + cx;
  blurred[i] = packed;
  if (cx == 0u) blurred[i - 1u].w = first * 0x01010101u;
  if (cx + 1u == pc.c) blurred[i + 1u].x = last * 0x01010101u;
}

void main() {
  uint id = gl_GlobalInvocationID.y * (gl_NumWorkGroups.x * gl_WorkGroupSize.x) + gl_GlobalInvocationID.x;
  uint cx = id % pc.c, block = id / pc.c;
  int h = int(pc.height);
  int y0 = int(block * kRows);
  if (y0 >= h) return;
  int y1 = min(y0 + int(kRows), h);
  int last_k = int(pc.width) - 1 - int(16u * cx);  // pixel w - 1 within this chunk when 0..15
  Chunk a = Load(y0 - 1, cx), b = Load(y0, cx);
  uvec4 top = uvec4(0u), bottom = uvec4(0u);
  uint top_first = 0u, top_last = 0u, bottom_first = 0u, bottom_last = 0u;
  for (int y = y0; y < y1; ++y) {
    Chunk c = Load(y + 1, cx);
    uvec4 v0 = a.p0 + 2u * b.p0 + c.p0, v1 = a.p1 + 2u * b.p1 + c.p1;
    uvec4 v2 = a.p2 + 2u * b.p2 + c.p2, v3 = a.p3 + 2u * b.p3 + c.p3;
    uint vl = a.l + 2u * b.l + c.l, vr = a.r + 2u * b.r + c.r;
    uvec4 o0 = (uvec4(vl, v0.xyz) + 2u * v0 + uvec4(v0.yzw, v1.x) + 8u) >> 4u;
    uvec4 o1 = (uvec4(v0.w, v1.xyz) + 2u * v1 + uvec4(v1.yzw, v2.x) + 8u) >> 4u;
    uvec4 o2 = (uvec4(v1.w, v2.xyz) + 2u * v2 + uvec4(v2.yzw, v3.x) + 8u) >> 4u;
    uvec4 o3 = (uvec4(v2.w, v3.xyz) + 2u * v3 + uvec4(v3.yzw, vr) + 8u) >> 4u;
    if (last_k < 15) {
      // The row ends inside this chunk: pixels past it repeat pixel w - 1 (replicate border).
      ivec4 k0 = ivec4(0, 1, 2, 3);
      uvec4 at = mix(uvec4(0u), o0, equal(k0, ivec4(last_k))) + mix(uvec4(0u), o1, equal(k0 + 4, ivec4(last_k))) +
                 mix(uvec4(0u), o2, equal(k0 + 8, ivec4(last_k))) + mix(uvec4(0u), o3, equal(k0 + 12, ivec4(last_k)));
      uint end = at.x + at.y + at.z + at.w;
      o0 = mix(o0, uvec4(end), greaterThan(k0, ivec4(last_k)));
      o1 = mix(o1, uvec4(end), greaterThan(k0 + 4, ivec4(last_k)));
      o2 = mix(o2, uvec4(end), greaterThan(k0 + 8, ivec4(last_k)));
      o3 = mix(o3, uvec4(end), greaterThan(k0 + 12, ivec4(last_k)));
    }
    uvec4 packed = uvec4(PackBytes(o0), PackBytes(o1), PackBytes(o2), PackBytes(o3));
    Store(y, cx, packed, o0.x, o3.w);
    if (y == y0) { top = packed; top_first = o0.x; top_last = o3.w; }
    bottom = packed; bottom_first = o0.x; bottom_last = o3.w;
    a = b;
    b = c;
  }
  // Replicated rows -1 and h, stored outside the loop (a branch inside it would run every row).
  if (y0 == 0) Store(-1, cx, top, top_first, top_last);
  if (y1 == h) Store(h, cx, bottom, bottom_first, bottom_last);
}

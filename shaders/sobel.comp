// sobel: 3x3 Sobel dx, dy and L1 magnitude, replicate border (kernels/sobel.h). Integer only.
//   dx = sum_j w_j (src(x+1, y+j) - src(x-1, y+j)),  dy = sum_i w_i (src(x+i, y+1) - src(x+i, y-1)),
//   mag = |dx| + |dy|  (|dx|, |dy| <= 1020, mag <= 2040).
// In:  the padded frame of gaussian.comp (pads hold the replicate border, so no border tests):
//      FROM_BLURRED (specialisation constant 0) == 1: binding 1 (the Gaussian output); else
//      binding 0 (the frame as uploaded). A constant, not a push constant: lavapipe runs both sides
//      of a branch (masked), so a run-time choice would load from both buffers.
// Out: bindings 2 / 3: dx / dy (int16), packed two per uint (pixel 2k in the
//      low half), rows of pc.d uvec4 = 8 * pc.d elements (a whole number of 32-pixel hysteresis
//      mask words, >= the pc.c chunks of 16 pixels written here; elements past the row end are
//      don't-care). dx and dy are what the host downloads. mag is not stored: its readers
//      (histogram, nms) recompute |dx| + |dy|, cheaper than a third plane of stores on lavapipe.
// One invocation: one 16-pixel chunk of kRows rows, the three input rows kept in registers.
#version 450
layout(local_size_x = 64) in;

layout(std430, set = 0, binding = 0) readonly buffer Image { uvec4 image[]; };
layout(std430, set = 0, binding = 1) readonly buffer Blurred { uvec4 blurred[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Dx { uvec4 dx[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Dy { uvec4 dy[]; };
layout(push_constant) uniform Params { uint width; uint height; uint a; uint b; uint c; uint d; } pc;

layout(constant_id = 0) const uint FROM_BLURRED = 1u;
const uint kRows = 8u;

struct Chunk { ivec4 p0, p1, p2, p3; int l, r; };

ivec4 Bytes(uint word) { return ivec4((uvec4(word) >> uvec4(0u, 8u, 16u, 24u)) & 255u); }

Chunk Load(int row, uint cx) {
  uint i = uint(row + 1) * pc.b + 1u + cx;
  uvec4 q;
  uint l, r;
  if (FROM_BLURRED == 1u) {
    q = blurred[i]; l = blurred[i - 1u].w; r = blurred[i + 1u].x;
  } else {
    q = image[i]; l = image[i - 1u].w; r = image[i + 1u].x;
  }
  Chunk c;
  c.p0 = Bytes(q.x); c.p1 = Bytes(q.y); c.p2 = Bytes(q.z); c.p3 = Bytes(q.w);
  c.l = int(l >> 24u);
  c.r = int(r & 255u);
  return c;
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

void main() {
  uint id = gl_GlobalInvocationID.y * (gl_NumWorkGroups.x * gl_WorkGroupSize.x) + gl_GlobalInvocationID.x;
  uint cx = id % pc.c, block = id / pc.c;
  int h = int(pc.height);
  int y0 = int(block * kRows);
  if (y0 >= h) return;
  int y1 = min(y0 + int(kRows), h);
  Chunk a = Load(y0 - 1, cx), b = Load(y0, cx);
  ivec4 sa0, sa1, sa2, sa3, sb0, sb1, sb2, sb3;  // row-smoothed rows y - 1 and y
  Smooth(a, sa0, sa1, sa2, sa3);
  Smooth(b, sb0, sb1, sb2, sb3);
  for (int y = y0; y < y1; ++y) {
    Chunk c = Load(y + 1, cx);
    ivec4 sc0, sc1, sc2, sc3;
    Smooth(c, sc0, sc1, sc2, sc3);
    // Column sums [1 2 1]^T, then their difference one pixel right minus one pixel left.
    ivec4 v0 = a.p0 + 2 * b.p0 + c.p0, v1 = a.p1 + 2 * b.p1 + c.p1;
    ivec4 v2 = a.p2 + 2 * b.p2 + c.p2, v3 = a.p3 + 2 * b.p3 + c.p3;
    int vl = a.l + 2 * b.l + c.l, vr = a.r + 2 * b.r + c.r;
    ivec4 gx0 = ivec4(v0.yzw, v1.x) - ivec4(vl, v0.xyz);
    ivec4 gx1 = ivec4(v1.yzw, v2.x) - ivec4(v0.w, v1.xyz);
    ivec4 gx2 = ivec4(v2.yzw, v3.x) - ivec4(v1.w, v2.xyz);
    ivec4 gx3 = ivec4(v3.yzw, vr) - ivec4(v2.w, v3.xyz);
    ivec4 gy0 = sc0 - sa0, gy1 = sc1 - sa1, gy2 = sc2 - sa2, gy3 = sc3 - sa3;
    uint o = uint(y) * pc.d + 2u * cx;
    dx[o] = Pack16(gx0, gx1);
    dx[o + 1u] = Pack16(gx2, gx3);
    dy[o] = Pack16(gy0, gy1);
    dy[o + 1u] = Pack16(gy2, gy3);
    a = b;
    b = c;
    sa0 = sb0; sa1 = sb1; sa2 = sb2; sa3 = sb3;
    sb0 = sc0; sb1 = sc1; sb2 = sc2; sb3 = sc3;
  }
}

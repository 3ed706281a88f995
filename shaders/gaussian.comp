// gaussian: 3x3 binomial smoothing, [1 2 1]^T [1 2 1] / 16, replicate border (kernels/gaussian.h).
//   dst(x, y) = (sum w_i w_j src(x+i, y+j) + 8) >> 4; integer only, so bit-identical to the scalar path.
// In:  binding 0, the frame as packed bytes (4 pixels per uint, little-endian, rows `width` bytes).
// Out: binding 1, one uint per pixel (an internal buffer: portable without 8-bit storage features).
#version 450
layout(local_size_x = 16, local_size_y = 16) in;

layout(std430, set = 0, binding = 0) readonly buffer Image { uint image[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Blurred { uint blurred[]; };
layout(push_constant) uniform Params { uint width; uint height; uint a; uint b; uint c; uint d; } pc;

uint Src(int x, int y) {
  uint i = uint(y) * pc.width + uint(x);
  return (image[i >> 2] >> ((i & 3u) * 8u)) & 255u;
}

void main() {
  int x = int(gl_GlobalInvocationID.x), y = int(gl_GlobalInvocationID.y);
  int w = int(pc.width), h = int(pc.height);
  if (x >= w || y >= h) return;
  int xl = max(x - 1, 0), xr = min(x + 1, w - 1), yu = max(y - 1, 0), yd = min(y + 1, h - 1);
  uint left = Src(xl, yu) + 2u * Src(xl, y) + Src(xl, yd);
  uint centre = Src(x, yu) + 2u * Src(x, y) + Src(x, yd);
  uint right = Src(xr, yu) + 2u * Src(xr, y) + Src(xr, yd);
  blurred[uint(y) * pc.width + uint(x)] = (left + 2u * centre + right + 8u) >> 4;
}

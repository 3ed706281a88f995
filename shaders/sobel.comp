// sobel: 3x3 Sobel dx, dy and L1 magnitude, replicate border (kernels/sobel.h). Integer only.
//   dx = sum_j w_j (src(x+1, y+j) - src(x-1, y+j)),  dy = sum_i w_i (src(x+i, y+1) - src(x+i, y-1)),
//   mag = |dx| + |dy|  (|dx|, |dy| <= 1020, mag <= 2040).
// In:  pc.a == 1: binding 1 (one uint per pixel, the Gaussian output); else binding 0 (packed bytes).
// Out: bindings 2 / 3, dx / dy as packed int16 pairs (pixel 2k in the low half of word k, i.e. the
//      little-endian int16 array the host downloads as is); binding 4, mag, one uint per pixel.
// One invocation writes one packed word = two consecutive pixels of the row-major frame.
#version 450
layout(local_size_x = 256) in;

layout(std430, set = 0, binding = 0) readonly buffer Image { uint image[]; };
layout(std430, set = 0, binding = 1) readonly buffer Blurred { uint blurred[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Dx { uint dx[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Dy { uint dy[]; };
layout(std430, set = 0, binding = 4) writeonly buffer Mag { uint mag[]; };
layout(push_constant) uniform Params { uint width; uint height; uint a; uint b; uint c; uint d; } pc;

int Src(int x, int y) {
  uint i = uint(y) * pc.width + uint(x);
  if (pc.a == 1u) return int(blurred[i]);
  return int((image[i >> 2] >> ((i & 3u) * 8u)) & 255u);
}

void main() {
  uint word = gl_GlobalInvocationID.y * (gl_NumWorkGroups.x * gl_WorkGroupSize.x) + gl_GlobalInvocationID.x;
  uint n = pc.width * pc.height;
  if (2u * word >= n) return;
  int w = int(pc.width), h = int(pc.height);
  uint packed_dx = 0u, packed_dy = 0u;
  for (uint k = 0u; k < 2u; ++k) {
    uint i = 2u * word + k;
    if (i >= n) break;
    int y = int(i / pc.width), x = int(i % pc.width);
    int xl = max(x - 1, 0), xr = min(x + 1, w - 1), yu = max(y - 1, 0), yd = min(y + 1, h - 1);
    int gx = (Src(xr, yu) + 2 * Src(xr, y) + Src(xr, yd)) - (Src(xl, yu) + 2 * Src(xl, y) + Src(xl, yd));
    int gy = (Src(xl, yd) + 2 * Src(x, yd) + Src(xr, yd)) - (Src(xl, yu) + 2 * Src(x, yu) + Src(xr, yu));
    packed_dx |= (uint(gx) & 0xffffu) << (16u * k);
    packed_dy |= (uint(gy) & 0xffffu) << (16u * k);
    mag[i] = uint(abs(gx) + abs(gy));
  }
  dx[word] = packed_dx;
  dy[word] = packed_dy;
}

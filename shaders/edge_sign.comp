// edge_sign: gradient-sign class of each edge pixel, paper eq. 1 (kernels/edge_sign.h). Integer only:
//   out = 1 when edge and dx * dy > 0, 2 when edge and dx * dy < 0, else 0 (|dx * dy| <= 1020^2).
// In: binding 7 (hysteresis map, edge == 2), bindings 2 / 3 (packed int16 dx / dy).
// Out: binding 9, packed bytes (4 pixels per uint, little-endian): the uint8 edge map as downloaded.
#version 450
layout(local_size_x = 256) in;

layout(std430, set = 0, binding = 2) readonly buffer Dx { uint dx[]; };
layout(std430, set = 0, binding = 3) readonly buffer Dy { uint dy[]; };
layout(std430, set = 0, binding = 7) readonly buffer Map { uint map[]; };
layout(std430, set = 0, binding = 9) writeonly buffer Edges { uint edges[]; };
layout(push_constant) uniform Params { uint width; uint height; uint a; uint b; uint c; uint d; } pc;

int Unpack16(uint word, uint i) { return bitfieldExtract(int(word), int((i & 1u) * 16u), 16); }

void main() {
  uint word = gl_GlobalInvocationID.y * (gl_NumWorkGroups.x * gl_WorkGroupSize.x) + gl_GlobalInvocationID.x;
  uint n = pc.width * pc.height;
  if (4u * word >= n) return;
  uint packed = 0u;
  for (uint k = 0u; k < 4u; ++k) {
    uint i = 4u * word + k;
    if (i >= n) break;
    if (map[i] != 2u) continue;
    int p = Unpack16(dx[i >> 1], i) * Unpack16(dy[i >> 1], i);
    uint cls = p > 0 ? 1u : (p < 0 ? 2u : 0u);
    packed |= cls << (8u * k);
  }
  edges[word] = packed;
}

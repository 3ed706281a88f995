// edge_sign: gradient-sign class of each edge pixel, paper eq. 1 (kernels/edge_sign.h). Integer only:
//   out = 1 when edge and dx * dy > 0, 2 when edge and dx * dy < 0, else 0 (|dx * dy| <= 1020^2).
// In: binding 6 (hysteresis.comp bit masks: the edge bit of pixel (x, y) is bit x % 32 of
// masks[y * pc.b + x / 32].y), bindings 2 / 3 (dx / dy as sobel.comp packs them, rows of pc.d uvec4).
// Out: binding 8, packed bytes (4 pixels per uint, little-endian), rows of 16 * pc.c bytes: the
// uint8 edge map the host downloads (bytes past the row end are don't-care).
// One invocation: one 16-pixel chunk of a row.
#version 450
layout(local_size_x = 64) in;

layout(std430, set = 0, binding = 2) readonly buffer Dx { uvec4 dx[]; };
layout(std430, set = 0, binding = 3) readonly buffer Dy { uvec4 dy[]; };
layout(std430, set = 0, binding = 6) readonly buffer Masks { uvec2 masks[]; };
layout(std430, set = 0, binding = 8) writeonly buffer Edges { uvec4 edges[]; };
layout(push_constant) uniform Params { uint width; uint height; uint a; uint b; uint c; uint d; } pc;

// Classes of 4 pixels (edge bits in `bits`) packed into the bytes of one word.
uint Classes(uvec4 gx2, uvec4 gy2, uint bits) {
  // gx2 / gy2 hold 4 pixels' values sign-extended from their 16-bit halves by the caller.
  ivec4 p = ivec4(gx2) * ivec4(gy2);
  uvec4 cls = mix(mix(uvec4(0u), uvec4(2u), lessThan(p, ivec4(0))), uvec4(1u), greaterThan(p, ivec4(0)));
  cls *= (uvec4(bits) >> uvec4(0u, 1u, 2u, 3u)) & 1u;  // 0 off the edge
  return cls.x | (cls.y << 8u) | (cls.z << 16u) | (cls.w << 24u);
}

uvec4 Lo(uvec4 v) { return uvec4(ivec4(uvec4(v.xxyy) << uvec4(16u, 0u, 16u, 0u)) >> 16); }
uvec4 Hi(uvec4 v) { return uvec4(ivec4(uvec4(v.zzww) << uvec4(16u, 0u, 16u, 0u)) >> 16); }

void main() {
  uint id = gl_GlobalInvocationID.y * (gl_NumWorkGroups.x * gl_WorkGroupSize.x) + gl_GlobalInvocationID.x;
  uint cx = id % pc.c, y = id / pc.c;
  if (y >= pc.height) return;
  uint bits = (masks[y * pc.b + (cx >> 1u)].y >> (16u * (cx & 1u))) & 0xffffu;
  uint q = y * pc.d + 2u * cx;
  uvec4 out4 = uvec4(0u);
  if (bits != 0u) {
    uvec4 x0 = dx[q], x1 = dx[q + 1u], y0 = dy[q], y1 = dy[q + 1u];
    out4 = uvec4(Classes(Lo(x0), Lo(y0), bits), Classes(Hi(x0), Hi(y0), bits >> 4u),
                 Classes(Lo(x1), Lo(y1), bits >> 8u), Classes(Hi(x1), Hi(y1), bits >> 12u));
  }
  edges[y * pc.c + cx] = out4;
}

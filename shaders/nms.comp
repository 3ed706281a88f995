// nms: Canny non-maximum suppression with the two thresholds applied (kernels/nms.h). Integer only:
//   ax = |dx|, ay = |dy|;  (ay << 15) < 13573 ax -> horizontal neighbours (x-1, y), (x+1, y)
//                          (ay << 15) > 79109 ax -> vertical neighbours (x, y-1), (x, y+1)
//                          otherwise diagonal, s = (dx, dy same sign) ? 1 : -1: (x-s, y-1), (x+s, y+1)
//   local max: mag > first and mag >= second (diagonal: > both); mag <= low is never an edge.
// Out (binding 7, one uint per pixel): 0 none, 1 weak (mag > low), 2 strong (mag > high);
// the outermost rows and columns are 0. Thresholds come from binding 6 (canny_thresholds.comp).
#version 450
layout(local_size_x = 16, local_size_y = 16) in;

layout(std430, set = 0, binding = 2) readonly buffer Dx { uint dx[]; };
layout(std430, set = 0, binding = 3) readonly buffer Dy { uint dy[]; };
layout(std430, set = 0, binding = 4) readonly buffer Mag { uint mag[]; };
layout(std430, set = 0, binding = 6) readonly buffer Thresholds { uint params[]; };
layout(std430, set = 0, binding = 7) writeonly buffer Map { uint map[]; };
layout(push_constant) uniform Params { uint width; uint height; uint a; uint b; uint c; uint d; } pc;

int Unpack16(uint word, uint i) { return bitfieldExtract(int(word), int((i & 1u) * 16u), 16); }
int M(int x, int y) { return int(mag[uint(y) * pc.width + uint(x)]); }

void main() {
  int x = int(gl_GlobalInvocationID.x), y = int(gl_GlobalInvocationID.y);
  int w = int(pc.width), h = int(pc.height);
  if (x >= w || y >= h) return;
  uint i = uint(y) * pc.width + uint(x);
  uint result = 0u;
  int low = int(params[0]), high = int(params[1]);
  int m = int(mag[i]);
  if (x > 0 && y > 0 && x < w - 1 && y < h - 1 && m > low) {
    int gx = Unpack16(dx[i >> 1], i), gy = Unpack16(dy[i >> 1], i);
    int ax = abs(gx), ay = abs(gy);
    int ay15 = ay << 15;
    bool is_max;
    if (ay15 < 13573 * ax) {
      is_max = m > M(x - 1, y) && m >= M(x + 1, y);
    } else if (ay15 > 79109 * ax) {
      is_max = m > M(x, y - 1) && m >= M(x, y + 1);
    } else {
      int s = ((gx ^ gy) < 0) ? -1 : 1;
      is_max = m > M(x - s, y - 1) && m > M(x + s, y + 1);
    }
    if (is_max) result = (m > high) ? 2u : 1u;
  }
  map[i] = result;
}

// nms_edge_sign: two kernels in one pass: Canny non-maximum suppression with the two thresholds
// applied (kernels/nms.h), and the gradient-sign class (kernels/edge_sign.h, paper eq. 1) of
// every pixel it keeps. Integer only:
//   ax = |dx|, ay = |dy|;  (ay << 15) < 13573 ax -> horizontal neighbours (x-1, y), (x+1, y)
//                          (ay << 15) > 79109 ax -> vertical neighbours (x, y-1), (x, y+1)
//                          otherwise diagonal, s = (dx, dy same sign) ? 1 : -1: (x-s, y-1), (x+s, y+1)
//   local max: mag > first and mag >= second (diagonal: > both); mag <= low is never an edge.
//   class = 1 when dx * dy > 0, 2 when dx * dy < 0, 0 otherwise (|dx * dy| <= 1020^2), for the
//   weak and strong pixels; 0 for the others. Which of them are edges is hysteresis.comp's to
//   decide: it clears the classes of the weak pixels that are not. Classifying here, where dx
//   and dy are already in registers and all workgroups run in parallel, spares the one-workgroup
//   hysteresis dispatch a pass over dx and dy.
// In: dx, dy as gaussian_sobel_thresholds.comp packs them (two int16 per uint, rows of pc.d =
// 4 * pc.b uvec4, i.e. whole mask words; values past the row end are don't-care),
// mag = |dx| + |dy| recomputed; thresholds from binding 4 (gaussian_sobel_thresholds.comp): tile
// t's pair at params[2 t], params[2 t + 1], t = (y >> pc.e) * pc.f + (x >> pc.e) (kernels/nms.h).
// Out: binding 5, the bit masks of hysteresis.comp: per row y and 32-pixel word s (pc.b words per
// row), uvec2(weak or strong, strong), bit k = pixel x = 32 s + k; the outermost rows and columns
// and the bits past the row end are 0. Binding 6, the edge map: packed bytes (4 pixels per uint,
// little-endian), rows of 32 * pc.b bytes, every word written (the host reads the first w bytes).
// One invocation: one mask word (32 pixels) of kRows rows, the three gradient rows carried in
// registers; 8 pixels (one uvec4 per row) at a time in vector registers. Tiles are >= 32 px, so
// the word's rows and pixels lie in one tile.
#version 450
layout(local_size_x = 64) in;

layout(std430, set = 0, binding = 1) readonly buffer Dx { uvec4 dx[]; };
layout(std430, set = 0, binding = 2) readonly buffer Dy { uvec4 dy[]; };
layout(std430, set = 0, binding = 4) readonly buffer Thresholds { uint params[]; };
layout(std430, set = 0, binding = 5) writeonly buffer Masks { uvec2 masks[]; };
layout(std430, set = 0, binding = 6) writeonly buffer Edges { uvec4 edges[]; };
layout(push_constant) uniform Params { uint width; uint height; uint a; uint b; uint c; uint d; uint e; uint f; } pc;

const uint kRows = 8u;

// Eight packed int16 (value 2k in the low half of word k): pixels 0..3 in lo, 4..7 in hi.
void Signed16(uvec4 v, out ivec4 lo, out ivec4 hi) {
  lo = ivec4(uvec4(v.xxyy) << uvec4(16u, 0u, 16u, 0u)) >> 16;
  hi = ivec4(uvec4(v.zzww) << uvec4(16u, 0u, 16u, 0u)) >> 16;
}

// A row's 32 pixels of dx and dy (x0 / y0 = pixels 0..7, ...) plus the magnitudes of the pixels
// just left and right of them.
struct Row { uvec4 x0, x1, x2, x3, y0, y1, y2, y3; int l, r; };

Row LoadRow(int y, uint s, bool has_left, bool has_right) {
  uint q = uint(y) * pc.d + 4u * s;
  Row row;
  row.x0 = dx[q]; row.x1 = dx[q + 1u]; row.x2 = dx[q + 2u]; row.x3 = dx[q + 3u];
  row.y0 = dy[q]; row.y1 = dy[q + 1u]; row.y2 = dy[q + 2u]; row.y3 = dy[q + 3u];
  row.l = has_left ? abs(int(dx[q - 1u].w) >> 16) + abs(int(dy[q - 1u].w) >> 16) : 0;
  row.r = has_right ? abs(int(dx[q + 4u].x << 16u) >> 16) + abs(int(dy[q + 4u].x << 16u) >> 16) : 0;
  return row;
}

// Group j (8 pixels) of a row: gradients, magnitudes, and the magnitudes of the pixels left and
// right of the group. j is a constant at every call, so the selects fold away.
void Group(Row row, uint j, out ivec4 gxl, out ivec4 gxh, out ivec4 gyl, out ivec4 gyh, out ivec4 mlo,
           out ivec4 mhi, out int l, out int r) {
  uvec4 qx = j == 0u ? row.x0 : j == 1u ? row.x1 : j == 2u ? row.x2 : row.x3;
  uvec4 qy = j == 0u ? row.y0 : j == 1u ? row.y1 : j == 2u ? row.y2 : row.y3;
  Signed16(qx, gxl, gxh);
  Signed16(qy, gyl, gyh);
  mlo = abs(gxl) + abs(gyl);
  mhi = abs(gxh) + abs(gyh);
  if (j == 0u) {
    l = row.l;
  } else {
    uvec4 px = j == 1u ? row.x0 : j == 2u ? row.x1 : row.x2, py = j == 1u ? row.y0 : j == 2u ? row.y1 : row.y2;
    l = abs(int(px.w) >> 16) + abs(int(py.w) >> 16);
  }
  if (j == 3u) {
    r = row.r;
  } else {
    uvec4 nx = j == 0u ? row.x1 : j == 1u ? row.x2 : row.x3, ny = j == 0u ? row.y1 : j == 1u ? row.y2 : row.y3;
    r = abs(int(nx.x << 16u) >> 16) + abs(int(ny.x << 16u) >> 16);
  }
}

// 4 pixels: bit k of the result for pixel k when it is a local maximum above `low`; `strong` the
// same for mag > high. l/r: the pixels' left/right neighbours on their own row, u*/d*: above/below.
uint Classify(ivec4 m, ivec4 l, ivec4 r, ivec4 u, ivec4 ul, ivec4 ur, ivec4 d, ivec4 dl, ivec4 dr,
              ivec4 gx, ivec4 gy, ivec4 x, int low, int high, out uint strong) {
  ivec4 ax = abs(gx), ay = abs(gy);
  ivec4 ay15 = ay << 15;
  bvec4 horiz = lessThan(ay15, 13573 * ax);
  bvec4 vert = greaterThan(ay15, 79109 * ax);
  bvec4 same = greaterThanEqual(gx ^ gy, ivec4(0));
  ivec4 first = mix(mix(mix(ur, ul, same), u, vert), l, horiz);
  ivec4 second = mix(mix(mix(dl, dr, same), d, vert), r, horiz);
  uvec4 diag = uvec4(not(horiz)) & uvec4(not(vert));
  uvec4 beats_second = uvec4(greaterThan(m, second)) | (uvec4(equal(m, second)) & (1u - diag));
  uvec4 ok = uvec4(greaterThan(m, first)) & beats_second & uvec4(greaterThan(m, ivec4(low))) &
             uvec4(greaterThanEqual(x, ivec4(1))) & uvec4(lessThan(x, ivec4(int(pc.width) - 1)));
  uvec4 st = ok & uvec4(greaterThan(m, ivec4(high)));
  uvec4 shift = uvec4(0u, 1u, 2u, 3u);
  uvec4 sb = st << shift, cb = ok << shift;
  strong = sb.x | sb.y | sb.z | sb.w;
  return cb.x | cb.y | cb.z | cb.w;
}

// Sign classes of 4 pixels (0 where `bits` has no bit) packed into the bytes of one word.
uint Classes(ivec4 gx, ivec4 gy, uint bits) {
  ivec4 p = gx * gy;
  uvec4 cls = mix(mix(uvec4(0u), uvec4(2u), lessThan(p, ivec4(0))), uvec4(1u), greaterThan(p, ivec4(0)));
  cls *= (uvec4(bits) >> uvec4(0u, 1u, 2u, 3u)) & 1u;
  return cls.x | (cls.y << 8u) | (cls.z << 16u) | (cls.w << 24u);
}

// Pixels 8 j .. 8 j + 7 of the word: candidate bits (returned) and strong bits, in the low byte;
// the candidates' classes, pixels 0..3 and 4..7 (two words of the edge map).
uint ClassifyGroup(Row u, Row c, Row d, uint j, int x0, int low, int high, out uint strong, out uvec2 classes) {
  ivec4 gxl, gxh, gyl, gyh, ulo, uhi, clo, chi, dlo, dhi, unused;
  int ul, ur, cl, cr, dl, dr;
  Group(u, j, unused, unused, unused, unused, ulo, uhi, ul, ur);
  Group(d, j, unused, unused, unused, unused, dlo, dhi, dl, dr);
  Group(c, j, gxl, gxh, gyl, gyh, clo, chi, cl, cr);
  ivec4 xl = ivec4(x0) + ivec4(0, 1, 2, 3);
  uint st_lo, st_hi;
  uint c_lo = Classify(clo, ivec4(cl, clo.xyz), ivec4(clo.yzw, chi.x), ulo, ivec4(ul, ulo.xyz), ivec4(ulo.yzw, uhi.x),
                       dlo, ivec4(dl, dlo.xyz), ivec4(dlo.yzw, dhi.x), gxl, gyl, xl, low, high, st_lo);
  uint c_hi = Classify(chi, ivec4(clo.w, chi.xyz), ivec4(chi.yzw, cr), uhi, ivec4(ulo.w, uhi.xyz), ivec4(uhi.yzw, ur),
                       dhi, ivec4(dlo.w, dhi.xyz), ivec4(dhi.yzw, dr), gxh, gyh, xl + 4, low, high, st_hi);
  strong = st_lo | (st_hi << 4u);
  classes = uvec2(Classes(gxl, gyl, c_lo), Classes(gxh, gyh, c_hi));
  return c_lo | (c_hi << 4u);
}

void main() {
  uint id = gl_GlobalInvocationID.y * (gl_NumWorkGroups.x * gl_WorkGroupSize.x) + gl_GlobalInvocationID.x;
  uint s = id % pc.b, block = id / pc.b;
  int w = int(pc.width), h = int(pc.height);
  int y0 = int(block * kRows);
  if (y0 >= h) return;
  int y1 = min(y0 + int(kRows), h);
  uint tile = (uint(y0) >> pc.e) * pc.f + ((32u * s) >> pc.e);
  int low = int(params[2u * tile]), high = int(params[2u * tile + 1u]);
  bool has_left = s > 0u, has_right = s + 1u < pc.b;
  int x0 = int(32u * s);
  // Rows y - 1, y, y + 1, carried down the block; rows 0 and h - 1 are all zero (border).
  Row u = LoadRow(max(y0 - 1, 0), s, has_left, has_right);
  Row c = LoadRow(y0, s, has_left, has_right);
  for (int y = y0; y < y1; ++y) {
    Row d = LoadRow(min(y + 1, h - 1), s, has_left, has_right);
    uint cand = 0u, strong = 0u;
    uvec2 cls[4] = uvec2[4](uvec2(0u), uvec2(0u), uvec2(0u), uvec2(0u));
    if (y > 0 && y < h - 1) {
      for (uint j = 0u; j < 4u; ++j) {
        uint st;
        uint cb = ClassifyGroup(u, c, d, j, x0 + int(8u * j), low, high, st, cls[j]);
        cand |= cb << (8u * j);
        strong |= st << (8u * j);
      }
    }
    uint word = uint(y) * pc.b + s;
    masks[word] = uvec2(cand, strong);
    edges[2u * word] = uvec4(cls[0], cls[1]);
    edges[2u * word + 1u] = uvec4(cls[2], cls[3]);
    u = c;
    c = d;
  }
}

// World rendering: ray casting, shading, textures, blur and noise, a scene's truth.
#include "tools/scenes/world.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace ellipsekit::scenes::detail {

// ---------------------------------------------------------------- ray casting
// A jar with a narrower lid: the lid (top disc and side, shoulder_h..h) on the body (shoulder ring
// and side, 0..shoulder_h); the nearest of the four surfaces.
bool World::IntersectJar(const Cylinder& c, V3 D, double s_max, Hit* h) const {
  const V3 O = cam_.pos;
  const double ox = O.x - c.x, oy = O.y - c.y;
  double best = s_max, rho2 = 0;
  int part = -1;
  auto disc = [&](double z, double rmin2, double rmax2, int p) {
    if (D.z >= 0) return;
    const double st = (z - O.z) / D.z;
    if (!(st > 0 && st < best)) return;
    const double qx = ox + st * D.x, qy = oy + st * D.y, rr = qx * qx + qy * qy;
    if (rr <= rmax2 && rr >= rmin2) {
      best = st;
      part = p;
      rho2 = rr;
    }
  };
  auto side = [&](double r2, double z0, double z1, int p) {
    const double A = D.x * D.x + D.y * D.y;
    if (A < 1e-18) return;
    const double B = ox * D.x + oy * D.y, C = ox * ox + oy * oy - r2;
    const double d = B * B - A * C;
    if (d < 0) return;
    const double s1 = (-B - std::sqrt(d)) / A;
    if (!(s1 > 0 && s1 < best)) return;
    const double z = O.z + s1 * D.z;
    if (z < z0 || z > z1) return;
    best = s1;
    part = p;
  };
  // A bottle's shoulder: radius rho(z) = r + k (z - shoulder_h) from shoulder_h up to neck_h;
  // |(ox, oy) + s (Dx, Dy)|^2 = (q0 + q1 s)^2 is quadratic in s.
  auto cone = [&]() {
    const double k = (c.lid_r - c.r) / (c.neck_h - c.shoulder_h);
    const double q0 = c.r + k * (O.z - c.shoulder_h), q1 = k * D.z;
    const double A = D.x * D.x + D.y * D.y - q1 * q1, B = ox * D.x + oy * D.y - q0 * q1;
    const double C = ox * ox + oy * oy - q0 * q0, d = B * B - A * C;
    if (d < 0 || std::abs(A) < 1e-18) return;
    for (const double st : {(-B - std::sqrt(d)) / A, (-B + std::sqrt(d)) / A}) {
      const double z = O.z + st * D.z;
      if (st > 0 && st < best && z >= c.shoulder_h && z <= c.neck_h && q0 + q1 * st >= 0) {
        best = st;
        part = kShoulder;
      }
    }
  };
  const double lr2 = c.lid_r * c.lid_r;
  disc(c.h, 0, lr2, kTop);
  side(lr2, c.bottle() ? c.neck_h : c.shoulder_h, c.h, kLidSide);
  if (c.bottle()) {
    cone();
  } else {
    disc(c.shoulder_h, lr2, c.r2, kShoulder);
  }
  side(c.r2, 0, c.shoulder_h, kSide);
  if (part < 0) return false;
  h->s = best;
  h->part = part;
  h->p = O + D * best;
  h->rho2 = rho2;
  return true;
}

bool World::IntersectCylinder(const Cylinder& c, V3 D, double s_max, Hit* h) const {
  if (c.lid_r > 0) return IntersectJar(c, D, s_max, h);
  const V3 O = cam_.pos;
  const double ox = O.x - c.x, oy = O.y - c.y;
  if (D.z < 0) {  // the top plane, seen from above
    const double st = (c.h - O.z) / D.z;
    if (st > 0 && st < s_max) {
      const double qx = ox + st * D.x, qy = oy + st * D.y;
      const double rr = qx * qx + qy * qy;
      if (rr <= c.r2) {
        if ((c.kind == CylKind::kCup || c.recess > 0) && rr < c.r_in2) {
          // Into the cup (or a can's recessed lid): the inner wall (far side) or the floor.
          const double A = D.x * D.x + D.y * D.y;
          double s_hit = kInf;
          int part = kFloor;
          if (A > 1e-18) {
            const double B = ox * D.x + oy * D.y, C = ox * ox + oy * oy - c.r_in2;
            const double disc = std::max(0.0, B * B - A * C);
            const double s2 = (-B + std::sqrt(disc)) / A;
            if (O.z + s2 * D.z >= c.z_floor) {
              s_hit = s2;
              part = kInner;
            }
          }
          if (part == kFloor) s_hit = (c.z_floor - O.z) / D.z;
          if (s_hit >= s_max) return false;
          h->s = s_hit;
          h->part = part;
          h->p = O + D * s_hit;
          h->rho2 = rr;
          return true;
        }
        h->s = st;
        h->part = kTop;
        h->p = O + D * st;
        h->rho2 = rr;
        return true;
      }
    }
  }
  const double A = D.x * D.x + D.y * D.y;
  if (A < 1e-18) return false;
  const double B = ox * D.x + oy * D.y, C = ox * ox + oy * oy - c.r2;
  const double disc = B * B - A * C;
  if (disc < 0) return false;
  const double s1 = (-B - std::sqrt(disc)) / A;
  if (s1 <= 0 || s1 >= s_max) return false;
  const double z = O.z + s1 * D.z;
  if (z < 0 || z > c.h) return false;
  h->s = s1;
  h->part = kSide;
  h->p = O + D * s1;
  return true;
}

bool World::IntersectBox(const Box& b, V3 O, V3 D, double s_max, Hit* h) const {
  const double rx = O.x - b.x, ry = O.y - b.y;
  const double o[3] = {rx * b.c + ry * b.s, -rx * b.s + ry * b.c, O.z};
  const double d[3] = {D.x * b.c + D.y * b.s, -D.x * b.s + D.y * b.c, D.z};
  const double lo[3] = {-b.hx, -b.hy, 0}, hi[3] = {b.hx, b.hy, b.hz};
  double t0 = 0, t1 = s_max;
  int face = -1;
  double sign = 0;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) < 1e-15) {
      if (o[k] < lo[k] || o[k] > hi[k]) return false;
      continue;
    }
    const double inv = 1.0 / d[k];
    double ta = (lo[k] - o[k]) * inv, tb = (hi[k] - o[k]) * inv;
    double sg = -1;  // entering through the low face: outward normal points to -k
    if (ta > tb) {
      std::swap(ta, tb);
      sg = 1;
    }
    if (ta > t0) {
      t0 = ta;
      face = k;
      sign = sg;
    }
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  if (face < 0 || t0 >= s_max) return false;  // starts inside, or beyond the current nearest hit
  if (h != nullptr) {
    h->s = t0;
    h->part = kBoxFace;
    h->p = O + D * t0;
    V3 n;
    if (face == 0) n = {sign * b.c, sign * b.s, 0};
    if (face == 1) n = {-sign * b.s, sign * b.c, 0};
    if (face == 2) n = {0, 0, sign};
    h->n = n;
  }
  return true;
}

void World::Trace(V3 D, int px, int py, Hit* h) const {
  const V3 O = cam_.pos;
  *h = Hit();
  if (D.z < 0) {
    const double s = -O.z / D.z;
    const V3 P = O + D * s;
    if (P.x < wall_x_) {
      h->s = s;
      h->part = kTable;
      h->p = P;
    }
  }
  if (h->part == kBackground && has_wall_ && D.x > 0) {
    const double s = (wall_x_ - O.x) / D.x;
    h->s = s;
    h->part = kWall;
    h->p = O + D * s;
  }
  for (int i = 0; i < static_cast<int>(cyl_.size()); ++i) {
    if (!cyl_[i].bbox.Contains(px, py)) continue;
    if (IntersectCylinder(cyl_[i], D, h->s, h)) h->obj = i;
  }
  for (int i = 0; i < static_cast<int>(box_.size()); ++i) {
    if (!box_[i].bbox.Contains(px, py)) continue;
    if (IntersectBox(box_[i], O, D, h->s, h)) h->obj = i;
  }
}

bool World::OccludedBefore(V3 D, double s_max, int px, int py, int skip_cyl) const {
  Hit h;
  for (int i = 0; i < static_cast<int>(cyl_.size()); ++i) {
    if (i == skip_cyl || !cyl_[i].bbox.Contains(px, py)) continue;
    if (IntersectCylinder(cyl_[i], D, s_max, &h)) return true;
  }
  for (const Box& b : box_) {
    if (b.bbox.Contains(px, py) && IntersectBox(b, cam_.pos, D, s_max, &h)) return true;
  }
  return false;
}

double World::Noise(double x, double y) const {
  const double fx = std::floor(x), fy = std::floor(y);
  const long long ix = static_cast<long long>(fx), iy = static_cast<long long>(fy);
  double tx = x - fx, ty = y - fy;
  tx = tx * tx * (3 - 2 * tx);
  ty = ty * ty * (3 - 2 * ty);
  const int x0 = static_cast<int>(ix & 255), x1 = static_cast<int>((ix + 1) & 255);
  const int y0 = static_cast<int>(iy & 255), y1 = static_cast<int>((iy + 1) & 255);
  const double a = lattice_[y0 * 256 + x0], b = lattice_[y0 * 256 + x1];
  const double c = lattice_[y1 * 256 + x0], d = lattice_[y1 * 256 + x1];
  return (a + (b - a) * tx) * (1 - ty) + (c + (d - c) * tx) * ty;
}

// Contrast kept for a feature of size `lambda` metres when a pixel covers `fp` metres (cheap mip-mapping).
inline double Keep(double fp, double lambda) {
  const double q = 3 * fp / lambda;
  return 1.0 / (1.0 + q * q);
}

double World::TableTexture(double X, double Y, double fp) const {
  double t = 0;
  switch (table_kind_) {
    case TableKind::kWood: {
      const double along = X * grain_c_ + Y * grain_s_, across = -X * grain_s_ + Y * grain_c_;
      const double w = across / grain_period_ + grain_warp_ * Noise(along * 1.5 + 17.3, across * 1.5 + 5.1);
      const double ring = w - std::floor(w);
      const double tri = std::abs(2 * ring - 1);
      const double profile = tri * tri * (3 - 2 * tri);
      const double streak = Noise(along * 4 + 91.7, across * 150 + 33.3);
      t = grain_contrast_ * (profile - 0.5) * Keep(fp, grain_period_) +
          0.15 * (streak - 0.5) * Keep(fp, 1.0 / 150) + 0.12 * (Noise(X * 3 + 50.5, Y * 3 + 7.7) - 0.5);
      break;
    }
    case TableKind::kMottled:
      t = noise_contrast_ * (0.6 * Noise(X * 8 + 3.3, Y * 8 + 9.9) +
                             0.4 * (Noise(X * 30 + 71.1, Y * 30 + 2.2) - 0.5) * Keep(fp, 1.0 / 30) - 0.3) +
          speck_ * (Noise(X * 300 + 11.1, Y * 300 + 61.6) - 0.5) * Keep(fp, 1.0 / 300);
      break;
    case TableKind::kPlain:
      t = noise_contrast_ * (Noise(X * 5 + 123.4, Y * 5 + 43.2) - 0.5) +
          speck_ * 0.5 * (Noise(X * 200 + 1.1, Y * 200 + 8.8) - 0.5) * Keep(fp, 1.0 / 200);
      break;
    case TableKind::kCloth: {  // a woven cloth: fine threads, soft plaid bands, folds
      const double along = X * grain_c_ + Y * grain_s_, across = -X * grain_s_ + Y * grain_c_;
      const double pitch = 0.05 * grain_period_ + 0.001;  // threads 1.4-2.5 mm apart
      const double weave = std::sin(2 * kPi * along / pitch) * std::sin(2 * kPi * across / pitch);
      const double band_period = 6 * grain_period_;
      const double band = Clamp(2.5 * std::sin(2 * kPi * along / band_period), -1.0, 1.0) +
                          Clamp(2.5 * std::sin(2 * kPi * across / band_period), -1.0, 1.0);
      t = noise_contrast_ * weave * Keep(fp, pitch) + 0.5 * grain_contrast_ * band * Keep(fp, band_period / 4) +
          0.15 * (Noise(X * 4 + 31.3, Y * 4 + 77.7) - 0.5);
      break;
    }
  }
  const double illum = 1 + illum_var_ * (Noise(X * 0.8 + 200.5, Y * 0.8 + 100.5) - 0.5);
  return table_base_ * (1 + t) * illum;
}

double World::WallTexture(double Y, double Z) const {
  return wall_albedo_ * (1 + 0.08 * (Noise(Y * 4 + 140.0, Z * 4 + 20.0) - 0.5));
}

// Direct light reaching table point P (0..1): soft cylinder shadows, hard box shadows, contact darkening.
double World::TableLit(V3 P) const {
  double lit = 1;
  const double lx = light_.x, ly = light_.y, lz = light_.z, ll = lx * lx + ly * ly;
  for (const Cylinder& c : cyl_) {
    if (!c.shadow.Contains(P.x, P.y)) continue;
    const double px = P.x - c.x, py = P.y - c.y;
    // Closest horizontal approach of the shadow ray to the axis while it is below the top.
    const double s_top = c.h / lz;
    const double s = ll > 1e-12 ? Clamp(-(px * lx + py * ly) / ll, 0.0, s_top) : 0.0;
    const double d = std::hypot(px + s * lx, py + s * ly);
    const double w = 0.002 + penumbra_ * s;
    lit *= Smoothstep(c.r - w, c.r + w, d);
    const double gap = std::hypot(px, py) - c.r;  // contact darkening near the base
    if (gap < 0.03) {
      const double g = 1 - Clamp(gap / 0.03, 0.0, 1.0);
      lit *= 1 - 0.45 * g * g;
    }
  }
  for (const Box& b : box_) {
    if (!b.shadow.Contains(P.x, P.y)) continue;
    if (IntersectBox(b, V3{P.x, P.y, 1e-9}, light_, kInf, nullptr)) lit *= 0.0;
    // contact darkening
    const double dx = P.x - b.x, dy = P.y - b.y;
    const double qx = std::abs(dx * b.c + dy * b.s) - b.hx, qy = std::abs(-dx * b.s + dy * b.c) - b.hy;
    const double gap = std::hypot(std::max(qx, 0.0), std::max(qy, 0.0));
    if (gap < 0.02) {
      const double g = 1 - gap / 0.02;
      lit *= 1 - 0.4 * g * g;
    }
  }
  return lit;
}

// Direct light on a point inside a cup: shadowed where the way to the light leaves through the wall.
double World::CupLit(const Cylinder& c, V3 P) const {
  const double px = P.x - c.x, py = P.y - c.y;
  const double lx = light_.x, ly = light_.y, ll = lx * lx + ly * ly;
  if (ll < 1e-12) return 1;
  const double pl = px * lx + py * ly;
  const double disc = std::max(0.0, pl * pl - ll * (px * px + py * py - c.r_in2));
  const double u = (-pl + std::sqrt(disc)) / ll;
  const double z_exit = P.z + u * light_.z;
  return Smoothstep(c.h - 0.004, c.h + 0.004, z_exit);
}

double World::Vignette(double u, double v) const {
  const double du = (u - cam_.pcx) / (cam_.pcx + 1), dv = (v - cam_.pcy) / (cam_.pcx + 1);
  return 1 - vignette_ * (du * du + dv * dv);
}

double World::Shade(const Hit& h, V3 D, V3 D_centre, TexCache* tc) const {
  double albedo = 0, lit = 0;  // lit: ambient + diffuse, spec added separately
  double spec = 0;
  const V3 P = h.p;
  // Phong highlight of a container's side (and a bottle's shoulder) with surface normal n.
  auto side_spec = [&](const Cylinder& c, V3 n) {
    const V3 Hh = Normalize(light_ + Normalize(cam_.pos - P));
    return c.spec * std::pow(std::max(0.0, Dot(n, Hh)), c.shininess);
  };
  switch (h.part) {
    case kBackground:
      return background_;
    case kTable: {
      if (!tc->table_ok) {
        // Texture at the pixel centre's table point (smooth: one evaluation per pixel).
        V3 Q = P;
        double s = h.s;
        V3 Dq = D;
        if (D_centre.z < 0) {
          const double sc = -cam_.pos.z / D_centre.z;
          const V3 Pc = cam_.pos + D_centre * sc;
          if (Pc.x < wall_x_) {
            Q = Pc;
            s = sc;
            Dq = D_centre;
          }
        }
        const double fp = s * Dot(Dq, Dq) / (cam_.f * std::abs(Dq.z));
        tc->table = TableTexture(Q.x, Q.y, fp);
        tc->table_ok = true;
      }
      albedo = tc->table;
      for (const Shape& sh : shape_) {  // printed shapes (later ones on top), sharp: per sample
        if (sh.area.Contains(P.x, P.y) && sh.Inside(P.x, P.y)) albedo = sh.albedo;
      }
      const double l = TableLit(P);
      lit = ambient_ * (0.75 + 0.25 * l) + diffuse_ * light_.z * l;
      break;
    }
    case kWall: {
      if (!tc->wall_ok) {
        tc->wall = WallTexture(P.y, P.z);
        tc->wall_ok = true;
      }
      albedo = tc->wall;
      lit = ambient_ + diffuse_ * std::max(0.0, -light_.x) * 0.9;
      break;
    }
    case kSide: {
      const Cylinder& c = cyl_[h.obj];
      const V3 n{(P.x - c.x) / c.r, (P.y - c.y) / c.r, 0};
      albedo = c.side_albedo;
      if (c.has_label && P.z >= c.label_z0 && P.z <= c.label_z1) {
        albedo = c.label_albedo;
        if (c.has_print && Dot(n, c.print_dir) > c.print_cos && P.z < 0.5 * (c.label_z0 + c.label_z1))
          albedo = c.print_albedo;
      }
      if (c.has_neck && P.z > c.h - c.neck_width) albedo = c.neck_albedo;
      if (c.material != PlainMaterial::kNone) albedo *= PlainTexture(c, P, false);
      const double ao = 1 - 0.35 * std::max(0.0, 1 - P.z / 0.012);
      lit = ambient_ * ao + diffuse_ * std::max(0.0, Dot(n, light_));
      if (c.spec > 0) spec = side_spec(c, n);
      break;
    }
    case kTop: {
      const Cylinder& c = cyl_[h.obj];
      albedo = c.top_albedo;
      if (c.has_rim) {
        const double rho = std::sqrt(h.rho2);
        if (rho > c.rim_r() - c.rim_width)
          albedo = c.rim_albedo;
        else if (c.kind == CylKind::kCan && c.recess == 0 && rho > c.r - c.rim_width - 0.002)
          albedo = c.top_albedo * 0.8;  // the lid's countersink groove
      }
      if (c.material != PlainMaterial::kNone) albedo *= PlainTexture(c, P, true);
      albedo = std::min(albedo * c.top_scale, 1.0);
      lit = ambient_ + diffuse_ * light_.z;
      if (c.recess > 0) {  // the rolled rim: a bead whose normal turns from inward to outward
        const double rho = std::sqrt(h.rho2);
        const double t = Clamp((rho - c.r_in) / std::max(1e-6, c.r - c.r_in), 0.0, 1.0);
        const double ang = (t - 0.5) * 0.8 * kPi, sa = std::sin(ang);
        const V3 n{(P.x - c.x) / std::max(rho, 1e-9) * sa, (P.y - c.y) / std::max(rho, 1e-9) * sa, std::cos(ang)};
        lit = ambient_ + diffuse_ * std::max(0.0, Dot(n, light_));
      }
      if (c.spec > 0) {
        const V3 Hh = Normalize(light_ + Normalize(cam_.pos - P));
        spec = 0.5 * c.spec * std::pow(std::max(0.0, Hh.z), 4 * c.shininess);
      }
      break;
    }
    case kInner: {
      const Cylinder& c = cyl_[h.obj];
      const V3 n{-(P.x - c.x) / c.r_in, -(P.y - c.y) / c.r_in, 0};
      albedo = std::min(c.inner_albedo * c.top_scale, 1.0);
      const double depth = Clamp((P.z - c.z_floor) / std::max(1e-6, c.h - c.z_floor), 0.0, 1.0);
      const double ao = c.recess > 0 ? 0.8 + 0.2 * depth : 0.4 + 0.6 * depth;  // a shallow lid sees the sky
      lit = ambient_ * ao + diffuse_ * std::max(0.0, Dot(n, light_)) * CupLit(c, P);
      break;
    }
    case kFloor: {
      const Cylinder& c = cyl_[h.obj];
      albedo = std::min((c.floor_albedo >= 0 ? c.floor_albedo : c.inner_albedo) * c.top_scale, 1.0);
      lit = ambient_ * (c.recess > 0 ? 0.8 : 0.4) + diffuse_ * light_.z * CupLit(c, P);
      if (c.recess > 0 && c.spec > 0) {  // the lid's metal floor
        const V3 Hh = Normalize(light_ + Normalize(cam_.pos - P));
        spec = 0.5 * c.spec * std::pow(std::max(0.0, Hh.z), 4 * c.shininess) * CupLit(c, P);
      }
      break;
    }
    case kLidSide: {
      const Cylinder& c = cyl_[h.obj];
      const V3 n{(P.x - c.x) / c.lid_r, (P.y - c.y) / c.lid_r, 0};
      const bool neck = c.bottle() && P.z < c.h - c.cap_h;  // a bottle's neck, below its cap
      albedo = neck ? c.side_albedo : std::min(c.top_albedo * c.top_scale, 1.0);
      lit = ambient_ + diffuse_ * std::max(0.0, Dot(n, light_));
      break;
    }
    case kShoulder: {
      const Cylinder& c = cyl_[h.obj];
      if (c.bottle()) {
        // A bottle's rounded shoulder: the shading normal rises from the side's (horizontal) to
        // kShoulderTilt above it and back to the neck's, so neither end shows a crease.
        constexpr double kShoulderTilt = 1.2;  // rad
        const double t = Clamp((P.z - c.shoulder_h) / (c.neck_h - c.shoulder_h), 0.0, 1.0);
        const double dx = P.x - c.x, dy = P.y - c.y, rho = std::max(1e-9, std::hypot(dx, dy));
        const double up = kShoulderTilt * std::sin(kPi * t);
        const V3 n{dx / rho * std::cos(up), dy / rho * std::cos(up), std::sin(up)};
        albedo = c.side_albedo;
        lit = ambient_ + diffuse_ * std::max(0.0, Dot(n, light_));
        if (c.spec > 0) spec = side_spec(c, n);
        break;
      }
      albedo = 0.85 * c.side_albedo;
      lit = ambient_ + diffuse_ * light_.z;
      break;
    }
    case kBoxFace: {
      const Box& b = box_[h.obj];
      albedo = b.albedo;
      if (b.has_print && h.n.z > 0.5) {
        const double dx = P.x - b.x, dy = P.y - b.y;
        if (std::abs(dx * b.c + dy * b.s) < b.print_hx && std::abs(-dx * b.s + dy * b.c) < b.print_hy)
          albedo = b.print_albedo;
      }
      const double ao = 1 - 0.3 * std::max(0.0, 1 - P.z / 0.01);
      lit = ambient_ * ao + diffuse_ * std::max(0.0, Dot(h.n, light_));
      break;
    }
  }
  return 255.0 * gain_ * (albedo * lit + spec);
}

double World::ShadeAt(double u, double v) const {
  const V3 D = cam_.Ray(u, v);
  Hit h;
  Trace(D, static_cast<int>(std::lround(u)), static_cast<int>(std::lround(v)), &h);
  TexCache tc;
  return Shade(h, D, D, &tc) * Vignette(u, v);
}

// One pixel: the mean of 2x2 sub-samples at (x +- 0.25, y +- 0.25), times the vignette.
float World::RenderPixel(int x, int y) const {
  static constexpr double kSub[4][2] = {{-0.25, -0.25}, {0.25, -0.25}, {-0.25, 0.25}, {0.25, 0.25}};
  const V3 Dc = cam_.Ray(x, y);
  TexCache tc;
  double sum = 0;
  for (const auto& sub : kSub) {
    const V3 D = cam_.Ray(x + sub[0], y + sub[1]);
    Hit h;
    Trace(D, x, y, &h);
    sum += Shade(h, D, Dc, &tc);
  }
  return static_cast<float>(0.25 * sum * Vignette(x, y));
}

void World::Render(std::vector<float>* img) const {
  img->assign(static_cast<size_t>(W_) * H_, 0.f);
  RenderRect(IRect{0, 0, W_ - 1, H_ - 1}, img);
}

void World::RenderRect(const IRect& r, std::vector<float>* img) const {
  const int x0 = std::max(r.x0, 0), y0 = std::max(r.y0, 0);
  const int x1 = std::min(r.x1, W_ - 1), y1 = std::min(r.y1, H_ - 1);
  for (int y = y0; y <= y1; ++y) {
    float* row = img->data() + static_cast<size_t>(y) * W_;
    for (int x = x0; x <= x1; ++x) row[x] = RenderPixel(x, y);
  }
}

// Camera-axis depth of the first hit of each pixel's centre ray: D . forward = 1, so the ray
// parameter s is that depth. 0 where the ray sees no surface.
void World::RenderDepth(const IRect& r, std::vector<double>* z) const {
  const int x0 = std::max(r.x0, 0), y0 = std::max(r.y0, 0);
  const int x1 = std::min(r.x1, W_ - 1), y1 = std::min(r.y1, H_ - 1);
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      Hit h;
      Trace(cam_.Ray(x, y), x, y, &h);
      (*z)[static_cast<size_t>(y) * W_ + x] = (h.part == kBackground || !std::isfinite(h.s)) ? 0.0 : h.s;
    }
  }
}

// Separable Gaussian blur (reflect-101 border), then additive Gaussian noise, round and clamp.
void World::Finish(const std::vector<float>& img, cv::Mat* gray) {
  std::vector<float> a = img;
  if (opt_.blur_sigma > 0) {
    const int rad = std::max(1, static_cast<int>(std::ceil(3 * opt_.blur_sigma)));
    std::vector<double> k(2 * rad + 1);
    double ksum = 0;
    for (int i = -rad; i <= rad; ++i) ksum += k[i + rad] = std::exp(-0.5 * i * i / (opt_.blur_sigma * opt_.blur_sigma));
    for (double& v : k) v /= ksum;
    auto reflect = [](int i, int n) {
      if (n == 1) return 0;
      while (i < 0 || i >= n) i = i < 0 ? -i : 2 * n - 2 - i;
      return i;
    };
    std::vector<float> b(a.size());
    for (int y = 0; y < H_; ++y) {
      const float* src = a.data() + static_cast<size_t>(y) * W_;
      float* dst = b.data() + static_cast<size_t>(y) * W_;
      for (int x = 0; x < W_; ++x) {
        double s = 0;
        if (x >= rad && x < W_ - rad) {
          for (int i = -rad; i <= rad; ++i) s += k[i + rad] * src[x + i];
        } else {
          for (int i = -rad; i <= rad; ++i) s += k[i + rad] * src[reflect(x + i, W_)];
        }
        dst[x] = static_cast<float>(s);
      }
    }
    std::vector<double> acc(W_);
    for (int y = 0; y < H_; ++y) {
      std::fill(acc.begin(), acc.end(), 0.0);
      for (int i = -rad; i <= rad; ++i) {
        const float* src = b.data() + static_cast<size_t>(reflect(y + i, H_)) * W_;
        const double w = k[i + rad];
        for (int x = 0; x < W_; ++x) acc[x] += w * src[x];
      }
      float* dst = a.data() + static_cast<size_t>(y) * W_;
      for (int x = 0; x < W_; ++x) dst[x] = static_cast<float>(acc[x]);
    }
  }
  gray->create(H_, W_, CV_8UC1);
  for (int y = 0; y < H_; ++y) {
    const float* src = a.data() + static_cast<size_t>(y) * W_;
    std::uint8_t* dst = gray->ptr<std::uint8_t>(y);
    for (int x = 0; x < W_; ++x) {
      double v = src[x];
      if (opt_.noise_sigma > 0) v += opt_.noise_sigma * rng_.Normal();
      dst[x] = static_cast<std::uint8_t>(Clamp(std::floor(v + 0.5), 0.0, 255.0));
    }
  }
}

Scene World::Build() {
  SetupCamera();
  SetupLightAndSurfaces();
  PlaceClutter();
  PlaceCylinders();
  FixContrast();
  std::vector<float> img;
  Render(&img);
  Scene scene;
  Finish(img, &scene.gray);
  for (const Cylinder& c : cyl_) scene.truth.push_back(c.truth);
  return scene;
}

}  // namespace ellipsekit::scenes::detail

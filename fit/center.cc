#include "fit/center.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace ellipsekit {

namespace {

// Two centre lines are used together only when they cross at more than ~6 degrees.
constexpr double kMinSinBetweenLines = 0.1;

struct EndPoint {
  Eigen::Vector2d p, n;
  int arc;
};

Eigen::Vector3d TangentLine(const Eigen::Vector2d& p, const Eigen::Vector2d& n) {
  return {n.x(), n.y(), -n.dot(p)};
}

}  // namespace

bool ChordCenterLine(const Eigen::Vector2d& p, const Eigen::Vector2d& np, const Eigen::Vector2d& q,
                     const Eigen::Vector2d& nq, Eigen::Vector3d* line) {
  const Eigen::Vector3d pole = TangentLine(p, np).cross(TangentLine(q, nq));
  const Eigen::Vector2d m = 0.5 * (p + q);
  const Eigen::Vector3d l = Eigen::Vector3d(m.x(), m.y(), 1.0).cross(pole);
  // Not normalised: IntersectLines is scale-invariant.
  if (!(l.head<2>().squaredNorm() > 1e-24)) return false;
  *line = l;
  return true;
}

bool IntersectLines(const Eigen::Vector3d& l1, const Eigen::Vector3d& l2, Eigen::Vector2d* point) {
  const Eigen::Vector3d x = l1.cross(l2);
  // sin(angle between the lines) = |x.z| / (|n1| |n2|), compared squared: no root, no division.
  const double n1 = l1.head<2>().squaredNorm(), n2 = l2.head<2>().squaredNorm();
  if (x.z() * x.z() < kMinSinBetweenLines * kMinSinBetweenLines * n1 * n2) return false;
  if (!(std::abs(x.z()) > 1e-12)) return false;
  *point = x.head<2>() / x.z();
  return std::isfinite(point->x()) && std::isfinite(point->y());
}

bool PairCenter(const Arc& a, const Arc& b, CenterMethod method, Eigen::Vector2d* center) {
  if (method == CenterMethod::kArcChords) {
    Eigen::Vector3d la, lb;
    return ChordCenterLine(a.p0, a.n0, a.p1, a.n1, &la) && ChordCenterLine(b.p0, b.n0, b.p1, b.n1, &lb) &&
           IntersectLines(la, lb, center);
  }
  const std::array<EndPoint, 4> e = {{{a.p0, a.n0, 0}, {a.p1, a.n1, 0}, {b.p0, b.n0, 1}, {b.p1, b.n1, 1}}};
  // The six chords, longest first (a stable sort: ties keep the order below), each centre line
  // computed only when the search reaches it; a chord whose line does not exist is skipped. The
  // endpoints are integer pixels, so squared lengths order the chords exactly as lengths do.
  struct Chord {
    double length2;
    int i, j;
    int state;  // 0: line not computed, 1: computed, -1: no line
    Eigen::Vector3d line;
  };
  std::array<Chord, 6> chords;
  int n = 0;
  for (int i = 0; i < 4; ++i) {
    for (int j = i + 1; j < 4; ++j) chords[n++] = {(e[i].p - e[j].p).squaredNorm(), i, j, 0, Eigen::Vector3d::Zero()};
  }
  for (int i = 1; i < n; ++i) {
    for (int j = i; j > 0 && chords[j - 1].length2 < chords[j].length2; --j) std::swap(chords[j - 1], chords[j]);
  }
  auto has_line = [&](Chord& c) {
    if (c.state == 0) c.state = ChordCenterLine(e[c.i].p, e[c.i].n, e[c.j].p, e[c.j].n, &c.line) ? 1 : -1;
    return c.state > 0;
  };
  for (int i = 0; i < n; ++i) {
    if (!has_line(chords[i])) continue;
    for (int j = i + 1; j < n; ++j) {
      if (has_line(chords[j]) && IntersectLines(chords[i].line, chords[j].line, center)) return true;
    }
  }
  return false;
}

Eigen::Vector2d TripletCenter(const Arc& a, const Arc& b, const Arc& c, const Eigen::Vector2d& c_ab,
                              const Eigen::Vector2d& c_bc, const Options& options,
                              bool* iterations_capped) {
  const Eigen::Vector2d start = 0.5 * (c_ab + c_bc);
  *iterations_capped = false;
  if (options.center_method == CenterMethod::kArcChords) return start;

  const std::array<EndPoint, 6> e = {{{a.p0, a.n0, 0}, {a.p1, a.n1, 0}, {b.p0, b.n0, 1},
                                      {b.p1, b.n1, 1}, {c.p0, c.n0, 2}, {c.p1, c.n1, 2}}};
  std::array<Eigen::Vector3d, 12> lines;
  int nl = 0;
  for (int i = 0; i < 6; ++i) {
    for (int j = i + 1; j < 6; ++j) {
      if (e[i].arc == e[j].arc) continue;
      Eigen::Vector3d l;
      if (ChordCenterLine(e[i].p, e[i].n, e[j].p, e[j].n, &l)) lines[nl++] = l;
    }
  }
  std::array<Eigen::Vector2d, 66> points;
  int np = 0;
  for (int i = 0; i < nl; ++i) {
    for (int j = i + 1; j < nl; ++j) {
      Eigen::Vector2d x;
      if (IntersectLines(lines[i], lines[j], &x)) points[np++] = x;
    }
  }
  // Flat-kernel mean shift: move to the mean of the intersections within the bandwidth.
  const double h2 = options.mean_shift_bandwidth * options.mean_shift_bandwidth;
  Eigen::Vector2d x = start;
  for (int it = 0; it < options.max_mean_shift_iterations; ++it) {
    Eigen::Vector2d sum(0, 0);
    int count = 0;
    for (int i = 0; i < np; ++i) {
      if ((points[i] - x).squaredNorm() <= h2) { sum += points[i]; ++count; }
    }
    if (count == 0) return x;
    const Eigen::Vector2d next = sum / count;
    const double shift = (next - x).squaredNorm();
    x = next;
    if (shift < 1e-6) return x;
  }
  *iterations_capped = true;
  return x;
}

}  // namespace ellipsekit

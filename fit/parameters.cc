#include "fit/parameters.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ellipsekit {

namespace {

constexpr int kSamplesPerArc = 16;      // points per arc voting for rho and N
constexpr int kAxisSamplesPerArc = 48;  // points per arc voting for A
constexpr double kPi = std::numbers::pi;

void SampleArc(const Curves& c, const Arc& arc, int arc_index, int samples,
               const Eigen::Vector2d& center, ParameterScratch* s) {
  const int n = arc.points();
  const int k = std::min(samples, n);
  for (int i = 0; i < k; ++i) {
    const int idx = arc.begin + (k == 1 ? 0 : static_cast<int>((static_cast<long long>(i) * (n - 1)) / (k - 1)));
    const double gx = c.gx[idx], gy = c.gy[idx];
    const double gn = std::hypot(gx, gy);
    if (gn == 0) continue;
    s->px.push_back(c.x[idx] - center.x());
    s->py.push_back(c.y[idx] - center.y());
    s->tx.push_back(-gy / gn);
    s->ty.push_back(gx / gn);
    s->arc_of.push_back(arc_index);
  }
}

}  // namespace

void ParameterScratch::Reserve() {
  constexpr std::size_t kPoints = 3 * kAxisSamplesPerArc;
  for (auto* v : {&px, &py, &tx, &ty, &a}) v->reserve(kPoints);
  arc_of.reserve(kPoints);
  constexpr std::size_t kVotes = (3 * kSamplesPerArc) * (3 * kSamplesPerArc - 1) / 2;
  rho.reserve(kVotes);
  n.reserve(kVotes);
}

double DensestWindowMean(std::vector<double>* values, double width, double period) {
  std::vector<double>& v = *values;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  if (n == 0) return 0;
  std::size_t best_lo = 0, best_count = 0;
  std::size_t hi = 0;
  // On a circle, the window may wrap: index i + n stands for v[i] + period.
  const std::size_t limit = period > 0 ? 2 * n : n;
  auto at = [&](std::size_t i) { return i < n ? v[i] : v[i - n] + period; };
  for (std::size_t lo = 0; lo < n; ++lo) {
    if (hi < lo) hi = lo;
    while (hi + 1 < limit && hi + 1 < lo + n && at(hi + 1) - at(lo) <= width) ++hi;
    if (hi - lo + 1 > best_count) { best_count = hi - lo + 1; best_lo = lo; }
  }
  double sum = 0;
  for (std::size_t i = best_lo; i < best_lo + best_count; ++i) sum += at(i);
  double mean = sum / static_cast<double>(best_count);
  if (period > 0) mean = std::fmod(mean, period);
  return mean;
}

void NormalizeEllipse(Ellipse* e) {
  if (e->b > e->a) {
    std::swap(e->a, e->b);
    e->theta += kPi / 2;
  }
  e->theta = std::fmod(e->theta + kPi / 2, kPi);
  if (e->theta < 0) e->theta += kPi;
  e->theta -= kPi / 2;
}

bool EstimateParameters(const Curves& curves, const Arc* const* arcs, int count,
                        const Eigen::Vector2d& center, ParameterScratch* s, Ellipse* out) {
  s->px.clear(); s->py.clear(); s->tx.clear(); s->ty.clear(); s->arc_of.clear();
  s->rho.clear(); s->n.clear(); s->a.clear();
  for (int i = 0; i < count; ++i) SampleArc(curves, *arcs[i], i, kSamplesPerArc, center, s);
  const std::size_t m = s->px.size();
  for (std::size_t i = 0; i < m; ++i) {
    // Row of the linear condition t^T M r = 0 in (M00, M01, M11).
    const Eigen::Vector3d ri(s->tx[i] * s->px[i], s->tx[i] * s->py[i] + s->ty[i] * s->px[i], s->ty[i] * s->py[i]);
    for (std::size_t j = i + 1; j < m; ++j) {
      if (s->arc_of[j] == s->arc_of[i]) continue;
      const Eigen::Vector3d rj(s->tx[j] * s->px[j], s->tx[j] * s->py[j] + s->ty[j] * s->px[j], s->ty[j] * s->py[j]);
      Eigen::Vector3d q = ri.cross(rj);  // (M00, M01, M11) up to scale
      if (q.x() + q.z() < 0) q = -q;
      const double p00 = q.x(), p01 = q.y(), p11 = q.z();
      const double half_tr = 0.5 * (p00 + p11);
      const double disc = std::hypot(0.5 * (p00 - p11), p01);
      const double lmin = half_tr - disc, lmax = half_tr + disc;
      if (!(lmin > 1e-9 * lmax) || !(lmax > 0)) continue;  // not an ellipse
      double rho = 0.5 * std::atan2(2 * p01, p00 - p11) + kPi / 2;  // major axis: smaller eigenvalue
      rho = std::fmod(rho, kPi);
      if (rho < 0) rho += kPi;
      s->rho.push_back(rho);
      s->n.push_back(std::sqrt(lmin / lmax));
    }
  }
  if (s->rho.empty()) return false;
  const double rho = DensestWindowMean(&s->rho, 2.0 * kPi / 180.0, kPi);
  const double n = DensestWindowMean(&s->n, 0.02, 0.0);
  if (!(n > 0.01)) return false;

  // A from every sampled point (eqs. 10-12).
  s->px.clear(); s->py.clear(); s->tx.clear(); s->ty.clear(); s->arc_of.clear();
  for (int i = 0; i < count; ++i) SampleArc(curves, *arcs[i], i, kAxisSamplesPerArc, center, s);
  const double c = std::cos(rho), sn = std::sin(rho);
  for (std::size_t i = 0; i < s->px.size(); ++i) {
    const double xo = s->px[i] * c + s->py[i] * sn;
    const double yo = -s->px[i] * sn + s->py[i] * c;
    s->a.push_back(std::sqrt(xo * xo + yo * yo / (n * n)));
  }
  if (s->a.empty()) return false;
  std::vector<double>& a = s->a;
  std::nth_element(a.begin(), a.begin() + a.size() / 2, a.end());
  const double a_median = a[a.size() / 2];
  const double axis = DensestWindowMean(&a, std::max(1.0, 0.02 * a_median), 0.0);
  if (!(axis > 0) || !std::isfinite(axis)) return false;
  out->cx = center.x();
  out->cy = center.y();
  out->a = axis;
  out->b = n * axis;
  out->theta = rho;
  NormalizeEllipse(out);
  return true;
}

}  // namespace ellipsekit

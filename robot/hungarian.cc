// Minimum-cost assignment: the Hungarian algorithm with row/column potentials (Kuhn–Munkres,
// shortest augmenting paths), O(n^2 m) for n <= m. Written from the textbook formulation.
#include "ellipsekit/robot/hungarian.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ellipsekit::robot {

void AssignmentSolver::Reserve(int rows, int cols) {
  const std::size_t r = static_cast<std::size_t>(std::max(rows, 0)), c = static_cast<std::size_t>(std::max(cols, 0));
  const std::size_t big = std::max(r, c) + 1;
  a_.reserve(r * c);
  for (auto* v : {&u_, &v_, &minv_}) v->reserve(big);
  for (auto* v : {&p_, &way_, &result_}) v->reserve(big);
  used_.reserve(big);
}

// n <= m rows of a_ (transposed: a_'s columns are the rows); 1-based internally. Leaves, for each
// of the n rows, its column in p_ (p_[j]: row matched to column j, 0 = none).
void AssignmentSolver::SolveRowsLeCols(int n, int m, bool transposed) {
  const double inf = std::numeric_limits<double>::infinity();
  const std::size_t ld = static_cast<std::size_t>(a_rows_);
  auto at = [&](int i, int j) {  // the (i, j) entry of the n x m problem, 0-based
    return transposed ? a_[static_cast<std::size_t>(j) + static_cast<std::size_t>(i) * ld]
                      : a_[static_cast<std::size_t>(i) + static_cast<std::size_t>(j) * ld];
  };
  u_.assign(static_cast<std::size_t>(n) + 1, 0);
  v_.assign(static_cast<std::size_t>(m) + 1, 0);
  p_.assign(static_cast<std::size_t>(m) + 1, 0);
  way_.assign(static_cast<std::size_t>(m) + 1, 0);
  for (int i = 1; i <= n; ++i) {
    p_[0] = i;
    int j0 = 0;
    minv_.assign(static_cast<std::size_t>(m) + 1, inf);
    used_.assign(static_cast<std::size_t>(m) + 1, 0);
    do {
      used_[static_cast<std::size_t>(j0)] = 1;
      const int i0 = p_[static_cast<std::size_t>(j0)];
      double delta = inf;
      int j1 = 0;
      for (int j = 1; j <= m; ++j) {
        if (used_[static_cast<std::size_t>(j)]) continue;
        const double cur = at(i0 - 1, j - 1) - u_[static_cast<std::size_t>(i0)] - v_[static_cast<std::size_t>(j)];
        if (cur < minv_[static_cast<std::size_t>(j)]) {
          minv_[static_cast<std::size_t>(j)] = cur;
          way_[static_cast<std::size_t>(j)] = j0;
        }
        if (minv_[static_cast<std::size_t>(j)] < delta) {
          delta = minv_[static_cast<std::size_t>(j)];
          j1 = j;
        }
      }
      for (int j = 0; j <= m; ++j) {
        const std::size_t js = static_cast<std::size_t>(j);
        if (used_[js]) {
          u_[static_cast<std::size_t>(p_[js])] += delta;
          v_[js] -= delta;
        } else {
          minv_[js] -= delta;
        }
      }
      j0 = j1;
    } while (p_[static_cast<std::size_t>(j0)] != 0);
    do {  // augment along the path
      const int j1 = way_[static_cast<std::size_t>(j0)];
      p_[static_cast<std::size_t>(j0)] = p_[static_cast<std::size_t>(j1)];
      j0 = j1;
    } while (j0 != 0);
  }
}

const std::vector<int>& AssignmentSolver::Solve(const double* cost, int rows, int cols, double forbidden) {
  result_.assign(static_cast<std::size_t>(std::max(rows, 0)), -1);
  if (rows <= 0 || cols <= 0) return result_;
  const std::size_t ld = static_cast<std::size_t>(rows);
  auto c = [&](int i, int j) { return cost[static_cast<std::size_t>(i) + static_cast<std::size_t>(j) * ld]; };
  // Forbidden (or non-finite) entries get a penalty larger than any sum of allowed costs, so the
  // optimum uses as few of them as possible; they are dropped afterwards.
  double max_allowed = 0;
  for (int j = 0; j < cols; ++j)
    for (int i = 0; i < rows; ++i)
      if (std::isfinite(c(i, j)) && c(i, j) < forbidden) max_allowed = std::max(max_allowed, std::abs(c(i, j)));
  const double penalty = (max_allowed + 1) * (std::min(rows, cols) + 1) * 2;
  a_.resize(ld * static_cast<std::size_t>(cols));
  a_rows_ = rows;
  for (int j = 0; j < cols; ++j)
    for (int i = 0; i < rows; ++i)
      a_[static_cast<std::size_t>(i) + static_cast<std::size_t>(j) * ld] =
          (std::isfinite(c(i, j)) && c(i, j) < forbidden) ? c(i, j) : penalty;
  if (rows <= cols) {
    SolveRowsLeCols(rows, cols, false);
    for (int j = 1; j <= cols; ++j)
      if (p_[static_cast<std::size_t>(j)] != 0) result_[static_cast<std::size_t>(p_[static_cast<std::size_t>(j)] - 1)] = j - 1;
  } else {
    SolveRowsLeCols(cols, rows, true);  // columns as rows: p_[i + 1] is the column matched to row i
    for (int i = 1; i <= rows; ++i)
      if (p_[static_cast<std::size_t>(i)] != 0) result_[static_cast<std::size_t>(i - 1)] = p_[static_cast<std::size_t>(i)] - 1;
  }
  for (int i = 0; i < rows; ++i) {
    const int j = result_[static_cast<std::size_t>(i)];
    if (j >= 0 && a_[static_cast<std::size_t>(i) + static_cast<std::size_t>(j) * ld] == penalty)
      result_[static_cast<std::size_t>(i)] = -1;
  }
  return result_;
}

std::vector<int> SolveAssignment(const Eigen::MatrixXd& cost, double forbidden) {
  AssignmentSolver solver;
  const Eigen::MatrixXd c = cost;  // column-major, contiguous
  return solver.Solve(c.data(), static_cast<int>(c.rows()), static_cast<int>(c.cols()), forbidden);
}

}  // namespace ellipsekit::robot

// Minimum-cost assignment: the Hungarian algorithm with row/column potentials (Kuhn–Munkres,
// shortest augmenting paths), O(n^2 m) for n <= m. Written from the textbook formulation.
#include "ellipsekit/robot/hungarian.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ellipsekit::robot {

namespace {

// n <= m; a is 1-based internally. Returns row -> column for all n rows.
std::vector<int> SolveRowsLeCols(const Eigen::MatrixXd& a) {
  const int n = static_cast<int>(a.rows()), m = static_cast<int>(a.cols());
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> u(n + 1, 0), v(m + 1, 0);
  std::vector<int> p(m + 1, 0), way(m + 1, 0);  // p[j]: row matched to column j (0 = none)
  for (int i = 1; i <= n; ++i) {
    p[0] = i;
    int j0 = 0;
    std::vector<double> minv(m + 1, inf);
    std::vector<char> used(m + 1, 0);
    do {
      used[j0] = 1;
      const int i0 = p[j0];
      double delta = inf;
      int j1 = 0;
      for (int j = 1; j <= m; ++j) {
        if (used[j]) continue;
        const double cur = a(i0 - 1, j - 1) - u[i0] - v[j];
        if (cur < minv[j]) {
          minv[j] = cur;
          way[j] = j0;
        }
        if (minv[j] < delta) {
          delta = minv[j];
          j1 = j;
        }
      }
      for (int j = 0; j <= m; ++j) {
        if (used[j]) {
          u[p[j]] += delta;
          v[j] -= delta;
        } else {
          minv[j] -= delta;
        }
      }
      j0 = j1;
    } while (p[j0] != 0);
    do {  // augment along the path
      const int j1 = way[j0];
      p[j0] = p[j1];
      j0 = j1;
    } while (j0 != 0);
  }
  std::vector<int> row_to_col(n, -1);
  for (int j = 1; j <= m; ++j)
    if (p[j] != 0) row_to_col[p[j] - 1] = j - 1;
  return row_to_col;
}

}  // namespace

std::vector<int> SolveAssignment(const Eigen::MatrixXd& cost, double forbidden) {
  const int rows = static_cast<int>(cost.rows()), cols = static_cast<int>(cost.cols());
  std::vector<int> result(rows, -1);
  if (rows == 0 || cols == 0) return result;
  // Forbidden (or non-finite) entries get a penalty larger than any sum of allowed costs, so the
  // optimum uses as few of them as possible; they are dropped afterwards.
  double max_allowed = 0;
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j)
      if (std::isfinite(cost(i, j)) && cost(i, j) < forbidden) max_allowed = std::max(max_allowed, std::abs(cost(i, j)));
  const double penalty = (max_allowed + 1) * (std::min(rows, cols) + 1) * 2;
  Eigen::MatrixXd a(rows, cols);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j)
      a(i, j) = (std::isfinite(cost(i, j)) && cost(i, j) < forbidden) ? cost(i, j) : penalty;
  if (rows <= cols) {
    result = SolveRowsLeCols(a);
  } else {
    const std::vector<int> col_to_row = SolveRowsLeCols(a.transpose());
    for (int j = 0; j < cols; ++j)
      if (col_to_row[j] >= 0) result[col_to_row[j]] = j;
  }
  for (int i = 0; i < rows; ++i)
    if (result[i] >= 0 && a(i, result[i]) == penalty) result[i] = -1;
  return result;
}

}  // namespace ellipsekit::robot

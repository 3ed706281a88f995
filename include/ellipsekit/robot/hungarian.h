// Optimal assignment (Hungarian / Kuhn–Munkres with potentials, O(n^2 m)).
#pragma once

#include <vector>

#include <Eigen/Core>

namespace ellipsekit::robot {

// Minimum-cost assignment of rows to columns of a rows x cols cost matrix (any shape; finite costs).
// Returns, for each row, the assigned column or -1 (when rows > cols some rows stay unassigned).
// Entries >= `forbidden` are never assigned (the row or column stays unassigned instead).
std::vector<int> SolveAssignment(const Eigen::MatrixXd& cost, double forbidden = 1e18);

// The same with buffers kept between calls: after a call of a given size, calls up to that size
// do not allocate (the tracker runs one per frame).
class AssignmentSolver {
 public:
  // `cost` is rows x cols, column-major (cost(i, j) = cost[i + j * rows]). Returns row -> column
  // or -1, valid until the next call.
  const std::vector<int>& Solve(const double* cost, int rows, int cols, double forbidden = 1e18);
  void Reserve(int rows, int cols);

 private:
  void SolveRowsLeCols(int n, int m, bool transposed);
  std::vector<double> a_, u_, v_, minv_;
  std::vector<int> p_, way_, result_;
  std::vector<char> used_;
  int a_rows_ = 0;  // leading dimension of a_ (the cost's rows)
};

}  // namespace ellipsekit::robot

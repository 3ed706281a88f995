// Optimal assignment (Hungarian / Kuhn–Munkres with potentials, O(n^2 m)).
#pragma once

#include <vector>

#include <Eigen/Core>

namespace ellipsekit::robot {

// Minimum-cost assignment of rows to columns of a rows x cols cost matrix (any shape; finite costs).
// Returns, for each row, the assigned column or -1 (when rows > cols some rows stay unassigned).
// Entries >= `forbidden` are never assigned (the row or column stays unassigned instead).
std::vector<int> SolveAssignment(const Eigen::MatrixXd& cost, double forbidden = 1e18);

}  // namespace ellipsekit::robot

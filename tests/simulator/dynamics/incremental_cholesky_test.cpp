// The incremental factor against a fresh factorisation, through joins and leaves in
// the order an active-set solve makes them, with rows that depend on each other.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <random>
#include <stdexcept>

#include "simulator/dynamics/incremental_cholesky.hpp"

namespace arphys::dynamics {
namespace {

// J M^-1 J^T of random contact-like rows on a few bodies: positive semidefinite, and
// singular (more rows than the bodies' 6 degrees of freedom each).
Eigen::MatrixXd delassus_like(int rows, int dofs, std::mt19937& rng) {
  std::normal_distribution<double> gauss;
  Eigen::MatrixXd J(rows, dofs);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < dofs; ++c) J(r, c) = gauss(rng);
  return J * J.transpose();
}

Eigen::VectorXd fresh_solve(const Eigen::MatrixXd& A, const std::vector<int>& rows, double ridge,
                            const Eigen::VectorXd& rhs) {
  const int m = static_cast<int>(rows.size());
  Eigen::MatrixXd block(m, m);
  for (int r = 0; r < m; ++r)
    for (int c = 0; c < m; ++c) block(r, c) = A(rows[r], rows[c]) + (r == c ? ridge : 0.0);
  return block.ldlt().solve(rhs);
}

TEST(IncrementalCholesky, FollowsJoinsAndLeavesLikeAFreshFactorisation) {
  std::mt19937 rng(3);
  const Eigen::MatrixXd A = delassus_like(40, 60, rng);  // regular: 40 rows, 60 dofs
  const double ridge = 1e-13 * A.diagonal().maxCoeff();
  IncrementalCholesky factor;
  factor.factor(A, {3, 7, 11}, ridge);
  std::uniform_int_distribution<int> pick(0, 39);
  std::normal_distribution<double> gauss;
  for (int change = 0; change < 200; ++change) {
    const int row = pick(rng);
    const auto& rows = factor.rows();
    const auto at = std::find(rows.begin(), rows.end(), row);
    if (at == rows.end())
      factor.add(A, row, ridge);
    else if (rows.size() > 1)
      factor.remove(static_cast<std::size_t>(at - rows.begin()));
    Eigen::VectorXd rhs(factor.size());
    for (auto& x : rhs) x = gauss(rng);
    const Eigen::VectorXd expected = fresh_solve(A, factor.rows(), ridge, rhs);
    ASSERT_LE((factor.solve(rhs) - expected).norm(), 1e-8 * expected.norm()) << "after change " << change;
  }
}

TEST(IncrementalCholesky, DependentRowsStaySolvable) {
  // Four corners of a box face on the ground: three degrees of freedom, four rows.
  Eigen::MatrixXd J(4, 3);  // (vz, wx, wy) of a 0.2 m box
  J << 1, 0.1, -0.1, 1, 0.1, 0.1, 1, -0.1, -0.1, 1, -0.1, 0.1;
  const Eigen::MatrixXd A = J * J.transpose();
  const double ridge = 1e-13 * A.diagonal().maxCoeff();
  IncrementalCholesky factor;
  for (int row = 0; row < 4; ++row) factor.add(A, row, ridge);
  // Equal pushes at the four corners: any solution must give J^T x the same force.
  const Eigen::VectorXd rhs = Eigen::VectorXd::Constant(4, 1.0);
  const Eigen::VectorXd x = factor.solve(rhs);
  ASSERT_TRUE(x.allFinite());
  EXPECT_LE((A * x - rhs).norm(), 1e-6);
  factor.remove(1);
  const Eigen::VectorXd y = factor.solve(Eigen::VectorXd::Constant(3, 1.0));
  EXPECT_LE((fresh_solve(A, factor.rows(), ridge, Eigen::VectorXd::Constant(3, 1.0)) - y).norm(), 1e-6 * y.norm());
}

TEST(IncrementalCholesky, BadArgumentsAreNamed) {
  const Eigen::MatrixXd A = Eigen::MatrixXd::Identity(3, 3);
  IncrementalCholesky factor;
  EXPECT_THROW(factor.add(A, 3, 1e-13), std::invalid_argument);
  EXPECT_THROW(factor.add(A, 0, 0.0), std::invalid_argument);
  factor.add(A, 0, 1e-13);
  EXPECT_THROW(factor.add(A, 0, 1e-13), std::invalid_argument);
  EXPECT_THROW(factor.remove(1), std::invalid_argument);
  EXPECT_THROW(factor.solve(Eigen::VectorXd::Zero(2)), std::invalid_argument);
  try {
    factor.add(A, -1, 1e-13);
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("row -1"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace arphys::dynamics

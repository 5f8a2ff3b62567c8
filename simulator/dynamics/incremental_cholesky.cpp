#include "simulator/dynamics/incremental_cholesky.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace arphys::dynamics {
namespace {

void check_row(const Eigen::MatrixXd& A, int row, const std::vector<int>& present) {
  if (row < 0 || row >= A.rows() || A.rows() != A.cols())
    throw std::invalid_argument("IncrementalCholesky: row " + std::to_string(row) + " is outside the " +
                                std::to_string(A.rows()) + " x " + std::to_string(A.cols()) + " matrix");
  if (std::find(present.begin(), present.end(), row) != present.end())
    throw std::invalid_argument("IncrementalCholesky: row " + std::to_string(row) + " is already in the factor");
}

void check_ridge(double ridge) {
  if (!(ridge > 0)) throw std::invalid_argument("IncrementalCholesky: ridge must be positive, got " + std::to_string(ridge));
}

}  // namespace

void IncrementalCholesky::factor(const Eigen::MatrixXd& A, const std::vector<int>& rows, double ridge) {
  check_ridge(ridge);
  rows_.clear();
  for (const int row : rows) {
    check_row(A, row, rows_);
    rows_.push_back(row);
  }
  const int m = static_cast<int>(rows.size());
  Eigen::MatrixXd block(m, m);
  for (int c = 0; c < m; ++c) {
    for (int r = 0; r < m; ++r) block(r, c) = A(rows[r], rows[c]);
    block(c, c) += ridge;
  }
  // A blocked factorisation when the block is numerically positive definite; else row
  // by row, where a pivot lost to rounding is replaced by the ridge.
  Eigen::LLT<Eigen::MatrixXd> llt(block);
  if (llt.info() == Eigen::Success) {
    L_ = llt.matrixL();
    return;
  }
  rows_.clear();
  L_.resize(0, 0);
  for (const int row : rows) add(A, row, ridge);
}

void IncrementalCholesky::add(const Eigen::MatrixXd& A, int row, double ridge) {
  check_ridge(ridge);
  check_row(A, row, rows_);
  const int m = static_cast<int>(rows_.size());
  if (L_.rows() <= m) {
    const int capacity = std::max(8, 2 * m);
    Eigen::MatrixXd grown = Eigen::MatrixXd::Zero(capacity, capacity);
    grown.topLeftCorner(m, m) = L_.topLeftCorner(m, m);
    L_.swap(grown);
  }
  Eigen::VectorXd coupling(m);
  for (int r = 0; r < m; ++r) coupling[r] = A(rows_[r], row);
  if (m > 0) L_.block(0, 0, m, m).triangularView<Eigen::Lower>().solveInPlace(coupling);
  const double pivot = A(row, row) + ridge - coupling.squaredNorm();
  L_.block(m, 0, 1, m) = coupling.transpose();
  L_(m, m) = std::sqrt(std::max(pivot, ridge));
  rows_.push_back(row);
}

void IncrementalCholesky::remove(std::size_t position) {
  const int m = static_cast<int>(rows_.size());
  if (position >= rows_.size())
    throw std::invalid_argument("IncrementalCholesky: no row at position " + std::to_string(position) + " of " +
                                std::to_string(m));
  const int k = static_cast<int>(position);
  const int after = m - 1 - k;
  // Without row k, the rows after it carry what it contributed: their block's factor
  // gets the rank-one update T T^T + x x^T, x its column below the diagonal.
  Eigen::VectorXd x = L_.block(k + 1, k, after, 1);
  auto T = L_.block(k + 1, k + 1, after, after);
  for (int i = 0; i < after; ++i) {
    const double diagonal = T(i, i);
    const double r = std::hypot(diagonal, x[i]);
    const double c = r / diagonal, s = x[i] / diagonal;
    T(i, i) = r;
    const int below = after - 1 - i;
    if (below == 0) continue;
    auto column = T.block(i + 1, i, below, 1);
    auto rest = x.segment(i + 1, below);
    column = (column + s * rest) / c;
    rest = c * rest - s * column;
  }
  // Close the gap: rows after k move up, columns after k move left.
  if (after > 0) {
    L_.block(k, 0, after, k) = L_.block(k + 1, 0, after, k).eval();
    L_.block(k, k, after, after) = L_.block(k + 1, k + 1, after, after).eval();
  }
  rows_.erase(rows_.begin() + k);
}

Eigen::VectorXd IncrementalCholesky::solve(const Eigen::VectorXd& rhs) const {
  const int m = static_cast<int>(rows_.size());
  if (rhs.size() != m)
    throw std::invalid_argument("IncrementalCholesky::solve: right-hand side of " + std::to_string(rhs.size()) +
                                " entries for a factor of " + std::to_string(m) + " rows");
  Eigen::VectorXd x = rhs;
  if (m == 0) return x;
  const auto L = L_.topLeftCorner(m, m).triangularView<Eigen::Lower>();
  L.solveInPlace(x);
  L.transpose().solveInPlace(x);
  return x;
}

}  // namespace arphys::dynamics

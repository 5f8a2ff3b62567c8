#pragma once
// The Cholesky factor of a symmetric positive semidefinite matrix's principal
// submatrix on a changing set of rows, kept up to date as rows join and leave:
//   L L^T = A_PP + ridge I,   P = rows(), in the order they joined.
// The active-set contact solver adds or drops one row per iteration; updating the
// factor costs O(m^2) per change where factorising again costs O(m^3) (in a 1000-box
// pile, a quarter of the run was spent refactorising passive sets of 20-60 rows).
#include <cstddef>
#include <vector>

#include <Eigen/Core>

namespace arphys::dynamics {

class IncrementalCholesky {
 public:
  // Starts over on `rows` of A (square, symmetric; only its entries on those rows are read).
  // ridge > 0 keeps the factor regular when rows depend on each other (four corners of a
  // box face constrain three degrees of freedom); a row that depends on the ones before
  // it to rounding gets the ridge as its pivot. Throws std::invalid_argument for a row
  // outside A, a row already present or a ridge that is not positive.
  void factor(const Eigen::MatrixXd& A, const std::vector<int>& rows, double ridge);
  // Appends a row (O(m^2)).
  void add(const Eigen::MatrixXd& A, int row, double ridge);
  // Drops the row at `position` of rows() (O(m^2): a rank-one update of the rows after it).
  void remove(std::size_t position);
  // x with (A_PP + ridge I) x = rhs, both ordered as rows().
  Eigen::VectorXd solve(const Eigen::VectorXd& rhs) const;

  const std::vector<int>& rows() const { return rows_; }
  std::size_t size() const { return rows_.size(); }

 private:
  Eigen::MatrixXd L_;  // the factor is its leading size() x size() lower triangle
  std::vector<int> rows_;
};

}  // namespace arphys::dynamics

#include "simulator/dynamics/contact_solver.hpp"

#include <Eigen/Cholesky>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "simulator/dynamics/disjoint_sets.hpp"
#include "simulator/dynamics/incremental_cholesky.hpp"

namespace arphys::dynamics {
namespace {

// One row's Jacobian: the 6-vectors multiplying body a's and body b's (v, w).
struct JacobianRow {
  Eigen::Matrix<double, 6, 1> a = Eigen::Matrix<double, 6, 1>::Zero(), b = Eigen::Matrix<double, 6, 1>::Zero();
};

JacobianRow jacobian(const ContactRow& row, const Eigen::Vector3d& direction, const std::vector<BodyInertia>& inertia) {
  JacobianRow J;
  if (row.body_b >= 0) {
    J.b.head<3>() = direction;
    J.b.tail<3>() = (row.point_W - inertia[row.body_b].com_W).cross(direction);
  }
  if (row.body_a >= 0) {
    J.a.head<3>() = -direction;
    J.a.tail<3>() = -(row.point_W - inertia[row.body_a].com_W).cross(direction);
  }
  return J;
}

Eigen::Matrix<double, 6, 1> inverse_mass_times(const BodyInertia& body, const Eigen::Matrix<double, 6, 1>& f) {
  Eigen::Matrix<double, 6, 1> out;
  out.head<3>() = body.inverse_mass_1_kg * f.head<3>();
  out.tail<3>() = body.inverse_inertia_W * f.tail<3>();
  return out;
}

double apply(const JacobianRow& J, const ContactRow& row, const std::vector<BodyVelocity>& u) {
  double value = 0;
  if (row.body_a >= 0) value += J.a.head<3>().dot(u[row.body_a].v_WBcm_m_s) + J.a.tail<3>().dot(u[row.body_a].w_WB_rad_s);
  if (row.body_b >= 0) value += J.b.head<3>().dot(u[row.body_b].v_WBcm_m_s) + J.b.tail<3>().dot(u[row.body_b].w_WB_rad_s);
  return value;
}

void add_impulse(const JacobianRow& J, const ContactRow& row, const std::vector<BodyInertia>& inertia, double impulse,
                 std::vector<BodyVelocity>& u) {
  auto add = [&](int body, const Eigen::Matrix<double, 6, 1>& j) {
    const Eigen::Matrix<double, 6, 1> du = inverse_mass_times(inertia[body], impulse * j);
    u[body].v_WBcm_m_s += du.head<3>();
    u[body].w_WB_rad_s += du.tail<3>();
  };
  if (row.body_a >= 0) add(row.body_a, J.a);
  if (row.body_b >= 0) add(row.body_b, J.b);
}

// M^-1 J^T of a row, by body side: an impulse along the row changes the bodies'
// velocities by impulse times this.
JacobianRow mass_weighted(const JacobianRow& J, const ContactRow& row, const std::vector<BodyInertia>& inertia) {
  JacobianRow W;
  if (row.body_a >= 0) W.a = inverse_mass_times(inertia[row.body_a], J.a);
  if (row.body_b >= 0) W.b = inverse_mass_times(inertia[row.body_b], J.b);
  return W;
}

// The island's Delassus matrix J M^-1 J^T. Rows couple only through a body they share
// (in a pile, a few dozen of an island's hundreds of rows): only those entries are
// computed, the rest are zero (computing all n^2 cost 6 % of a 1000-box pile's time).
// Each row's M^-1 J^T is formed once, so an entry is a 6-vector dot product per shared body.
Eigen::MatrixXd delassus_matrix(const std::vector<JacobianRow>& J, const std::vector<ContactRow>& rows,
                                const std::vector<int>& island, const std::vector<BodyInertia>& inertia) {
  const int n = static_cast<int>(island.size());
  std::vector<std::vector<int>> rows_of_body(inertia.size());
  std::vector<JacobianRow> MJ(n);  // M^-1 J^T, by body side
  for (int k = 0; k < n; ++k) {
    const ContactRow& row = rows[island[k]];
    if (row.body_a >= 0) rows_of_body[row.body_a].push_back(k);
    if (row.body_b >= 0 && row.body_b != row.body_a) rows_of_body[row.body_b].push_back(k);
    MJ[k] = mass_weighted(J[k], row, inertia);
  }
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
  std::vector<int> seen(n, -1);
  for (int i = 0; i < n; ++i) {
    const ContactRow& ri = rows[island[i]];
    for (const int body : {ri.body_a, ri.body_b}) {
      if (body < 0) continue;
      for (const int j : rows_of_body[body]) {
        if (j < i || seen[j] == i) continue;  // each coupled pair once (summing the shared bodies)
        seen[j] = i;
        const ContactRow& rj = rows[island[j]];
        double value = 0;
        for (const auto& [body_i, ji] : {std::pair{ri.body_a, &J[i].a}, std::pair{ri.body_b, &J[i].b}}) {
          if (body_i < 0) continue;
          if (body_i == rj.body_a) value += ji->dot(MJ[j].a);
          if (body_i == rj.body_b) value += ji->dot(MJ[j].b);
        }
        A(i, j) = A(j, i) = value;
      }
    }
  }
  return A;
}

// How far a squeezed island's bounds are relaxed (solve_contacts).
enum class Relaxation { kNone, kContradictoryRows, kEveryRow, kNonDynamicMotionToo };

struct DualSolution {
  Eigen::VectorXd lambda;
  // The ridge added to the passive block's diagonal: where the demands contradict each
  // other, the solve meets them only through it, with impulses of about demand / ridge.
  double ridge = 0;
  double residual = 0;
  int iterations = 0;
  bool converged = true;
};

// Above this many rows the active set's passive block is factorised sparse (in the
// order a fill-reducing order of the whole island induces on it) and the dual residual
// computed with the sparse matrix: a dense factorisation of a pile's 600-row island costs
// 20-30 ms, one per added row, while its Delassus matrix has a few dozen non-zeros per row.
// Below it, dense is faster.
constexpr int kSparseRows = 128;

// An island's Delassus matrix in sparse form and its fill-reducing order, built when a
// solve first needs them and kept for the island's other solves (a frictional island is
// solved three times, and again when squeezed; building them is a scan of the whole dense
// matrix and an AMD ordering).
struct SparseDelassus {
  Eigen::SparseMatrix<double> A;
  bool built = false;
  std::vector<int> rank;  // a row's place in the elimination order (empty: not found yet)
};

// min 1/2 l^T A l + q^T l over l >= 0 (Lawson & Hanson's active set on the normal
// equations, as in Bro & de Jong's fast NNLS). A is positive semidefinite; a tiny
// ridge keeps the passive block solvable when contacts are redundant (four corners
// of a face constrain three degrees of freedom). The passive block's factor follows
// the rows joining and leaving it (IncrementalCholesky) up to kSparseRows rows; a
// larger block is factorised sparse, afresh, each time it changes (unless that loses
// digits: then the dense factor follows it again).
// start_from: rows the active set starts from; with_violated: and every row the
// unconstrained motion violates; sparse_form: the island's, shared by its solves.
// (One active-set loop over one factor: kept whole, longer than the usual 100 lines.)
DualSolution solve_dual_exact(const Eigen::MatrixXd& A, const Eigen::VectorXd& q, bool with_violated,
                              const std::vector<char>& start_from, SparseDelassus& sparse_form) {
  using SparseMatrix = Eigen::SparseMatrix<double>;
  const bool sparse = q.size() > kSparseRows;
  if (sparse && !sparse_form.built) {
    sparse_form.A = SparseMatrix(A.sparseView());
    sparse_form.built = true;
  }
  const SparseMatrix& A_sparse = sparse_form.A;
  const auto residual = [&](const Eigen::VectorXd& lambda) -> Eigen::VectorXd {
    return sparse ? Eigen::VectorXd(A_sparse * lambda + q) : Eigen::VectorXd(A * lambda + q);
  };
  const int n = static_cast<int>(q.size());
  DualSolution out;
  out.lambda = Eigen::VectorXd::Zero(n);
  const double scale = std::max(1.0, q.cwiseAbs().maxCoeff());
  const double tolerance = 1e-11 * scale;
  const double ridge = std::max(1e-300, 1e-13 * A.diagonal().maxCoeff());
  out.ridge = ridge;
  std::vector<char> passive(n, 0);
  std::vector<int> P;  // the passive rows, in the order they joined
  IncrementalCholesky factor;
  bool factor_follows = false;  // factor.rows() == P
  // Set when a sparse factorisation lost digits (nearly dependent rows: a squeezed pile
  // of meshes, sixteen rows a pair): from then on the dense factor, kept up to date row
  // by row, serves the rest of the solve. (A dense factorisation afresh for every change of
  // the active set costs 30 s per step in a 100-bunny pile.)
  bool sparse_unreliable = false;
  const auto large = [&] { return sparse && !sparse_unreliable && static_cast<int>(P.size()) > kSparseRows; };
  const auto join = [&](int row) {
    P.push_back(row);
    passive[row] = 1;
    if (!factor_follows) return;
    if (large())
      factor_follows = false;
    else
      factor.add(A, row, ridge);
  };
  // Drops the rows at these positions of P (ascending).
  const auto leave = [&](const std::vector<std::size_t>& positions) {
    // Many rows leaving at once: cheaper to factorise again when next needed.
    if (3 * positions.size() > P.size()) factor_follows = false;
    for (auto position = positions.rbegin(); position != positions.rend(); ++position) {
      passive[P[*position]] = 0;
      P.erase(P.begin() + static_cast<std::ptrdiff_t>(*position));
      if (factor_follows) factor.remove(*position);
    }
  };
  std::vector<int> local(q.size(), -1);  // a row's place in the passive block
  std::vector<int>& rank = sparse_form.rank;  // a row's place in the island's elimination order (sparse only)
  // The equality problem on the passive rows (with the ridge), by position in P.
  const auto solve_passive = [&]() -> Eigen::VectorXd {
    const int m = static_cast<int>(P.size());
    Eigen::VectorXd rhs(m);
    for (int r = 0; r < m; ++r) rhs[r] = -q[P[r]];
    if (!large()) {
      if (!factor_follows) {
        factor.factor(A, P, ridge);
        factor_follows = true;
      }
      return factor.solve(rhs);
    }
    if (rank.empty()) {
      // The island's fill-reducing order, found once: each passive block is factorised
      // in the order it induces (an elimination order per block, found afresh for each
      // of a pile's thousands of factorisations, cost more than the factorisations).
      Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> elimination;
      Eigen::AMDOrdering<int>()(A_sparse, elimination);
      rank.resize(n);
      for (int k = 0; k < n; ++k) rank[elimination.indices()[k]] = k;
    }
    std::vector<int> order(m);  // positions in P, in elimination order
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int x, int y) { return rank[P[x]] < rank[P[y]]; });
    for (int k = 0; k < m; ++k) local[P[order[k]]] = k;
    std::vector<Eigen::Triplet<double>> entries;
    for (int c = 0; c < m; ++c)
      for (SparseMatrix::InnerIterator it(A_sparse, P[c]); it; ++it)
        if (local[it.row()] >= 0)
          entries.emplace_back(local[it.row()], local[P[c]], it.value() + (it.row() == P[c] ? ridge : 0.0));
    for (int r = 0; r < m; ++r) local[P[r]] = -1;
    SparseMatrix App(m, m);
    App.setFromTriplets(entries.begin(), entries.end());
    const Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower, Eigen::NaturalOrdering<int>> ldlt(App);
    if (ldlt.info() == Eigen::Success) {
      // Without pivoting the ridge-regularised block can lose digits: refined once and
      // checked against the block itself, else solved dense (from here on).
      Eigen::VectorXd rhs_ordered(m);
      for (int k = 0; k < m; ++k) rhs_ordered[k] = rhs[order[k]];
      Eigen::VectorXd s_ordered = ldlt.solve(rhs_ordered);
      s_ordered += ldlt.solve(rhs_ordered - App * s_ordered);
      if (s_ordered.allFinite() && (App * s_ordered - rhs_ordered).norm() <= 1e-9 * (rhs.norm() + 1e-300)) {
        Eigen::VectorXd s(m);
        for (int k = 0; k < m; ++k) s[order[k]] = s_ordered[k];
        return s;
      }
    }
    sparse_unreliable = true;
    factor.factor(A, P, ridge);
    factor_follows = true;
    return factor.solve(rhs);
  };
  // Warm start: at rest, most active rows are those the unconstrained motion would
  // violate, and most of the others pushed in the caller's previous solve. Start from
  // them, dropping those the equality solution pushes the wrong way until it is
  // positive; the loop below then adds what is still violated, one row at a time. A
  // cold start adds every one of them that way, one iteration each: a second for a pile
  // with a thousand contact rows.
  // Where contacts are redundant (a bunny's sixteen points on a table) starting from
  // every violated row spreads the impulse over all of them where the one-at-a-time
  // loop picks a few; both are exact for the normals, but the staggered friction solve
  // bounds each point's friction by its normal impulse and, from the spread answer,
  // launched bunnies of a frictional pile (300+ rad/s). So frictional islands start only
  // from rows that pushed before (the loop's own earlier picks: no spreading).
  for (int i = 0; i < n; ++i)
    if ((with_violated && q[i] < -tolerance) || start_from[i]) join(i);
  while (!P.empty()) {
    const Eigen::VectorXd s = solve_passive();
    std::vector<std::size_t> pushing_wrong_way;
    for (std::size_t r = 0; r < P.size(); ++r)
      if (!(s[r] > 0)) pushing_wrong_way.push_back(r);
    if (pushing_wrong_way.empty()) {
      for (std::size_t r = 0; r < P.size(); ++r) out.lambda[P[r]] = s[r];
      break;
    }
    leave(pushing_wrong_way);
  }
  Eigen::VectorXd w = residual(out.lambda);
  const int max_outer = 3 * n + 20;
  for (int outer = 0; outer < max_outer; ++outer) {
    ++out.iterations;
    int j = -1;
    for (int i = 0; i < n; ++i)
      if (!passive[i] && w[i] < -tolerance && (j < 0 || w[i] < w[j])) j = i;
    if (j < 0) break;
    join(j);
    for (int inner = 0; inner < 3 * n + 20; ++inner) {
      const Eigen::VectorXd s = solve_passive();
      if ((s.array() > 0).all()) {
        for (std::size_t r = 0; r < P.size(); ++r) out.lambda[P[r]] = s[r];
        break;
      }
      // Step from lambda towards s until a passive variable reaches zero.
      double alpha = 1;
      for (std::size_t r = 0; r < P.size(); ++r)
        if (s[r] <= 0) alpha = std::min(alpha, out.lambda[P[r]] / (out.lambda[P[r]] - s[r]));
      std::vector<std::size_t> reached_zero;
      for (std::size_t r = 0; r < P.size(); ++r) {
        double& l = out.lambda[P[r]];
        l += alpha * (s[r] - l);
        if (l <= 1e-300 || (s[r] <= 0 && l <= 1e-15 * scale)) {
          l = 0;
          reached_zero.push_back(r);
        }
      }
      leave(reached_zero);
    }
    w = residual(out.lambda);
    if (!out.lambda.allFinite() || out.lambda.cwiseAbs().maxCoeff() > 1e12 * scale) {
      out.converged = false;
      break;
    }
  }
  for (int i = 0; i < n; ++i) {
    out.residual = std::max(out.residual, -w[i]);
    if (out.lambda[i] > 0) out.residual = std::max(out.residual, std::abs(w[i]));
  }
  if (out.residual > 1e-6 * scale) out.converged = false;
  return out;
}

// Union-find over dynamic bodies: rows that share a body belong to one island.
std::vector<std::vector<int>> islands(int bodies, const std::vector<ContactRow>& rows) {
  DisjointSets sets(bodies);
  for (const auto& row : rows)
    if (row.body_a >= 0 && row.body_b >= 0) sets.join(row.body_a, row.body_b);
  std::vector<int> island_of(bodies, -1);
  std::vector<std::vector<int>> groups;
  for (int r = 0; r < static_cast<int>(rows.size()); ++r) {
    const int body = rows[r].body_a >= 0 ? rows[r].body_a : rows[r].body_b;
    if (body < 0) continue;
    const int root = sets.find(body);
    if (island_of[root] < 0) {
      island_of[root] = static_cast<int>(groups.size());
      groups.emplace_back();
    }
    groups[island_of[root]].push_back(r);
  }
  return groups;
}

// Orthonormal tangents of a normal: the axes of the friction impulse.
void tangents(const Eigen::Vector3d& n, Eigen::Vector3d& t1, Eigen::Vector3d& t2) {
  t1 = (std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY()).cross(n).normalized();
  t2 = n.cross(t1);
}

// Scales the friction impulse (f1, f2) along two orthonormal tangents back onto Coulomb's
// disc of radius bound_N_s, keeping its direction.
void clamp_to_friction_disc(double& f1, double& f2, double bound_N_s) {
  // Squared, and sqrt rather than std::hypot: impulses are nowhere near overflow, and glibc's
  // careful hypot, called for every frictional row in every sweep, costs a quarter of a
  // frictional 1000-box pile's time.
  const double magnitude_squared = f1 * f1 + f2 * f2;
  if (magnitude_squared <= bound_N_s * bound_N_s) return;
  const double scale = bound_N_s > 0 ? bound_N_s / std::sqrt(magnitude_squared) : 0.0;
  f1 *= scale;
  f2 *= scale;
}

// The friction part of a warm-start impulse start_W along the row's tangents t1 and t2,
// in Coulomb's disc of mu times its normal part.
void warm_friction(const ContactRow& row, const Eigen::Vector3d& start_W, const Eigen::Vector3d& t1,
                   const Eigen::Vector3d& t2, double& f1, double& f2) {
  f1 = start_W.dot(t1);
  f2 = start_W.dot(t2);
  clamp_to_friction_disc(f1, f2, row.friction * std::max(0.0, start_W.dot(row.normal_W)));
}

// Projected Gauss-Seidel over an island's rows, warm-started from `lambda`; friction
// rows (two per frictional contact) stay in Coulomb's disc, mu times their normal impulse.
// (One sweep loop over the island's packed velocities: kept whole, a little over 100 lines.)
// Friction impulses along the two tangents of each row, warm-started and returned.
struct FrictionImpulses {
  std::vector<double> f1, f2;
};

int projected_gauss_seidel(const std::vector<BodyInertia>& inertia, std::vector<BodyVelocity>& u,
                           const std::vector<ContactRow>& rows, const std::vector<int>& island, Eigen::VectorXd& lambda,
                           int sweeps, double tolerance_m_s, bool normals_fixed, FrictionImpulses& friction) {
  using Vector6d = Eigen::Matrix<double, 6, 1>;
  const int n = static_cast<int>(island.size());
  // The island's bodies, and their velocities as contiguous 6-vectors; one more slot,
  // always zero, stands for the non-dynamic side of a row (its Jacobian there is zero),
  // so an update needs no branch.
  std::vector<int> bodies;
  for (const int r : island)
    for (const int body : {rows[r].body_a, rows[r].body_b})
      if (body >= 0) bodies.push_back(body);
  std::sort(bodies.begin(), bodies.end());
  bodies.erase(std::unique(bodies.begin(), bodies.end()), bodies.end());
  const int absent = static_cast<int>(bodies.size());
  const auto slot = [&](int body) {
    return body < 0 ? absent : static_cast<int>(std::lower_bound(bodies.begin(), bodies.end(), body) - bodies.begin());
  };
  std::vector<Vector6d> v(bodies.size() + 1, Vector6d::Zero());
  for (int s = 0; s < absent; ++s) v[s] << u[bodies[s]].v_WBcm_m_s, u[bodies[s]].w_WB_rad_s;
  // Each direction (a row's normal and, where it has friction, its two tangents) as a
  // sweep uses it: its slots, Jacobian and M^-1 J^T per side, formed once (a sweep's
  // update is then a scaled 6-vector), and its own coupling J M^-1 J^T. Contiguous, the
  // normals apart from the tangents, with what a sweep reads of their rows: a
  // frictionless sweep reads one array front to back. (Interleaved with unused tangents,
  // and reading each row's friction from the row, the sweeps of a frictionless 1000-box
  // pile take a sixth longer.)
  struct SweepDirection {
    int a = 0, b = 0;
    Vector6d Ja = Vector6d::Zero(), Jb = Vector6d::Zero(), Wa = Vector6d::Zero(), Wb = Vector6d::Zero();
    double coupling = 0;
    double offset_m_s = 0;  // normals: known minus demanded normal velocity; tangents: known slip
    double friction = 0;    // normals: the row's Coulomb coefficient
    // normals of frictional rows: the largest eigenvalue of the two tangents' coupling block
    double tangent_coupling = 0;
  };
  std::vector<SweepDirection> normals(n);
  bool frictional = false;
  for (const int r : island) frictional |= rows[r].friction > 0;
  std::vector<SweepDirection> tangent_directions(frictional ? 2 * static_cast<std::size_t>(n) : 0);
  const auto direction = [&](const ContactRow& row, const Eigen::Vector3d& along) {
    SweepDirection D;
    D.a = slot(row.body_a);
    D.b = slot(row.body_b);
    const JacobianRow J = jacobian(row, along, inertia);
    const JacobianRow W = mass_weighted(J, row, inertia);
    D.Ja = J.a;
    D.Jb = J.b;
    D.Wa = W.a;
    D.Wb = W.b;
    D.coupling = J.a.dot(W.a) + J.b.dot(W.b);
    return D;
  };
  std::vector<double>& f1 = friction.f1;
  std::vector<double>& f2 = friction.f2;
  f1.resize(n, 0.0);
  f2.resize(n, 0.0);
  for (int k = 0; k < n; ++k) {
    const ContactRow& row = rows[island[k]];
    normals[k] = direction(row, row.normal_W);
    normals[k].offset_m_s = row.known_normal_velocity_m_s - row.min_normal_velocity_m_s;
    normals[k].friction = row.friction;
    if (row.friction > 0) {
      Eigen::Vector3d t1, t2;
      tangents(row.normal_W, t1, t2);
      SweepDirection& T1 = tangent_directions[2 * k] = direction(row, t1);
      SweepDirection& T2 = tangent_directions[2 * k + 1] = direction(row, t2);
      T1.offset_m_s = t1.dot(row.known_tangent_velocity_W_m_s);
      T2.offset_m_s = t2.dot(row.known_tangent_velocity_W_m_s);
      const double cross = T1.Ja.dot(T2.Wa) + T1.Jb.dot(T2.Wb);
      normals[k].tangent_coupling = 0.5 * (T1.coupling + T2.coupling) +
                                    std::hypot(0.5 * (T1.coupling - T2.coupling), cross);
    }
  }
  // Moves impulse `value` towards `target` (clamped to [lo, hi]) along D; returns the
  // change of D's velocity.
  const auto update = [&](const SweepDirection& D, double& value, double target, double lo, double hi) {
    const double next = std::clamp(target, lo, hi);
    const double delta = next - value;
    v[D.a] += delta * D.Wa;
    v[D.b] += delta * D.Wb;
    value = next;
    return std::abs(delta) * D.coupling;
  };
  const auto velocity = [&](const SweepDirection& D) { return D.Ja.dot(v[D.a]) + D.Jb.dot(v[D.b]); };
  const double inf = std::numeric_limits<double>::infinity();
  int sweep = 0;
  for (; sweep < sweeps; ++sweep) {
    double change_m_s = 0;  // the largest change of a row's velocity in this sweep
    for (int k = 0; k < n; ++k) {
      const SweepDirection& N = normals[k];
      if (!normals_fixed && N.coupling > 0)
        change_m_s =
            std::max(change_m_s, update(N, lambda[k], lambda[k] - (velocity(N) + N.offset_m_s) / N.coupling, 0.0, inf));
      if (N.friction > 0) {
        // Both tangents take one step against the slip, scaled by the largest coupling
        // of the pair (the tangent block's largest eigenvalue), then the pair goes back into
        // Coulomb's disc: at the fixed point, friction is inside the disc with no slip, or
        // on its rim against the slip. (Each tangent scaled by its own coupling, the rim
        // friction opposed a skewed slip, and a box sliding down an incline at 30 degrees to
        // the tangents turned and slid 2 % fast.) The disc, not each tangent bounded by
        // mu lambda on its own (a pyramid): at 45 degrees that made friction sqrt(2) times
        // as strong, and the box slid 43 % slow.
        if (!(N.tangent_coupling > 0)) continue;
        const SweepDirection& T1 = tangent_directions[2 * k];
        const SweepDirection& T2 = tangent_directions[2 * k + 1];
        double g1 = f1[k] - (velocity(T1) + T1.offset_m_s) / N.tangent_coupling,
               g2 = f2[k] - (velocity(T2) + T2.offset_m_s) / N.tangent_coupling;
        clamp_to_friction_disc(g1, g2, N.friction * lambda[k]);
        change_m_s = std::max({change_m_s, update(T1, f1[k], g1, -inf, inf), update(T2, f2[k], g2, -inf, inf)});
      }
    }
    if (change_m_s <= tolerance_m_s) break;
  }
  for (int s = 0; s < absent; ++s) {
    u[bodies[s]].v_WBcm_m_s = v[s].head<3>();
    u[bodies[s]].w_WB_rad_s = v[s].tail<3>();
  }
  return sweep;
}

bool same_row(const ContactRow& a, const ContactRow& b) {
  return a.body_a == b.body_a && a.body_b == b.body_b && a.point_W == b.point_W && a.normal_W == b.normal_W &&
         a.min_normal_velocity_m_s == b.min_normal_velocity_m_s &&
         a.known_normal_velocity_m_s == b.known_normal_velocity_m_s && a.friction == b.friction &&
         a.pushed_before == b.pushed_before && a.warm_impulse_W_N_s == b.warm_impulse_W_N_s &&
         a.known_tangent_velocity_W_m_s == b.known_tangent_velocity_W_m_s;
}

// The same rows (bodies as keys) and the same starting velocities: the same answer.
bool same_island(const SolvedIslands::Island& a, const SolvedIslands::Island& b) {
  if (a.rows.size() != b.rows.size() || a.bodies != b.bodies) return false;
  for (std::size_t k = 0; k < a.rows.size(); ++k)
    if (!same_row(a.rows[k], b.rows[k])) return false;
  for (std::size_t k = 0; k < a.before.size(); ++k)
    if (a.before[k].v_WBcm_m_s != b.before[k].v_WBcm_m_s || a.before[k].w_WB_rad_s != b.before[k].w_WB_rad_s) return false;
  return true;
}

// `later` is `earlier` with rows added after its own (an island re-solved with an
// impact's rows; the rows come in the caller's order, meetings after resting contacts).
bool extends(const SolvedIslands::Island& later, const SolvedIslands::Island& earlier) {
  if (earlier.rows.size() >= later.rows.size()) return false;
  for (std::size_t k = 0; k < earlier.rows.size(); ++k)
    if (!same_row(earlier.rows[k], later.rows[k])) return false;
  return true;
}

// One island of a solve: its rows (indices into the rows), and, when its answer is
// remembered or it has friction, its bodies in order of first appearance in its rows and
// the velocities they start from (the memo's key, and where the friction rounds restart).
struct IslandInput {
  const std::vector<int>& island;
  std::vector<int> members;
  std::vector<BodyVelocity> before;
  bool frictional = false;
};

// An island's answer beside the velocities it leaves: its normal and friction impulses.
struct IslandAnswer {
  Eigen::VectorXd lambda;
  FrictionImpulses friction;
  double residual_m_s = 0;
  bool infeasible = false;
  int iterations = 0;
};

// The rows' velocities now minus their bounds, by how much a squeeze relaxes them (see
// relaxed_dual).
void fill_q(const std::vector<JacobianRow>& J, const std::vector<ContactRow>& rows, const std::vector<int>& island,
            const std::vector<BodyVelocity>& velocities, Relaxation relaxation, const std::vector<char>& contradictory,
            Eigen::VectorXd& q) {
  for (int i = 0; i < static_cast<int>(island.size()); ++i) {
    const ContactRow& ri = rows[island[i]];
    double slack = ri.known_normal_velocity_m_s - ri.min_normal_velocity_m_s;
    if (relaxation == Relaxation::kEveryRow || (relaxation == Relaxation::kContradictoryRows && contradictory[i]))
      slack = ri.known_normal_velocity_m_s - std::min(0.0, ri.min_normal_velocity_m_s);
    else if (relaxation == Relaxation::kNonDynamicMotionToo)
      slack = std::max(0.0, slack);
    q[i] = apply(J[i], ri, velocities) + slack;
  }
}

// Contradictory demands: a body squeezed (between a tracked box and the table, say). The
// island's bounds are relaxed step by step until solvable, never launching anything:
// 1. the rows the solve could meet only through its ridge (the contradiction) lose their
//    push-apart demands (depenetration, restitution): n . v_rel >= min(0, bound), "do not
//    approach"; the rest of the island keeps its own;
// 2. so does every row (the contradiction reached further);
// 3. non-dynamic bodies close in from two sides: what they press in cannot be undone this
//    step. The dynamic bodies only keep from approaching anything (J u >= min(0, bound -
//    known), which u = 0 meets: always feasible), so none falls through its other supports.
// (Relaxed with the wrong sign, stricter than the original, a squeezed 100-bunny pile got
// no impulses at all and fell through itself.)
DualSolution relaxed_dual(const Eigen::MatrixXd& A, const std::vector<JacobianRow>& J,
                          const std::vector<ContactRow>& rows, const IslandInput& in,
                          const std::vector<BodyVelocity>& velocities, const std::vector<char>& start_from,
                          SparseDelassus& sparse_form, DualSolution dual) {
  const int n = static_cast<int>(in.island.size());
  bool any_contradictory = false;
  std::vector<char> contradictory(n, 0);
  for (int k = 0; k < n; ++k) {
    contradictory[k] = dual.lambda[k] * dual.ridge > 1e-7;  // m/s of its demand met by the ridge
    any_contradictory |= contradictory[k] != 0;
  }
  Eigen::VectorXd q(n);
  for (const Relaxation relaxation :
       {Relaxation::kContradictoryRows, Relaxation::kEveryRow, Relaxation::kNonDynamicMotionToo}) {
    if (relaxation == Relaxation::kContradictoryRows && !any_contradictory) continue;
    fill_q(J, rows, in.island, velocities, relaxation, contradictory, q);
    dual = solve_dual_exact(A, q, !in.frictional, start_from, sparse_form);
    if (dual.converged) break;
  }
  if (!dual.converged) dual.lambda.setZero();  // numerically lost: give up on this island rather than launch it
  return dual;
}

// The exact solver's island: without friction one exact solve. With it, staggered: exact
// normals for the current friction impulses, then friction sweeps with those normals held,
// three times, ending on an exact normal solve so the constraints hold exactly.
IslandAnswer solve_island_exact(const std::vector<BodyInertia>& inertia, std::vector<BodyVelocity>& velocities,
                                const std::vector<ContactRow>& rows, const IslandInput& in,
                                const ContactSolverOptions& options, const SolvedIslands::Island* earlier) {
  const std::vector<int>& island = in.island;
  const int n = static_cast<int>(island.size());
  IslandAnswer answer;
  answer.lambda = Eigen::VectorXd::Zero(n);
  FrictionImpulses& friction = answer.friction;
  std::vector<JacobianRow> J(n);
  for (int k = 0; k < n; ++k) J[k] = jacobian(rows[island[k]], rows[island[k]].normal_W, inertia);
  const Eigen::MatrixXd A = delassus_matrix(J, rows, island, inertia);
  SparseDelassus sparse_form;
  std::vector<char> pushed_before(n);
  for (int k = 0; k < n; ++k) pushed_before[k] = rows[island[k]].pushed_before;
  // Its solve without the impact's rows at these poses (`earlier`) pushed with rows nearer
  // this answer's than the last step's. (Its friction is no better a start: the sweeps
  // stopped millimetres per second off the converged answer from there.)
  if (earlier)
    for (int k = 0; k < n && static_cast<std::size_t>(k) < earlier->impulses.size(); ++k)
      pushed_before[k] = earlier->impulses[k] > 0;
  const int rounds = in.frictional ? 3 : 1;
  if (in.frictional) {
    // The friction sweeps start from last step's friction (kept in the disc of mu times last
    // step's normal impulse), as the iterative solver's do: from zero, 50 sweeps did not
    // quite stop a box resting on an incline (mu 0.7, 30 degrees) each step.
    friction.f1.assign(n, 0.0);
    friction.f2.assign(n, 0.0);
    for (int k = 0; k < n; ++k) {
      const ContactRow& row = rows[island[k]];
      if (row.friction <= 0) continue;
      Eigen::Vector3d t1, t2;
      tangents(row.normal_W, t1, t2);
      warm_friction(row, row.warm_impulse_W_N_s, t1, t2, friction.f1[k], friction.f2[k]);
    }
  }
  for (int round = 0; round < rounds; ++round) {
    if (in.frictional) {
      // (The island's own bodies only: a copy of every body's velocity per island costs a
      // tenth of a 1000-box pile's solve.)
      if (round > 0)
        for (std::size_t b = 0; b < in.members.size(); ++b) velocities[in.members[b]] = in.before[b];
      // Apply the friction impulses found so far.
      for (int k = 0; k < n; ++k) {
        const ContactRow& row = rows[island[k]];
        if (row.friction <= 0) continue;
        Eigen::Vector3d t1, t2;
        tangents(row.normal_W, t1, t2);
        add_impulse(jacobian(row, t1, inertia), row, inertia, friction.f1[k], velocities);
        add_impulse(jacobian(row, t2, inertia), row, inertia, friction.f2[k], velocities);
      }
    }
    Eigen::VectorXd q(n);
    fill_q(J, rows, island, velocities, Relaxation::kNone, {}, q);
    // Frictional islands start from the rows that pushed (in the previous step, then in the
    // previous round), not from every violated row (see solve_dual_exact).
    std::vector<char> start_from = pushed_before;
    if (round > 0)
      for (int k = 0; k < n; ++k) start_from[k] = answer.lambda[k] > 0;
    DualSolution dual = solve_dual_exact(A, q, !in.frictional, start_from, sparse_form);
    if (!dual.converged) {
      answer.infeasible = true;
      dual = relaxed_dual(A, J, rows, in, velocities, start_from, sparse_form, std::move(dual));
    }
    answer.lambda = dual.lambda;
    answer.residual_m_s = std::max(answer.residual_m_s, dual.residual);
    answer.iterations += dual.iterations;
    for (int k = 0; k < n; ++k) add_impulse(J[k], rows[island[k]], inertia, answer.lambda[k], velocities);
    if (round + 1 < rounds) {
      const bool provisional = round + 2 < rounds;  // not the last round of sweeps
      const int sweeps =
          provisional ? std::min(options.iterations, options.provisional_friction_sweeps) : options.iterations;
      answer.iterations += projected_gauss_seidel(inertia, velocities, rows, island, answer.lambda, sweeps,
                                                  options.sweep_tolerance_m_s, true, friction);
    }
  }
  return answer;
}

// The iterative solver's island. Warm start: the sweeps begin from last step's impulses,
// applied, instead of from nothing (from zero, 50 sweeps left a stack of ten 1.5 mm/s off
// its bounds every step, and it toppled). An island re-solved with an impact's rows added
// (`earlier`: its solve without them at these poses) starts from that solve's impulses.
IslandAnswer solve_island_iterative(const std::vector<BodyInertia>& inertia, std::vector<BodyVelocity>& velocities,
                                    const std::vector<ContactRow>& rows, const IslandInput& in,
                                    const ContactSolverOptions& options, const SolvedIslands::Island* earlier) {
  const std::vector<int>& island = in.island;
  const int n = static_cast<int>(island.size());
  IslandAnswer answer;
  answer.lambda = Eigen::VectorXd::Zero(n);
  FrictionImpulses& friction = answer.friction;
  friction.f1.assign(n, 0.0);
  friction.f2.assign(n, 0.0);
  for (int k = 0; k < n; ++k) {
    const ContactRow& row = rows[island[k]];
    const Eigen::Vector3d& start_W = earlier && static_cast<std::size_t>(k) < earlier->impulses_W.size()
                                         ? earlier->impulses_W[k]
                                         : row.warm_impulse_W_N_s;
    answer.lambda[k] = std::max(0.0, start_W.dot(row.normal_W));
    add_impulse(jacobian(row, row.normal_W, inertia), row, inertia, answer.lambda[k], velocities);
    if (row.friction <= 0) continue;
    Eigen::Vector3d t1, t2;
    tangents(row.normal_W, t1, t2);
    warm_friction(row, start_W, t1, t2, friction.f1[k], friction.f2[k]);  // (lambda[k]: its normal part)
    add_impulse(jacobian(row, t1, inertia), row, inertia, friction.f1[k], velocities);
    add_impulse(jacobian(row, t2, inertia), row, inertia, friction.f2[k], velocities);
  }
  answer.iterations += projected_gauss_seidel(inertia, velocities, rows, island, answer.lambda, options.iterations,
                                              options.sweep_tolerance_m_s, false, friction);
  // How far the iterative answer is from the KKT conditions.
  for (int k = 0; k < n; ++k) {
    const ContactRow& row = rows[island[k]];
    const JacobianRow J = jacobian(row, row.normal_W, inertia);
    const double w = apply(J, row, velocities) + row.known_normal_velocity_m_s - row.min_normal_velocity_m_s;
    answer.residual_m_s = std::max(answer.residual_m_s, std::max(-w, answer.lambda[k] > 0 ? std::abs(w) : 0.0));
  }
  return answer;
}

// The island as a memo key: its rows and bodies by key, and the velocities it starts from.
SolvedIslands::Island island_key(const std::vector<ContactRow>& rows, const IslandInput& in,
                                 const std::vector<int>& body_keys) {
  const auto key_of = [&](int body) { return body < 0 ? -1 : body_keys[body]; };
  SolvedIslands::Island key;
  for (int r : in.island) {
    ContactRow row = rows[r];
    row.body_a = key_of(row.body_a);
    row.body_b = key_of(row.body_b);
    key.rows.push_back(row);
  }
  for (const int body : in.members) key.bodies.push_back(key_of(body));
  key.before = in.before;
  return key;
}

}  // namespace

ContactSolveResult solve_contacts(const std::vector<BodyInertia>& inertia, std::vector<BodyVelocity>& velocities,
                                  const std::vector<ContactRow>& rows, const ContactSolverOptions& options,
                                  SolvedIslands* memo, const std::vector<int>* body_keys) {
  ContactSolveResult result;
  result.normal_impulses_N_s.assign(rows.size(), 0.0);
  result.impulses_W_N_s.assign(rows.size(), Eigen::Vector3d::Zero());
  if (memo && (!body_keys || body_keys->size() != velocities.size()))
    throw std::invalid_argument("solve_contacts: a memo needs one body key per velocity");
  std::vector<int> island_stamp(velocities.size(), -1);  // the island a body was last listed for
  int island_index = -1;
  for (const std::vector<int>& island : islands(static_cast<int>(velocities.size()), rows)) {
    ++island_index;
    const int n = static_cast<int>(island.size());
    // Small islands are solved again: remembering them costs about what solving them does
    // (remembering every island made a 100-box drop, where nothing meets, 30 % slower).
    constexpr int kMemoRows = 16;
    const bool remember = memo && n >= kMemoRows;
    IslandInput in{island, {}, {}, false};
    for (int r : island) in.frictional |= rows[r].friction > 0;
    if (remember || in.frictional)
      for (int r : island)
        for (const int body : {rows[r].body_a, rows[r].body_b})
          if (body >= 0 && island_stamp[body] != island_index) {
            island_stamp[body] = island_index;
            in.members.push_back(body);
            in.before.push_back(velocities[body]);
          }
    SolvedIslands::Island key;
    // The same island solved earlier at these poses with fewer rows (before the CCD added an
    // impact's): where a solve starts from.
    const SolvedIslands::Island* earlier = nullptr;
    if (remember) {
      key = island_key(rows, in, *body_keys);
      const SolvedIslands::Island* same = nullptr;
      const auto candidates = memo->by_first_body.find(key.bodies.front());
      if (candidates != memo->by_first_body.end())
        for (const std::size_t k : candidates->second) {
          if (same_island(memo->islands[k], key)) {
            same = &memo->islands[k];
            break;
          }
          if (extends(key, memo->islands[k])) earlier = &memo->islands[k];
        }
      if (same) {
        ++memo->reused;
        for (int k = 0; k < n; ++k) {
          result.normal_impulses_N_s[island[k]] = same->impulses[k];
          result.impulses_W_N_s[island[k]] = same->impulses_W[k];
        }
        for (std::size_t b = 0; b < in.members.size(); ++b) velocities[in.members[b]] = same->after[b];
        result.kkt_residual_m_s = std::max(result.kkt_residual_m_s, same->summary.kkt_residual_m_s);
        result.infeasible |= same->summary.infeasible;
        result.iterative_islands += same->summary.iterative_islands;
        continue;
      }
    }
    const bool exact = options.kind == ContactSolverKind::kExact && n <= options.max_exact_rows;
    const int too_large = options.kind == ContactSolverKind::kExact && !exact ? 1 : 0;
    result.iterative_islands += too_large;
    const IslandAnswer answer = exact ? solve_island_exact(inertia, velocities, rows, in, options, earlier)
                                      : solve_island_iterative(inertia, velocities, rows, in, options, earlier);
    result.iterations += answer.iterations;
    for (int k = 0; k < n; ++k) {
      const ContactRow& row = rows[island[k]];
      result.normal_impulses_N_s[island[k]] = answer.lambda[k];
      Eigen::Vector3d impulse = answer.lambda[k] * row.normal_W;
      if (row.friction > 0 && answer.friction.f1.size() == static_cast<std::size_t>(n)) {
        Eigen::Vector3d t1, t2;
        tangents(row.normal_W, t1, t2);
        impulse += answer.friction.f1[k] * t1 + answer.friction.f2[k] * t2;
      }
      result.impulses_W_N_s[island[k]] = impulse;
    }
    result.kkt_residual_m_s = std::max(result.kkt_residual_m_s, answer.residual_m_s);
    result.infeasible |= answer.infeasible;
    if (remember) {
      for (int k = 0; k < n; ++k) {
        key.impulses.push_back(answer.lambda[k]);
        key.impulses_W.push_back(result.impulses_W_N_s[island[k]]);
      }
      for (const int body : in.members) key.after.push_back(velocities[body]);
      key.summary.kkt_residual_m_s = answer.residual_m_s;
      key.summary.infeasible = answer.infeasible;
      key.summary.iterative_islands = too_large;
      memo->by_first_body[key.bodies.front()].push_back(memo->islands.size());
      memo->islands.push_back(std::move(key));
    }
  }
  return result;
}

}  // namespace arphys::dynamics

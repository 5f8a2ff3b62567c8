#pragma once
// Contact dynamics by Gauss's principle of least constraint (docs/method.md section 2), at
// the velocity level of one time step: the new velocities are the admissible ones
// closest to the unconstrained ones in the kinetic metric,
//   u+ = argmin 1/2 (u - u*)^T M (u - u*)   subject to   J u >= beta,
// J the contact-normal rows. The same problem, with beta from the restitution law,
// is the impulse of an impact. Solved on its dual (lambda >= 0: the contact impulses),
// exactly by an active-set method (Lawson-Hanson) with a KKT residual check, or
// approximately by projected Gauss-Seidel, which also carries Coulomb friction.
#include <map>
#include <vector>

#include <Eigen/Core>

namespace arphys::dynamics {

struct BodyVelocity {
  Eigen::Vector3d v_WBcm_m_s = Eigen::Vector3d::Zero();  // centre of mass
  Eigen::Vector3d w_WB_rad_s = Eigen::Vector3d::Zero();
};

struct BodyInertia {
  double inverse_mass_1_kg = 0;
  Eigen::Matrix3d inverse_inertia_W = Eigen::Matrix3d::Zero();
  Eigen::Vector3d com_W = Eigen::Vector3d::Zero();
};

struct ContactRow {
  int body_a = -1, body_b = -1;  // indices of dynamic bodies in the solve; -1: not dynamic
  Eigen::Vector3d point_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal_W = Eigen::Vector3d::UnitZ();  // unit, from a to b
  // After the solve: n . (v_b(p) - v_a(p)) >= min_normal_velocity, where the non-dynamic
  // bodies contribute known_normal_velocity to that relative velocity.
  double min_normal_velocity_m_s = 0;
  double known_normal_velocity_m_s = 0;
  // The non-dynamic bodies' part of the tangential relative velocity v_b(p) - v_a(p) (world
  // frame, normal to normal_W): the slip friction acts against when the dynamic bodies'
  // own velocities are zero (a bunny on a tracked tray is carried along).
  Eigen::Vector3d known_tangent_velocity_W_m_s = Eigen::Vector3d::Zero();
  double friction = 0;  // Coulomb coefficient; 0: frictionless
  // A hint, not a constraint: the same contact pushed in the caller's previous solve.
  // The exact solver starts its active set from such rows (a pile's contacts between
  // boxes falling together are not violated by the unconstrained motion, and were
  // otherwise found one per iteration: about fifty per solve in a 1000-box pile).
  bool pushed_before = false;
  // The same contact's impulse (normal and friction, world frame) in the caller's previous
  // step, scaled to this solve: where the iterative solver and the exact solver's friction
  // sweeps start from (warm start). The exact normal solve does not need it: its answer does
  // not depend on where it starts.
  Eigen::Vector3d warm_impulse_W_N_s = Eigen::Vector3d::Zero();
};

enum class ContactSolverKind { kExact, kProjectedGaussSeidel };

struct ContactSolverOptions {
  ContactSolverKind kind = ContactSolverKind::kExact;
  int iterations = 50;  // projected Gauss-Seidel sweeps (and friction sweeps after an exact solve)
  // ... unless no contact velocity moved more than this in a sweep (metres per second):
  // further sweeps change nothing a step can show (a micrometre per second is a
  // nanometre per millisecond step), and a frictional pile's columns spent a sixth of
  // their time on them.
  double sweep_tolerance_m_s = 1e-6;
  // With friction the exact solver alternates exact normals and friction sweeps (three
  // normal solves, two rounds of sweeps). The first round's friction is provisional: the
  // normals it is bounded by still move by far more than sweep_tolerance_m_s before the
  // last round. So it gets at most this many sweeps, the last round `iterations`. (All 50
  // in both: a settled frictional 1000-box pile spent a fifth more time per step, with the
  // same exact slide and rest on a frictional incline.)
  int provisional_friction_sweeps = 5;
  // Islands with more contact rows than this are solved iteratively even under kExact
  // (counted in ContactSolveResult::iterative_islands; their KKT residual is reported):
  // the dense active-set solve costs about rows^3 per factorisation and a pile of a
  // thousand boxes leaning on each other (thousands of rows) takes minutes for one step.
  int max_exact_rows = 600;
};

struct ContactSolveResult {
  std::vector<double> normal_impulses_N_s;  // per row
  std::vector<Eigen::Vector3d> impulses_W_N_s;  // per row: normal and friction, world frame
  // Largest violation of the KKT conditions: a constraint broken, or a pushing contact
  // that is not exactly at its bound, in m/s. 0 for an exact solve up to rounding.
  double kkt_residual_m_s = 0;
  int iterations = 0;
  // The constraints contradict each other (a body squeezed between non-dynamic ones):
  // solved again with the contradictory rows' push-apart demands dropped (then every
  // row's, then the non-dynamic bodies' approach too), so nothing is launched and no
  // body falls through its other supports.
  bool infeasible = false;
  int iterative_islands = 0;  // islands over max_exact_rows, solved iteratively
};

// Islands solved before, by content: a caller that solves again with a few rows added
// (an impact found by the CCD) re-solves only the islands those rows touch. Valid while
// the bodies' inertia (their poses) is unchanged; bodies are named by the caller's keys
// (solve_contacts' body_keys), so solves over different subsets of bodies share it.
// An island solved iteratively again with rows added starts from its earlier answer.
struct SolvedIslands {
  struct Island {
    std::vector<ContactRow> rows;  // bodies as keys
    std::vector<int> bodies;       // keys, in order of first appearance in rows
    std::vector<BodyVelocity> before, after;
    std::vector<double> impulses;
    std::vector<Eigen::Vector3d> impulses_W;
    ContactSolveResult summary;  // its kkt_residual_m_s, infeasible and iterative_islands only
  };
  std::vector<Island> islands;
  std::map<int, std::vector<std::size_t>> by_first_body;  // islands by their first body's key
  int reused = 0;  // islands answered from here
};

// Solves for `velocities` (in: unconstrained u*, out: u+). Independent groups of
// bodies (islands) are solved separately. With `memo` (and body_keys: a key per body
// of `velocities`), an island identical to one solved before (rows and velocities) takes
// its answer, and every island of 16 rows or more that is solved is added.
ContactSolveResult solve_contacts(const std::vector<BodyInertia>& inertia, std::vector<BodyVelocity>& velocities,
                                  const std::vector<ContactRow>& rows, const ContactSolverOptions& options,
                                  SolvedIslands* memo = nullptr, const std::vector<int>* body_keys = nullptr);

}  // namespace arphys::dynamics

// The contact solver's island memo: a re-solve with a row added re-solves only the island
// the row touches, and gives bit for bit what a solve without the memo gives.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <stdexcept>

#include "simulator/dynamics/contact_solver.hpp"

namespace arphys::dynamics {
namespace {

BodyInertia unit_box(const Eigen::Vector3d& com_W) {
  BodyInertia body;
  body.inverse_mass_1_kg = 1.0;
  body.inverse_inertia_W = Eigen::Matrix3d::Identity() * (1.0 / 0.00667);  // 1 kg, 0.2 m cube
  body.com_W = com_W;
  return body;
}

// A corner of the body on the ground (non-dynamic, below it): no approach.
ContactRow on_ground(int body, const Eigen::Vector3d& point_W) {
  ContactRow row;
  row.body_b = body;
  row.point_W = point_W;
  row.normal_W = Eigen::Vector3d::UnitZ();
  return row;
}

TEST(SolvedIslands, AnAddedRowResolvesOnlyItsIslandAndAnswersAsAFreshSolve) {
  const std::vector<BodyInertia> inertia{unit_box({0, 0, 0.1}), unit_box({1, 0, 0.1})};
  std::vector<BodyVelocity> falling(2);
  falling[0].v_WBcm_m_s = {0.3, 0, -1};
  falling[1].v_WBcm_m_s = {-0.2, 0.1, -2};
  falling[1].w_WB_rad_s = {0, 1, 0};
  // 16 points under each box (islands that small are not remembered: re-solving them is as cheap).
  std::vector<ContactRow> rows;
  for (int body = 0; body < 2; ++body)
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) rows.push_back(on_ground(body, {body - 0.1 + 0.2 * i / 3, -0.1 + 0.2 * j / 3, 0}));
  const std::vector<int> keys{10, 11};
  SolvedIslands memo;
  std::vector<BodyVelocity> u = falling;
  solve_contacts(inertia, u, rows, {}, &memo, &keys);
  EXPECT_EQ(memo.islands.size(), 2u);
  EXPECT_EQ(memo.reused, 0);

  // A wall on body 1's -x side (the CCD found it): body 0's island is unchanged.
  ContactRow wall;
  wall.body_b = 1;
  wall.point_W = {0.9, 0, 0.1};
  wall.normal_W = Eigen::Vector3d::UnitX();
  rows.push_back(wall);
  std::vector<BodyVelocity> with_memo = falling, without = falling;
  const ContactSolveResult a = solve_contacts(inertia, with_memo, rows, {}, &memo, &keys);
  const ContactSolveResult b = solve_contacts(inertia, without, rows, {});
  EXPECT_EQ(memo.reused, 1);
  for (int k = 0; k < 2; ++k) {
    EXPECT_EQ(with_memo[k].v_WBcm_m_s, without[k].v_WBcm_m_s) << "body " << k;
    EXPECT_EQ(with_memo[k].w_WB_rad_s, without[k].w_WB_rad_s) << "body " << k;
  }
  EXPECT_EQ(a.normal_impulses_N_s, b.normal_impulses_N_s);
  EXPECT_GE(with_memo[1].v_WBcm_m_s.x(), -1e-12);  // the wall holds
  EXPECT_NEAR(with_memo[0].v_WBcm_m_s.x(), 0.3, 1e-12);  // frictionless ground: body 0 slides on

  // Body 0 starting a hair faster is another island: solved, not taken from the memo.
  std::vector<BodyVelocity> faster = falling;
  faster[0].v_WBcm_m_s.z() -= 1e-12;
  solve_contacts(inertia, faster, rows, {}, &memo, &keys);
  EXPECT_EQ(memo.reused, 2);  // body 1's island (with the wall) again, not body 0's

  const std::vector<int> too_few{10};
  EXPECT_THROW(solve_contacts(inertia, u, rows, {}, &memo, &too_few), std::invalid_argument);
}

// An island over the dense threshold (a row of 60 boxes on the ground, closing on each
// other: 60 x 4 ground rows and 59 x 4 side rows) is solved exactly through the sparse
// factorisation: KKT residual at rounding level, no penetrating velocity, and the
// frictionless ground leaves the row's x momentum as it was.
TEST(ContactSolver, LargeIslandIsSolvedExactly) {
  const int boxes = 60;
  std::vector<BodyInertia> inertia;
  std::vector<BodyVelocity> u(boxes);
  std::vector<ContactRow> rows;
  double momentum_x = 0;
  for (int k = 0; k < boxes; ++k) {
    const double x = 0.2 * k;
    inertia.push_back(unit_box({x, 0, 0.1}));
    u[k].v_WBcm_m_s = {k % 2 == 0 ? 0.5 : -0.5, 0, -0.01 * (k % 7)};
    u[k].w_WB_rad_s = {0.1 * (k % 3), -0.05 * (k % 5), 0};
    momentum_x += u[k].v_WBcm_m_s.x();
    for (const double dy : {-0.1, 0.1})
      for (const double dx : {-0.1, 0.1}) rows.push_back(on_ground(k, {x + dx, dy, 0}));
    if (k + 1 < boxes)
      for (const double dy : {-0.1, 0.1})
        for (const double z : {0.0, 0.2}) {
          ContactRow side;
          side.body_a = k;
          side.body_b = k + 1;
          side.point_W = {x + 0.1, dy, z};
          side.normal_W = Eigen::Vector3d::UnitX();
          rows.push_back(side);
        }
  }
  ASSERT_GT(rows.size(), 400u);
  const ContactSolveResult result = solve_contacts(inertia, u, rows, {});
  EXPECT_EQ(result.iterative_islands, 0);
  EXPECT_FALSE(result.infeasible);
  EXPECT_LE(result.kkt_residual_m_s, 1e-9);
  double after_x = 0;
  for (int k = 0; k < boxes; ++k) after_x += u[k].v_WBcm_m_s.x();
  EXPECT_NEAR(after_x, momentum_x, 1e-9);
  for (const ContactRow& row : rows) {
    const auto point_velocity = [&](int body) -> Eigen::Vector3d {
      return u[body].v_WBcm_m_s + u[body].w_WB_rad_s.cross(row.point_W - inertia[body].com_W);
    };
    Eigen::Vector3d relative = point_velocity(row.body_b);
    if (row.body_a >= 0) relative -= point_velocity(row.body_a);
    EXPECT_GE(row.normal_W.dot(relative), -1e-9);
  }
}

// Box 0 is pressed into the ground by a static body overlapping it (its rows demand it
// move down at 5 cm/s, the ground's that it not move down): a contradiction. Box 1, beside
// it in the same island, must leave it at 0.1 m/s (a bounce). The solve is reported
// infeasible; box 0 neither sinks nor is launched, and box 1 still leaves: only the
// contradictory rows lose their push-apart demands. (Before, the relaxed bounds had the
// wrong sign and the island got no impulses at all: box 0 fell into the ground and box 1
// stayed.)
TEST(ContactSolver, ASqueezedBodyStaysOnItsSupportAndTheRestOfItsIslandIsSolved) {
  const double g_h = 9.81e-3;  // gravity over a 1 ms step
  const std::vector<BodyInertia> inertia{unit_box({0, 0, 0.1}), unit_box({0.2, 0, 0.1})};
  std::vector<BodyVelocity> u(2);
  u[0].v_WBcm_m_s = {0, 0, -g_h};
  u[1].v_WBcm_m_s = {0, 0, -g_h};
  std::vector<ContactRow> rows;
  for (int body = 0; body < 2; ++body)
    for (const double dx : {-0.1, 0.1})
      for (const double dy : {-0.1, 0.1}) rows.push_back(on_ground(body, {0.2 * body + dx, dy, 0}));
  for (const double dx : {-0.1, 0.1})
    for (const double dy : {-0.1, 0.1}) {
      ContactRow press;  // from the static press (above) to box 0: down
      press.body_b = 0;
      press.point_W = {dx, dy, 0.2};
      press.normal_W = -Eigen::Vector3d::UnitZ();
      press.min_normal_velocity_m_s = 0.05;
      rows.push_back(press);
    }
  for (const double dy : {-0.1, 0.1}) {
    ContactRow side;  // box 0 to box 1 along x, to part at 0.1 m/s
    side.body_a = 0;
    side.body_b = 1;
    side.point_W = {0.1, dy, 0.1};
    side.normal_W = Eigen::Vector3d::UnitX();
    side.min_normal_velocity_m_s = 0.1;
    rows.push_back(side);
  }
  const ContactSolveResult result = solve_contacts(inertia, u, rows, {});
  EXPECT_TRUE(result.infeasible);
  for (int body = 0; body < 2; ++body) {
    ASSERT_TRUE(u[body].v_WBcm_m_s.allFinite() && u[body].w_WB_rad_s.allFinite());
    EXPECT_LT(u[body].v_WBcm_m_s.norm(), 1.0) << "body " << body << " launched";
  }
  EXPECT_NEAR(u[0].v_WBcm_m_s.z(), 0.0, 1e-9);   // neither into the ground nor up
  EXPECT_NEAR(u[0].w_WB_rad_s.norm(), 0.0, 1e-9);
  EXPECT_GE(u[1].v_WBcm_m_s.x() - u[0].v_WBcm_m_s.x(), 0.1 - 1e-9);  // box 1's own demand holds
  EXPECT_NEAR(u[0].v_WBcm_m_s.x() + u[1].v_WBcm_m_s.x(), 0.0, 1e-9);  // frictionless ground: x momentum kept
}

// A stack of three boxes at rest falls as one under gravity: the contacts between boxes
// are not violated by the unconstrained motion, only the ground's are. The exact solver
// finds the others one per iteration, unless told which pushed in the previous step.
TEST(ContactSolver, RowsThatPushedBeforeStartTheActiveSetAndChangeNoAnswer) {
  const double g_h = 9.81e-3;  // gravity over a 1 ms step
  std::vector<BodyInertia> inertia;
  std::vector<BodyVelocity> u(3);
  std::vector<ContactRow> rows;
  for (int k = 0; k < 3; ++k) {
    inertia.push_back(unit_box({0, 0, 0.1 + 0.2 * k}));
    u[k].v_WBcm_m_s = {0, 0, -g_h};
    for (const double dy : {-0.1, 0.1})
      for (const double dx : {-0.1, 0.1}) {
        ContactRow row = on_ground(k, {dx, dy, 0.2 * k});
        row.body_a = k - 1;  // the box below, or the ground
        rows.push_back(row);
      }
  }
  // Solves cold, marks the rows that pushed, solves again from them: the boxes are held
  // and both answers agree.
  const auto cold_then_hinted = [&](const char* what) {
    for (ContactRow& row : rows) row.pushed_before = false;
    std::vector<BodyVelocity> cold_u = u, hinted_u = u;
    const ContactSolveResult cold = solve_contacts(inertia, cold_u, rows, {});
    for (std::size_t r = 0; r < rows.size(); ++r) rows[r].pushed_before = cold.normal_impulses_N_s[r] > 0;
    const ContactSolveResult hinted = solve_contacts(inertia, hinted_u, rows, {});
    for (int k = 0; k < 3; ++k) {
      EXPECT_LE(cold_u[k].v_WBcm_m_s.norm() + cold_u[k].w_WB_rad_s.norm(), 1e-12) << what << ": box " << k << " should be held";
      EXPECT_LE((hinted_u[k].v_WBcm_m_s - cold_u[k].v_WBcm_m_s).norm(), 1e-12) << what;
      EXPECT_LE((hinted_u[k].w_WB_rad_s - cold_u[k].w_WB_rad_s).norm(), 1e-12) << what;
    }
    return std::make_pair(cold, hinted);
  };
  const auto [cold, hinted] = cold_then_hinted("frictionless");
  EXPECT_LE(hinted.kkt_residual_m_s, 1e-12);
  // Cold: the four ground rows warm-start, then the rows between boxes join one per
  // iteration (two per interface here: the symmetric stack needs no more); hinted: the
  // first check finds nothing to add.
  EXPECT_GE(cold.iterations, 5);
  EXPECT_EQ(hinted.iterations, 1);

  // With friction the islands start only from the hinted rows (never from every violated
  // one, which spreads impulses over redundant points): still the same answer, in fewer
  // iterations (the three staggered rounds each start from the last one's pushing rows).
  for (ContactRow& row : rows) row.friction = 0.5;
  const auto [cold_friction, hinted_friction] = cold_then_hinted("friction 0.5");
  std::printf("frictional stack: %d iterations cold, %d hinted\n", cold_friction.iterations, hinted_friction.iterations);
  EXPECT_LT(hinted_friction.iterations, cold_friction.iterations);
}

// Ten boxes stacked in a column on the ground, four corner rows under each (on the box
// below, or the ground; friction mu),
// box k starting at velocity v(k), keyed 100 + k for the memo.
struct Column {
  std::vector<BodyInertia> inertia;
  std::vector<BodyVelocity> falling;
  std::vector<ContactRow> rows;
  std::vector<int> keys;
};
template <typename Velocity>
Column column_of_ten(Velocity v, double mu) {
  Column c;
  for (int k = 0; k < 10; ++k) {
    c.inertia.push_back(unit_box({0, 0, 0.1 + 0.2 * k}));
    c.keys.push_back(100 + k);
    BodyVelocity u;
    u.v_WBcm_m_s = v(k);
    c.falling.push_back(u);
    for (const double dy : {-0.1, 0.1})
      for (const double dx : {-0.1, 0.1}) {
        ContactRow row = on_ground(k, {dx, dy, 0.2 * k});
        row.body_a = k - 1;
        row.friction = mu;
        c.rows.push_back(row);
      }
  }
  return c;
}

// The iterative solver starts from the rows' warm impulses: given the exact answer it
// returns it at once; from nothing, a column of ten boxes takes more sweeps than it is
// allowed. The impulses come back whole (normal and friction) for the next warm start.
TEST(ContactSolver, TheIterativeSolverStartsFromTheWarmImpulses) {
  const int boxes = 10;
  // Sliding along x, with a 1 ms step of gravity.
  auto [inertia, u, rows, keys] = column_of_ten([](int) { return Eigen::Vector3d(0.003, 0, -9.81e-3); }, 0.0);
  rows[0].friction = 0.5;  // one frictional corner on the ground: the bottom box slows
  std::vector<BodyVelocity> exact_u = u;
  const ContactSolveResult exact = solve_contacts(inertia, exact_u, rows, {});
  ASSERT_LE(exact.kkt_residual_m_s, 1e-12);

  ContactSolverOptions iterative;
  iterative.kind = ContactSolverKind::kProjectedGaussSeidel;
  std::vector<BodyVelocity> cold_u = u;
  const ContactSolveResult cold = solve_contacts(inertia, cold_u, rows, iterative);
  std::vector<ContactRow> warm_rows = rows;
  for (std::size_t r = 0; r < rows.size(); ++r) warm_rows[r].warm_impulse_W_N_s = cold.impulses_W_N_s[r];
  std::vector<BodyVelocity> warm_u = u;
  const ContactSolveResult warm = solve_contacts(inertia, warm_u, warm_rows, iterative);
  std::printf("column of ten, iterative: residual %.2g m/s in %d sweeps cold, %.2g m/s in %d sweeps warm\n",
              cold.kkt_residual_m_s, cold.iterations, warm.kkt_residual_m_s, warm.iterations);
  EXPECT_EQ(cold.iterations, iterative.iterations);  // ran out of sweeps
  EXPECT_GT(cold.kkt_residual_m_s, 1e-5);
  EXPECT_LT(warm.kkt_residual_m_s, 0.5 * cold.kkt_residual_m_s);  // (a second solve goes on from the first)
  // Warm-started from the exact answer (frictionless: the exact solve's friction is a
  // staggered one), there is nothing left to sweep.
  std::vector<ContactRow> settled_rows = rows;
  settled_rows[0].friction = 0;
  std::vector<BodyVelocity> frictionless_u = u, settled_u = u;
  const ContactSolveResult frictionless = solve_contacts(inertia, frictionless_u, settled_rows, {});
  for (std::size_t r = 0; r < rows.size(); ++r) settled_rows[r].warm_impulse_W_N_s = frictionless.impulses_W_N_s[r];
  const ContactSolveResult settled = solve_contacts(inertia, settled_u, settled_rows, iterative);
  EXPECT_LE(settled.iterations, 1);
  EXPECT_LE(settled.kkt_residual_m_s, 1e-9);
  for (int k = 0; k < boxes; ++k) EXPECT_LE((settled_u[k].v_WBcm_m_s - frictionless_u[k].v_WBcm_m_s).norm(), 1e-9);
  // The impulses reported: the normal along the normal, the friction against the slide.
  EXPECT_NEAR(exact.impulses_W_N_s[0].dot(rows[0].normal_W), exact.normal_impulses_N_s[0], 1e-15);
  EXPECT_LT(exact.impulses_W_N_s[0].x(), 0);
  EXPECT_LE(-exact.impulses_W_N_s[0].x(), 0.5 * exact.normal_impulses_N_s[0] * (1 + 1e-12));
}

// An island too large for the exact solver, re-solved with a row added (the CCD found
// an impact), goes on from its earlier solve's impulses, not from last step's again.
TEST(SolvedIslands, AnIterativeReSolveGoesOnFromTheIslandsEarlierSolve) {
  const int boxes = 10;
  auto [inertia, falling, rows, keys] = column_of_ten([](int) { return Eigen::Vector3d(0.003, 0, -9.81e-3); }, 0.0);
  ContactSolverOptions options;  // exact, but for islands over max_exact_rows: as in a pile
  options.max_exact_rows = 8;
  SolvedIslands memo;
  std::vector<BodyVelocity> first_u = falling;
  const ContactSolveResult first = solve_contacts(inertia, first_u, rows, options, &memo, &keys);
  ASSERT_EQ(first.iterative_islands, 1);
  ASSERT_EQ(first.iterations, options.iterations);  // ran out of sweeps
  ASSERT_GT(first.kkt_residual_m_s, 1e-5);

  // A wall beside the top box, which slides away from it: the wall pushes nothing.
  ContactRow wall;
  wall.body_b = boxes - 1;
  wall.point_W = {-0.1, 0, 0.2 * boxes - 0.1};
  wall.normal_W = Eigen::Vector3d::UnitX();
  rows.push_back(wall);
  std::vector<BodyVelocity> with_memo = falling, without = falling;
  const ContactSolveResult resolved = solve_contacts(inertia, with_memo, rows, options, &memo, &keys);
  const ContactSolveResult afresh = solve_contacts(inertia, without, rows, options);
  std::printf("column of ten re-solved with a wall: residual %.2g m/s from the earlier solve, %.2g afresh (first %.2g)\n",
              resolved.kkt_residual_m_s, afresh.kkt_residual_m_s, first.kkt_residual_m_s);
  EXPECT_EQ(memo.reused, 0);  // not the same island: solved again
  EXPECT_NEAR(afresh.kkt_residual_m_s, first.kkt_residual_m_s, 0.01 * first.kkt_residual_m_s);
  EXPECT_LT(resolved.kkt_residual_m_s, 0.5 * first.kkt_residual_m_s);
  EXPECT_EQ(resolved.normal_impulses_N_s.back(), 0.0);
}

// An exact frictional island re-solved with a row added starts from the rows that pushed
// in its earlier solve: fewer iterations, the constraints as exact, and the motion as
// near a solve with converged friction sweeps as a solve afresh is.
TEST(SolvedIslands, AnExactReSolveStartsFromTheIslandsEarlierSolve) {
  const int boxes = 10;
  auto [inertia, falling, rows, keys] = column_of_ten(  // sliding on each other
      [](int k) { return Eigen::Vector3d(0.02 * ((k + 1) % 3) - 0.01, 0.01, -9.81e-3); }, 0.5);
  SolvedIslands memo;
  std::vector<BodyVelocity> first_u = falling;
  solve_contacts(inertia, first_u, rows, {}, &memo, &keys);
  ContactRow wall;  // beside the top box, which it stops from sliding into it
  wall.body_b = boxes - 1;
  wall.point_W = {0.1, 0, 0.2 * boxes - 0.1};
  wall.normal_W = -Eigen::Vector3d::UnitX();
  rows.push_back(wall);
  std::vector<BodyVelocity> with_memo = falling, without = falling;
  const ContactSolveResult resolved = solve_contacts(inertia, with_memo, rows, {}, &memo, &keys);
  const ContactSolveResult afresh = solve_contacts(inertia, without, rows, {});
  ContactSolverOptions converged;
  converged.iterations = converged.provisional_friction_sweeps = 5000;
  converged.sweep_tolerance_m_s = 0;
  std::vector<BodyVelocity> reference = falling;
  solve_contacts(inertia, reference, rows, converged);
  double warm_off = 0, cold_off = 0;
  for (int k = 0; k < boxes; ++k) {
    warm_off = std::max(warm_off, (with_memo[k].v_WBcm_m_s - reference[k].v_WBcm_m_s).norm());
    cold_off = std::max(cold_off, (without[k].v_WBcm_m_s - reference[k].v_WBcm_m_s).norm());
  }
  std::printf(
      "frictional column of ten re-solved with a wall: %d iterations from the earlier solve, %d afresh; %.3g / %.3g "
      "m/s from converged sweeps\n",
      resolved.iterations, afresh.iterations, warm_off, cold_off);
  EXPECT_EQ(memo.reused, 0);
  EXPECT_LT(resolved.iterations, afresh.iterations);
  EXPECT_LE(resolved.kkt_residual_m_s, 1e-9);
  EXPECT_GT(resolved.normal_impulses_N_s.back(), 0.0);  // the wall pushes
  EXPECT_LE(warm_off, 1.5 * cold_off + 1e-6);
}

// Friction sweeps stop once no row's velocity moves more than sweep_tolerance_m_s in a
// sweep: fewer sweeps, and the answer within a few times that of sweeping to the end.
TEST(ContactSolver, FrictionSweepsStopWhenVelocitiesSettle) {
  const int boxes = 10;
  std::vector<BodyInertia> inertia;
  std::vector<BodyVelocity> u(boxes);
  std::vector<ContactRow> rows;
  for (int k = 0; k < boxes; ++k) {
    const double x = 0.2 * k;
    inertia.push_back(unit_box({x, 0, 0.1}));
    u[k].v_WBcm_m_s = {k % 3 == 0 ? 0.02 : -0.01, 0.005 * (k % 2), -9.81e-3};  // sliding and sticking boxes
    for (const double dy : {-0.1, 0.1})
      for (const double dx : {-0.1, 0.1}) {
        ContactRow row = on_ground(k, {x + dx, dy, 0});
        row.friction = 0.5;
        rows.push_back(row);
      }
    if (k + 1 < boxes)
      for (const double dy : {-0.1, 0.1}) {
        ContactRow side;
        side.body_a = k;
        side.body_b = k + 1;
        side.point_W = {x + 0.1, dy, 0.1};
        side.normal_W = Eigen::Vector3d::UnitX();
        rows.push_back(side);
      }
  }
  ContactSolverOptions to_the_end;
  to_the_end.sweep_tolerance_m_s = 0;
  to_the_end.iterations = 500;
  std::vector<BodyVelocity> settled_u = u, full_u = u;
  const ContactSolveResult settled = solve_contacts(inertia, settled_u, rows, {});
  const ContactSolveResult full = solve_contacts(inertia, full_u, rows, to_the_end);
  std::printf("friction sweeps: %d iterations with the tolerance, %d without\n", settled.iterations, full.iterations);
  EXPECT_LT(settled.iterations, full.iterations);
  for (int k = 0; k < boxes; ++k) {
    EXPECT_LE((settled_u[k].v_WBcm_m_s - full_u[k].v_WBcm_m_s).norm(), 1e-5) << "box " << k;
    EXPECT_NEAR(settled_u[k].v_WBcm_m_s.z(), 0, 1e-9) << "box " << k;  // the normals stay exact
  }
}

}  // namespace
}  // namespace arphys::dynamics

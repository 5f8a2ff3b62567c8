// The solve stage of a step: rows from contacts, the constrained solve, the launch guard.
#include "simulator/dynamics/step_solve.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "simulator/dynamics/disjoint_sets.hpp"
#include "simulator/dynamics/step_helpers.hpp"

namespace arphys::dynamics {

using step_helpers::combined_friction;
using step_helpers::row_point;
using step_helpers::slot_of;

namespace {

// The angular velocity after h_s of torque-free motion.
Eigen::Vector3d gyroscopic_step(const Eigen::Matrix3d& I_W, const Eigen::Vector3d& w_WB_rad_s, double h_s) {
  // Implicit midpoint on I (w' - w) + h m x I m = 0, m = (w + w') / 2, by Newton from
  // w' = w: with the inertia held over the step it keeps the kinetic energy and the
  // angular momentum's size (both quadratic invariants). The explicit step
  // w' = w - h I^-1 (w x I w) gains energy (a spin near the intermediate axis runs away);
  // backward Euler is stable but loses angular momentum (docs/decisions/0011).
  auto skew = [](const Eigen::Vector3d& a) {
    Eigen::Matrix3d S;
    S << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
    return S;
  };
  Eigen::Vector3d w = w_WB_rad_s;
  for (int iteration = 0; iteration < 6; ++iteration) {
    const Eigen::Vector3d m = 0.5 * (w_WB_rad_s + w);
    const Eigen::Vector3d Im = I_W * m;
    const Eigen::Vector3d g = I_W * (w - w_WB_rad_s) + h_s * m.cross(Im);
    const Eigen::Matrix3d J = I_W + 0.5 * h_s * (skew(m) * I_W - skew(Im));
    const Eigen::Vector3d step = J.partialPivLu().solve(g);
    if (!step.allFinite()) return w_WB_rad_s;
    w -= step;
    if (step.norm() <= 1e-14 * (1 + w.norm())) break;
  }
  return w;
}

}  // namespace

std::vector<Contact> impact_contacts(const std::vector<BodyState>& state, const ImpactMap& impacts) {
  // Where the CCD found pairs meeting within the step: the material points that meet
  // (fixed in each body at the time of impact) and the normal there, at the current poses.
  std::vector<Contact> contacts;
  for (const auto& [pair, hits] : impacts) {
    const BodyState& a = state.at(pair.first);
    const BodyState& b = state.at(pair.second);
    for (const ImpactPoint& hit : hits) {
      collision::ManifoldPoint p;
      p.point_A_W = a.X_WB * hit.point_A_B;
      p.point_B_W = b.X_WB * hit.point_B_B;
      p.normal_W = a.X_WB.linear() * hit.normal_A_B;
      p.distance_m = p.normal_W.dot(p.point_B_W - p.point_A_W);
      contacts.push_back({pair.first, pair.second, p, 0.0, hit.min_normal_velocity_m_s});
    }
  }
  return contacts;
}

SolveSetup prepare_solve(const WorldModel& model, const std::vector<BodyState>& state, double h, double force_h,
                         const std::vector<int>& participants, const std::vector<Contact>& resting) {
  step_helpers::require_model("prepare_solve", model, state);
  step_helpers::require_participants("prepare_solve", participants, state.size());
  SolveSetup setup;
  setup.h = h;
  setup.warm_h_s = force_h > 0 ? h : 0.0;
  setup.unknown_of_slot.assign(participants.size(), -1);
  for (std::size_t s = 0; s < participants.size(); ++s) {
    const BodyModel& body = model.bodies[participants[s]];
    const BodyState& now = state[participants[s]];
    if (!moves(body, now)) continue;
    setup.unknown_of_slot[s] = static_cast<int>(setup.u_unconstrained.size());
    setup.slot_of_unknown.push_back(static_cast<int>(s));
    setup.body_of_unknown.push_back(participants[s]);
    BodyInertia in;
    in.inverse_mass_1_kg = 1.0 / body.mass.mass_kg;
    in.inverse_inertia_W = inverse_inertia_W(body, now);
    in.com_W = com_W(body, now);
    setup.inertia.push_back(in);
    // Unconstrained: gravity, and the gyroscopic term I dw/dt = -w x I w, implicitly.
    BodyVelocity v;
    v.v_WBcm_m_s = now.v_WBcm_m_s + force_h * model.options.gravity_m_s2;
    v.w_WB_rad_s = gyroscopic_step(inertia_W(body, now), now.w_WB_rad_s, force_h);
    setup.u_unconstrained.push_back(v);
  }
  setup.resting_rows.reserve(resting.size());
  for (const Contact& c : resting) {
    setup.resting_rows.push_back(contact_row(model, state, c, setup, participants));
    setup.deepest_m = std::max(setup.deepest_m, -c.feature.distance_m);
  }
  return setup;
}

ContactRow contact_row(const WorldModel& model, const std::vector<BodyState>& state, const Contact& c,
                       const SolveSetup& setup, const std::vector<int>& participants) {
  const WorldOptions& options = model.options;
  const auto unknown = [&](int body) {
    const int slot = slot_of(participants, body);
    return slot < 0 ? -1 : setup.unknown_of_slot[slot];
  };
  const double h = setup.h;
  const BodyModel& a = model.bodies.at(c.body_a);
  const BodyModel& b = model.bodies.at(c.body_b);
  const BodyState& sa = state.at(c.body_a);
  const BodyState& sb = state.at(c.body_b);
  ContactRow row;
  row.body_a = unknown(c.body_a);
  row.body_b = unknown(c.body_b);
  row.normal_W = c.feature.normal_W;
  row.point_W = row_point(c.feature);
  // The non-dynamic bodies' point velocities (a dynamic body's are unknowns of the solve).
  const Eigen::Vector3d v_a = moves(a, sa) ? Eigen::Vector3d::Zero() : velocity_of_point(a, sa, row.point_W);
  const Eigen::Vector3d v_b = moves(b, sb) ? Eigen::Vector3d::Zero() : velocity_of_point(b, sb, row.point_W);
  row.known_normal_velocity_m_s = -row.normal_W.dot(v_a) + row.normal_W.dot(v_b);
  const Eigen::Vector3d known_W = v_b - v_a;
  row.known_tangent_velocity_W_m_s = known_W - row.normal_W.dot(known_W) * row.normal_W;
  const double gap = c.feature.distance_m;
  // Close at most to the resting gap within h; undo an overlap, but not violently.
  row.min_normal_velocity_m_s = std::min(-(gap - options.contact_gap_m) / h, options.max_depenetration_speed_m_s);
  // An impact: closing fast enough to bounce and, at that speed, meeting within h.
  // The bounce then happens at the step boundary, as the velocity update of a
  // symplectic Euler step, which keeps an elastic ball's apex.
  const double approach =
      row.normal_W.dot(velocity_of_point(b, sb, row.point_W) - velocity_of_point(a, sa, row.point_W));
  if (approach < -options.restitution_threshold_m_s && -approach * h >= gap - options.contact_gap_m)
    row.min_normal_velocity_m_s =
        std::max(row.min_normal_velocity_m_s, -std::max(a.restitution, b.restitution) * approach);
  row.min_normal_velocity_m_s = std::max(row.min_normal_velocity_m_s, c.min_normal_velocity_m_s);
  row.friction = combined_friction(a, b);
  row.pushed_before = c.pushed_before;
  row.warm_impulse_W_N_s = setup.warm_h_s * c.warm_force_W_N;
  return row;
}

StepSolve solve_step(const WorldModel& model, const std::vector<BodyState>& state, const SolveSetup& setup,
                     const std::vector<int>& participants, const std::vector<Contact>& resting,
                     const ImpactMap& impacts, SolvedIslands* memo) {
  step_helpers::require_model("solve_step", model, state);
  step_helpers::require_size("solve_step", "setup (its participants)", setup.unknown_of_slot.size(),
                             participants.size());
  StepSolve out;
  const std::vector<Contact> meeting = impact_contacts(state, impacts);
  out.solved.reserve(resting.size() + meeting.size());
  out.solved.insert(out.solved.end(), resting.begin(), resting.end());
  out.solved.insert(out.solved.end(), meeting.begin(), meeting.end());
  std::vector<BodyVelocity> u = setup.u_unconstrained;
  std::vector<ContactRow> rows;
  rows.reserve(out.solved.size());
  rows.insert(rows.end(), setup.resting_rows.begin(), setup.resting_rows.end());
  for (const Contact& c : meeting) rows.push_back(contact_row(model, state, c, setup, participants));
  // The resting contacts' overlaps only: a meeting's material points, taken at the start
  // poses, say how they will meet, not that they overlap (a turning pair's can be half a
  // millimetre "deep" there while nothing overlaps at any time).
  out.deepest_resting_m = setup.deepest_m;
  const ContactSolveResult result =
      solve_contacts(setup.inertia, u, rows, model.options.solver, memo, &setup.body_of_unknown);
  out.launches_prevented = guard_launches(model, state, setup, participants, rows, u);
  out.kkt_residual_m_s = result.kkt_residual_m_s;
  out.infeasible = result.infeasible;
  out.iterative_islands = result.iterative_islands;
  out.iterations = result.iterations;
  for (std::size_t k = 0; k < out.solved.size(); ++k) {
    out.solved[k].impulse_N_s = result.normal_impulses_N_s[k];
    out.solved[k].impulse_W_N_s = result.impulses_W_N_s[k];
  }
  out.u.assign(participants.size(), BodyVelocity());
  for (std::size_t k = 0; k < u.size(); ++k) out.u[setup.slot_of_unknown[k]] = u[k];
  return out;
}

int guard_launches(const WorldModel& model, const std::vector<BodyState>& state, const SolveSetup& setup,
                   const std::vector<int>& participants, const std::vector<ContactRow>& rows,
                   std::vector<BodyVelocity>& u) {
  const WorldOptions& options = model.options;
  step_helpers::require_size("guard_launches", "u", u.size(), setup.u_unconstrained.size());
  // The speed a body's energy gives it, sqrt(|v|^2 + w.I.w / m), not its point speed
  // |v| + |w| r: an off-centre impact rightly turns a fall into a spin whose point speed
  // (r the bounding radius about the body origin) is several times the fall's.
  const std::vector<BodyVelocity>& u_unconstrained = setup.u_unconstrained;
  DisjointSets island(static_cast<int>(u.size()));
  const auto root = [&](int k) { return island.find(k); };
  for (const ContactRow& row : rows) {
    if (row.body_a >= 0 && row.body_b >= 0) island.join(row.body_a, row.body_b);
  }
  std::vector<double> radius(u.size(), 0.0), island_speed(u.size(), 0.0);
  for (std::size_t k = 0; k < u.size(); ++k) radius[k] = model.radius_m[participants[setup.slot_of_unknown[k]]];
  const auto point_speed = [&](const BodyVelocity& v, std::size_t k) {
    return v.v_WBcm_m_s.norm() + v.w_WB_rad_s.norm() * radius[k];
  };
  const auto energy_speed = [&](const BodyVelocity& v, std::size_t k) {
    const int i = setup.body_of_unknown[k];
    const double turning =
        v.w_WB_rad_s.dot(inertia_W(model.bodies[i], state[i]) * v.w_WB_rad_s) / model.bodies[i].mass.mass_kg;
    return std::sqrt(v.v_WBcm_m_s.squaredNorm() + std::max(0.0, turning));
  };
  for (std::size_t k = 0; k < u.size(); ++k) {
    const double speed = point_speed(u_unconstrained[k], k);
    if (std::isfinite(speed))
      island_speed[root(static_cast<int>(k))] = std::max(island_speed[root(static_cast<int>(k))], speed);
  }
  for (const ContactRow& row : rows) {
    const int k = row.body_a >= 0 ? row.body_a : row.body_b;
    if (k >= 0 && std::isfinite(row.known_normal_velocity_m_s)) {
      island_speed[root(k)] = std::max(island_speed[root(k)], std::abs(row.known_normal_velocity_m_s));
    }
  }
  int slowed = 0;
  for (std::size_t k = 0; k < u.size(); ++k) {
    // Twice the island's fastest motion bounds one solve, not a sequence of them: a body
    // bumped a little faster every step would still run away. max_body_speed_m_s caps
    // its points' speed absolutely (a desk-scale scene has nothing faster).
    const double bound = 2.0 * island_speed[root(static_cast<int>(k))] + options.max_depenetration_speed_m_s +
                         options.launch_guard_slack_m_s;
    const double energy = energy_speed(u[k], k), speed = point_speed(u[k], k);
    if (std::isfinite(energy) && std::isfinite(speed) && energy <= bound && speed <= options.max_body_speed_m_s)
      continue;
    if (std::isfinite(energy) && std::isfinite(speed)) {
      const double scale = std::min(energy > bound ? bound / energy : 1.0,
                                    speed > options.max_body_speed_m_s ? options.max_body_speed_m_s / speed : 1.0);
      u[k].v_WBcm_m_s *= scale;
      u[k].w_WB_rad_s *= scale;
    } else {
      u[k] = u_unconstrained[k];
    }
    ++slowed;
  }
  return slowed;
}

void tally(const StepSolve& solve, StepReport& report) {
  report.max_penetration_m = std::max(report.max_penetration_m, solve.deepest_resting_m);
  report.kkt_residual_m_s = std::max(report.kkt_residual_m_s, solve.kkt_residual_m_s);
  report.infeasible |= solve.infeasible;
  report.iterative_islands += solve.iterative_islands;
  report.solver_iterations += solve.iterations;
  report.launches_prevented += solve.launches_prevented;
}

}  // namespace arphys::dynamics

// World's bodies and its step: the first pass over everything (contacts, one solve, the
// CCD of its motions), the groups that can meet within the step, and what the step keeps
// for the next. The stages it runs are functions of their own (step_contacts, step_solve,
// step_sweep, step_rounds, step_cut, step_commit); a group's parts are in world_group.cpp,
// sleep in world_sleep.cpp.
#include "simulator/dynamics/world.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

#include "simulator/collision/broad_phase.hpp"
#include "simulator/dynamics/disjoint_sets.hpp"
#include "simulator/dynamics/step_helpers.hpp"
#include "simulator/dynamics/world_internal.hpp"

namespace arphys::dynamics {

using step_helpers::combined_friction;
using step_helpers::meets_inside;
using step_helpers::pairs_of;
using step_helpers::row_point;

World::World(WorldOptions options)
    : model_{(check_world_options(options), std::move(options)), {}, {}}, pool_(model_.options.threads) {}

int World::add_body(RigidBody body) {
  if (!body.X_WB.matrix().allFinite()) throw std::invalid_argument("World::add_body: body '" + body.id + "' has a non-finite pose");
  if (body.is_dynamic()) {
    if (body.shape.type() == collision::Shape::Type::kPlane)
      throw std::invalid_argument("World::add_body: body '" + body.id + "' is a dynamic plane (a plane has no mass)");
    if (!(body.mass.mass_kg > 0) || !std::isfinite(body.mass.mass_kg))
      throw std::invalid_argument("World::add_body: body '" + body.id + "' has mass " + std::to_string(body.mass.mass_kg) +
                                  " kg, expected a positive mass");
    const Eigen::Matrix3d& I = body.mass.inertia_about_com_kg_m2;
    if (!I.allFinite() || !(I.determinant() > 0))
      throw std::invalid_argument("World::add_body: body '" + body.id + "' has a singular inertia");
    if (!body.v_WBcm_m_s.allFinite() || !body.w_WB_rad_s.allFinite())
      throw std::invalid_argument("World::add_body: body '" + body.id + "' has a non-finite velocity");
  }
  if (find(body.id) >= 0) throw std::invalid_argument("World::add_body: duplicate body id '" + body.id + "'");
  model_.radius_m.push_back(body.bounding_radius_m());
  state_.mesh.placed_since_step.push_back(1);
  state_.sleep.placed_to_wake.push_back(0);
  state_.sleep.quiet_s.push_back(0);
  state_.sleep.touching.emplace_back();
  BodyState& added = state_.bodies.emplace_back(std::move(static_cast<BodyState&>(body)));
  added.asleep = false;
  model_.bodies.push_back(std::move(static_cast<BodyModel&>(body)));
  return body_count() - 1;
}

void World::place_body(int index, const geometry::Pose& X_WB) {
  const BodyModel& body = model_.bodies.at(index);
  if (!X_WB.matrix().allFinite()) throw std::invalid_argument("World::place_body: body '" + body.id + "': non-finite pose");
  state_.bodies[index].X_WB = X_WB;
  state_.mesh.placed_since_step.at(index) = 1;
  state_.sleep.placed_to_wake.at(index) = 1;
  wake({index});
}

void World::set_velocity(int index, const Eigen::Vector3d& v_WBcm_m_s, const Eigen::Vector3d& w_WB_rad_s) {
  const BodyModel& body = model_.bodies.at(index);
  if (!body.is_dynamic()) throw std::invalid_argument("World::set_velocity: body '" + body.id + "' is not dynamic");
  if (!v_WBcm_m_s.allFinite() || !w_WB_rad_s.allFinite())
    throw std::invalid_argument("World::set_velocity: body '" + body.id + "': non-finite velocity");
  state_.bodies[index].v_WBcm_m_s = v_WBcm_m_s;
  state_.bodies[index].w_WB_rad_s = w_WB_rad_s;
  wake({index});
}

void World::set_origin_velocity(int index, const Eigen::Vector3d& v_WBo_m_s, const Eigen::Vector3d& w_WB_rad_s) {
  set_velocity(index, com_velocity(model_.bodies.at(index), state_.bodies[index], v_WBo_m_s, w_WB_rad_s), w_WB_rad_s);
}

void World::set_trajectory(int index, KinematicTrajectory trajectory) {
  const BodyModel& body = model_.bodies.at(index);
  if (body.motion != BodyMotion::kKinematic)
    throw std::invalid_argument("World::set_trajectory: body '" + body.id + "' is not kinematic");
  state_.bodies[index].trajectory = std::move(trajectory);
}

void World::remove_body(int index) {
  model_.bodies.erase(model_.bodies.begin() + index);
  model_.radius_m.erase(model_.radius_m.begin() + index);
  state_.bodies.erase(state_.bodies.begin() + index);
  state_.sleep.quiet_s.erase(state_.sleep.quiet_s.begin() + index);
  state_.sleep.placed_to_wake.erase(state_.sleep.placed_to_wake.begin() + index);
  state_.sleep.touching.erase(state_.sleep.touching.begin() + index);
  for (auto& partners : state_.sleep.touching) {
    partners.erase(std::remove(partners.begin(), partners.end(), index), partners.end());
    for (int& j : partners) j -= j > index;
  }
  state_.contacts.clear();
  state_.hints = {};
  state_.held_back_bounces.clear();
  // (Pair indices shift: every body is tested again rather than the pairs renumbered.)
  state_.mesh = {};
  state_.mesh.placed_since_step.assign(model_.bodies.size(), 1);
}

std::vector<RigidBody> World::body_copies() const {
  std::vector<RigidBody> all;
  all.reserve(model_.bodies.size());
  for (int i = 0; i < body_count(); ++i) all.push_back(body_copy(i));
  return all;
}

int World::find(const std::string& id) const {
  for (int i = 0; i < body_count(); ++i)
    if (model_.bodies[i].id == id) return i;
  return -1;
}

void World::set_kinematic_state(const std::vector<int>& participants, double t_s, double h_s) {
  for (int i : participants) {
    const BodyModel& model = model_.bodies[i];
    BodyState& body = state_.bodies[i];
    if (model.motion != BodyMotion::kKinematic || body.trajectory.empty()) continue;
    body.X_WB = body.trajectory.pose_at(t_s);
    if (h_s > 0) {
      // The constant twist that takes it where the trajectory says it is after h (a
      // step can straddle two tracked poses: the instantaneous twist would be wrong).
      const geometry::ScrewMotion screw(body.X_WB, body.trajectory.pose_at(t_s + h_s));
      body.w_WB_rad_s = screw.angular_velocity() / h_s;
      body.v_WBcm_m_s = screw.velocity_of_point(com_W(model, body)) / h_s;
    } else {
      const Twist twist = body.trajectory.twist_at(t_s);
      body.w_WB_rad_s = twist.w_WB_rad_s;
      body.v_WBcm_m_s = twist.velocity_of_point(com_W(model, body), body.X_WB.translation());
    }
  }
}

void World::begin_step_memos() {
  state_.mesh.begin_step();
  state_.hints.pending_bounces = std::move(state_.held_back_bounces);
  state_.held_back_bounces.clear();
  std::stable_sort(state_.hints.pending_bounces.begin(), state_.hints.pending_bounces.end(),
                   [](const ContactHints::Bounce& x, const ContactHints::Bounce& y) { return x.bodies < y.bodies; });
}

World::FirstPass World::first_pass(double dt_s, const std::vector<int>& everyone, StepReport& report) {
  const int n = body_count();
  FirstPass pass;
  pass.resting = gather_contacts(model_, state_.bodies, state_.hints, state_.mesh, pool_, everyone,
                                 state_.contacts.size() + state_.contacts.size() / 4);
  StepSolve first =
      solve_step(model_, state_.bodies, prepare_solve(model_, state_.bodies, dt_s, dt_s, everyone, pass.resting),
                 everyone, pass.resting, {}, &pass.islands);
  tally(first, report);
  pass.u = std::move(first.u);
  pass.solved = std::move(first.solved);
  pass.next = candidate_poses(model_, state_.bodies, everyone, pass.u, state_.time_s, dt_s);
  // Groups: dynamic bodies in contact, or whose swept boxes overlap, may meet within the
  // step; bodies of different groups cannot, so each group is stepped on its own, its
  // events cutting only its own step and re-running only its own CCD. (Stepping them all
  // together made every time of impact in a 1000-box pile re-solve and re-sweep all of it.)
  pass.groups = DisjointSets(n);
  const auto join = [&](int i, int j) {
    if (moving(i) && moving(j)) pass.groups.join(i, j);
  };
  for (const Contact& c : pass.resting) join(c.body_a, c.body_b);
  pass.swept.resize(n);
  for (int i = 0; i < n; ++i) pass.swept[i] = swept_box(state_.bodies[i].X_WB, model_.radius_m[i], pass.next[i]);
  const std::vector<std::pair<int, int>> swept_pairs = collision::overlapping_pairs(pass.swept);
  for (const auto& [i, j] : swept_pairs) join(i, j);
  // The first CCD pass, for everything at once (the same pairs the groups would sweep):
  // most groups meet nothing and just move; only the others are stepped on their own.
  const std::vector<std::pair<int, int>> resting_pairs = pairs_of(pass.resting);
  report.ccd_queries +=
      sweep_motions(sweep_world(), everyone, pass.next, &resting_pairs, &pass.ccd, nullptr, &swept_pairs).ccd_queries;
  for (const auto& [pair, query] : pass.ccd) {
    if (query.deepens || meets_inside(query.result))
      pass.eventful.insert(pass.groups.find(moving(pair.first) ? pair.first : pair.second));
  }
  return pass;
}

void World::step_pending_groups(double dt_s, FirstPass& pass, const std::vector<int>& pending,
                                const std::vector<int>& dynamic, const std::vector<int>& fixed, GroupStepping& g,
                                StepReport& report) {
  const int n = body_count();
  const auto root = [&](int i) { return pass.groups.find(i); };
  std::vector<std::pair<int, int>> members;  // (root, body): the pending groups' bodies, in body order
  for (int i : dynamic)
    if (std::binary_search(pending.begin(), pending.end(), root(i))) members.emplace_back(root(i), i);
  std::sort(members.begin(), members.end());
  std::vector<std::vector<int>> resting_of(n);  // by root, for the groups stepped on their own
  for (std::size_t k = 0; k < pass.resting.size(); ++k) {
    const Contact& c = pass.resting[k];
    const int r = root(moving(c.body_a) ? c.body_a : c.body_b);
    if (g.stepped[r] || pass.eventful.count(r)) resting_of[r].push_back(static_cast<int>(k));
  }
  for (std::size_t first_member = 0; first_member < members.size();) {
    const int r = members[first_member].first;
    std::vector<int> bodies;
    for (; first_member < members.size() && members[first_member].first == r; ++first_member)
      bodies.push_back(members[first_member].second);
    if (g.stepped[r]) {
      // Stepped before, merged since: start again from the step's start (and forget the
      // bounces that pass held back: this one finds its own).
      const auto in_group = [&](int i) { return moving(i) && root(i) == r; };
      state_.held_back_bounces.erase(std::remove_if(state_.held_back_bounces.begin(), state_.held_back_bounces.end(),
                                                    [&](const ContactHints::Bounce& p) {
                                                      return in_group(p.bodies.first) || in_group(p.bodies.second);
                                                    }),
                                     state_.held_back_bounces.end());
      for (int i : bodies) {
        state_.bodies[i].X_WB = g.start[i].X_WB;
        state_.bodies[i].v_WBcm_m_s = g.start[i].v;
        state_.bodies[i].w_WB_rad_s = g.start[i].w;
      }
    } else if (!pass.eventful.count(r)) {
      for (int i : bodies) {
        g.moved[i] = pass.swept[i];
        state_.bodies[i].X_WB = pass.next[i];
        state_.bodies[i].v_WBcm_m_s = pass.u[i].v_WBcm_m_s;
        state_.bodies[i].w_WB_rad_s = pass.u[i].w_WB_rad_s;
      }
      continue;
    }
    std::vector<int> participants;
    std::merge(bodies.begin(), bodies.end(), fixed.begin(), fixed.end(), std::back_inserter(participants));
    FirstSolve f{{}, {}, {}, pass.islands};
    f.u.reserve(participants.size());
    for (int i : participants) f.u.push_back(pass.u[i]);
    f.resting.reserve(resting_of[r].size());
    f.solved.reserve(resting_of[r].size());
    for (int k : resting_of[r]) {
      f.resting.push_back(pass.resting[k]);
      f.solved.push_back(pass.solved[k]);
    }
    GroupOutcome outcome = advance_group(dt_s, participants, f, pass.ccd, report);
    g.stepped[r] = 1;
    g.contacts_of[r] = std::move(outcome.contacts);
    for (std::size_t s = 0; s < participants.size(); ++s)
      if (moving(participants[s])) g.moved[participants[s]] = outcome.swept[s];
  }
}

std::vector<int> World::reaching_groups(FirstPass& pass, const std::vector<int>& dynamic, GroupStepping& g) {
  const auto root = [&](int i) { return pass.groups.find(i); };
  // One group (a pile come to rest on itself): there is no other to reach.
  const int first_root = root(dynamic.front());
  if (std::all_of(dynamic.begin(), dynamic.end(), [&](int i) { return root(i) == first_root; })) return {};
  // The other groups' boxes are their first sweeps, which overlap no other group's: only a
  // pair with a stepped group's body can join two groups.
  std::vector<Eigen::AlignedBox3d> boxes;
  std::vector<char> of_stepped;
  boxes.reserve(dynamic.size());
  for (int i : dynamic) {
    boxes.push_back(g.moved[i]);
    of_stepped.push_back(g.stepped[root(i)]);
  }
  std::vector<int> pending;
  for (const auto& [p, q] : collision::overlapping_pairs_involving(boxes, of_stepped)) {
    const int i = dynamic[p], j = dynamic[q];
    if (root(i) == root(j)) continue;
    pass.groups.join(i, j);
    g.stepped[root(i)] = 1;  // its bodies restart from the step's start
    pending.push_back(root(i));
  }
  for (int& r : pending) r = root(r);
  std::sort(pending.begin(), pending.end());
  pending.erase(std::unique(pending.begin(), pending.end()), pending.end());
  return pending;
}

void World::keep_step_contacts(FirstPass& pass, const std::vector<int>& dynamic, const GroupStepping& g, double dt_s,
                               StepReport& report) {
  const auto root = [&](int i) { return pass.groups.find(i); };
  // The contacts of each group's last solve: the first solve's, unless stepped on its own.
  state_.contacts.clear();
  for (std::size_t k = 0; k < pass.resting.size(); ++k) {
    const Contact& c = pass.resting[k];
    if (!g.stepped[root(moving(c.body_a) ? c.body_a : c.body_b)]) state_.contacts.push_back(pass.solved[k]);
  }
  for (int i : dynamic)
    if (root(i) == i && g.stepped[i])
      state_.contacts.insert(state_.contacts.end(), g.contacts_of[i].begin(), g.contacts_of[i].end());
  report.contacts = static_cast<int>(state_.contacts.size());
  state_.hints.pushed_before.clear();
  for (const Contact& c : state_.contacts)
    if (c.impulse_N_s > 0)
      state_.hints.pushed_before.push_back(
          {{std::min(c.body_a, c.body_b), std::max(c.body_a, c.body_b)}, row_point(c.feature)});
  std::sort(state_.hints.pushed_before.begin(), state_.hints.pushed_before.end(),
            [](const ContactHints::Pushed& x, const ContactHints::Pushed& y) { return x.bodies < y.bodies; });
  // Kept only where a solve can use them: the iterative solver, an exact solver's island
  // too large for it (max_exact_rows), and the exact solver's friction sweeps (kept for
  // every contact, they cost a frictionless pile's small exact islands time for nothing).
  state_.hints.warm_forces.clear();
  const bool iterative =
      model_.options.solver.kind == ContactSolverKind::kProjectedGaussSeidel || report.iterative_islands > 0;
  for (const Contact& c : pass.solved)
    if (c.impulse_N_s > 0 && (iterative || combined_friction(model_.bodies[c.body_a], model_.bodies[c.body_b]) > 0))
      state_.hints.warm_forces.push_back(
          {{std::min(c.body_a, c.body_b), std::max(c.body_a, c.body_b)}, row_point(c.feature), c.impulse_W_N_s / dt_s});
  std::sort(state_.hints.warm_forces.begin(), state_.hints.warm_forces.end(),
            [](const ContactHints::Force& x, const ContactHints::Force& y) { return x.bodies < y.bodies; });
}

StepReport World::step(double dt_s) {
  if (!(dt_s > 0) || !std::isfinite(dt_s))
    throw std::invalid_argument("World::step: dt_s must be positive, got " + std::to_string(dt_s));
  StepReport report;
  const int n = body_count();
  std::vector<int> everyone(n), fixed, dynamic;
  std::iota(everyone.begin(), everyone.end(), 0);
  set_kinematic_state(everyone, state_.time_s, dt_s);
  if (model_.options.sleep_after_s > 0) wake_reachable_sleepers(dt_s);
  for (int i = 0; i < n; ++i) (moving(i) ? dynamic : fixed).push_back(i);
  begin_step_memos();
  FirstPass pass = first_pass(dt_s, everyone, report);
  // Each group stepped (or just moved), then again any whose motion reached into another's
  // sweep, merged with it, from the step's start. (Only a group stepped on its own can have
  // left the sweep it was grouped by.)
  GroupStepping g{std::vector<GroupStepping::State>(n), std::vector<Eigen::AlignedBox3d>(n), std::vector<char>(n, 0),
                  std::vector<std::vector<Contact>>(n)};
  for (int i : dynamic) g.start[i] = {state_.bodies[i].X_WB, state_.bodies[i].v_WBcm_m_s, state_.bodies[i].w_WB_rad_s};
  std::vector<int> pending;
  for (int i : dynamic)
    if (pass.groups.find(i) == i) pending.push_back(i);
  while (!pending.empty()) {
    step_pending_groups(dt_s, pass, pending, dynamic, fixed, g, report);
    if (std::none_of(pending.begin(), pending.end(), [&](int r) { return g.stepped[pass.groups.find(r)]; })) break;
    pending = reaching_groups(pass, dynamic, g);
  }
  keep_step_contacts(pass, dynamic, g, dt_s, report);
  if (model_.options.sleep_after_s > 0) end_sleep_step(dt_s, report);
  state_.time_s += dt_s;
  state_.mesh.placed_since_step.assign(n, 0);
  state_.sleep.placed_to_wake.assign(n, 0);
  set_kinematic_state(everyone, state_.time_s, 0.0);
  report.mesh_crossing_tests = state_.mesh.crossing_tests;
  return report;
}

}  // namespace arphys::dynamics
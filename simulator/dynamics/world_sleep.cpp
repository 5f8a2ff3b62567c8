// Sleep (WorldOptions::sleep_after_s): which bodies a step holds fixed, which it wakes, and
// which fall asleep after it.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "simulator/collision/broad_phase.hpp"
#include "simulator/dynamics/disjoint_sets.hpp"
#include "simulator/dynamics/step_helpers.hpp"
#include "simulator/dynamics/world.hpp"

namespace arphys::dynamics {

using step_helpers::ball_bounds;

void World::wake(std::vector<int> woken) {
  while (!woken.empty()) {
    const int i = woken.back();
    woken.pop_back();
    state_.sleep.quiet_s[i] = 0;
    if (!state_.bodies[i].asleep) continue;
    state_.bodies[i].asleep = false;
    for (int j : state_.sleep.touching[i])
      if (state_.bodies[j].asleep) woken.push_back(j);
  }
}

double World::point_speed_m_s(int i) const {
  const BodyState& body = state_.bodies[i];
  return body.v_WBcm_m_s.norm() + body.w_WB_rad_s.norm() * model_.radius_m[i];
}

void World::wake_reachable_sleepers(double dt_s) {
  const int n = body_count();
  const double tolerance = model_.options.contact_tolerance_m;
  const double fall_m = 0.5 * model_.options.gravity_m_s2.norm() * dt_s * dt_s;
  // What can reach a sleeper over the step, and how far (bounding radius included): a
  // moving kinematic body by its motion (this step's twist) and the contact tolerance; a
  // moving dynamic body by those and a fall under gravity. A quiet awake body wakes only
  // the sleepers it touches (it may be pushed into them, which held fixed would squeeze
  // it); by bounding balls, resting bodies near each other woke each other over and over.
  std::vector<int> sleepers, woken;
  std::vector<std::pair<int, double>> reaching;
  for (int i = 0; i < n; ++i) {
    const BodyModel& body = model_.bodies[i];
    const double speed_m_s = point_speed_m_s(i);
    if (state_.bodies[i].asleep && body.is_dynamic() && speed_m_s == 0) {
      sleepers.push_back(i);
      continue;
    }
    if (state_.bodies[i].asleep) woken.push_back(i);  // (a sleeper given a velocity from outside)
    if (state_.sleep.placed_to_wake[i]) {
      // Placed: it reaches what its new pose touches (a plane, everything).
      if (!std::isfinite(model_.radius_m[i])) {
        for (int j = 0; j < n; ++j)
          if (state_.bodies[j].asleep) woken.push_back(j);
      } else {
        reaching.emplace_back(i, model_.radius_m[i] + speed_m_s * dt_s + tolerance);
      }
    }
    if (body.motion == BodyMotion::kKinematic && speed_m_s > 0)
      reaching.emplace_back(i, model_.radius_m[i] + speed_m_s * dt_s + tolerance);
    if (body.is_dynamic() && speed_m_s >= model_.options.sleep_speed_m_s)
      reaching.emplace_back(i, model_.radius_m[i] + speed_m_s * dt_s + fall_m + tolerance);
  }
  // The sleepers a moving body reaches (bounding balls), and in turn those they touched.
  for (const Contact& c : state_.contacts)  // (the last step's)
    for (const auto& [awake, other] : {std::pair(c.body_a, c.body_b), std::pair(c.body_b, c.body_a)})
      if (moving(awake) && state_.bodies[other].asleep) woken.push_back(other);
  if (!reaching.empty() && !sleepers.empty()) {
    std::vector<Eigen::AlignedBox3d> boxes;
    for (const auto& [i, reach_m] : reaching)
      boxes.push_back(ball_bounds(state_.bodies[i].X_WB.translation(), reach_m));
    for (int i : sleepers) boxes.push_back(ball_bounds(state_.bodies[i].X_WB.translation(), model_.radius_m[i]));
    const int r = static_cast<int>(reaching.size());
    for (const auto& [p, q] : collision::overlapping_pairs(boxes))
      if ((p < r) != (q < r)) woken.push_back(sleepers[std::max(p, q) - r]);
  }
  wake(std::move(woken));
}

void World::end_sleep_step(double dt_s, StepReport& report) {
  const int n = body_count();
  const auto awake = [&](int i) { return moving(i); };
  for (int i = 0; i < n; ++i) {
    if (!awake(i)) continue;
    // (Counted in steps' worth of time: fifty 10 ms steps add up to just under 0.5 s.)
    state_.sleep.quiet_s[i] =
        point_speed_m_s(i) < model_.options.sleep_speed_m_s ? state_.sleep.quiet_s[i] + dt_s * (1 + 1e-9) : 0.0;
  }
  // Bodies in contact fall asleep together, once the last of them has been quiet long
  // enough: a body asleep against an awake one would be woken by it at once.
  DisjointSets islands(n);
  for (const Contact& c : state_.contacts)
    if (awake(c.body_a) && awake(c.body_b)) islands.join(c.body_a, c.body_b);
  std::vector<double> least_quiet_s(n, std::numeric_limits<double>::infinity());
  for (int i = 0; i < n; ++i)
    if (awake(i)) least_quiet_s[islands.find(i)] = std::min(least_quiet_s[islands.find(i)], state_.sleep.quiet_s[i]);
  std::vector<char> falling_asleep(n, 0);
  for (int i = 0; i < n; ++i) {
    if (!awake(i) || least_quiet_s[islands.find(i)] < model_.options.sleep_after_s) continue;
    falling_asleep[i] = 1;
    state_.bodies[i].v_WBcm_m_s.setZero();
    state_.bodies[i].w_WB_rad_s.setZero();
    state_.sleep.touching[i].clear();
  }
  for (const Contact& c : state_.contacts) {
    if (!model_.bodies[c.body_a].is_dynamic() || !model_.bodies[c.body_b].is_dynamic()) continue;
    if (falling_asleep[c.body_a]) state_.sleep.touching[c.body_a].push_back(c.body_b);
    if (falling_asleep[c.body_b]) state_.sleep.touching[c.body_b].push_back(c.body_a);
  }
  for (int i = 0; i < n; ++i) state_.bodies[i].asleep = state_.bodies[i].asleep || falling_asleep[i];
  report.bodies_asleep = static_cast<int>(
      std::count_if(state_.bodies.begin(), state_.bodies.end(), [](const BodyState& body) { return body.asleep; }));
}

}  // namespace arphys::dynamics

// World's bodies and its step: the first solve of everything, the groups that can meet
// within the step, each group's motion cut at its impacts, and sleep. A step's stages live
// beside it: the contacts and the constrained solve in world_contacts.cpp, the sweeping of
// the motions the solve gives in world_impacts.cpp.
#include "simulator/dynamics/world.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>

#include "simulator/collision/broad_phase.hpp"
#include "simulator/dynamics/disjoint_sets.hpp"
#include "simulator/dynamics/world_internal.hpp"

namespace arphys::dynamics {

using world_internal::ball_bounds;
using world_internal::combined_friction;
using world_internal::meets_inside;
using world_internal::row_point;
using world_internal::slot_of;

namespace {

// Projections before a part of a step falls back to re-solving its deep points.
constexpr int kMaxProjectionsPerMotion = 4;

// A body's pose after moving its centre of mass with v and turning with w for h.
geometry::Pose integrate(const RigidBody& body, const BodyVelocity& u, double h) {
  return moved_about_com(body.X_WB, body.mass.center_of_mass_m, u.v_WBcm_m_s * h, u.w_WB_rad_s, u.w_WB_rad_s.norm() * h);
}

// The body pairs of the contacts, sorted, once each.
std::vector<std::pair<int, int>> pairs_of(const std::vector<Contact>& contacts) {
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(contacts.size());
  for (const Contact& c : contacts) pairs.emplace_back(std::min(c.body_a, c.body_b), std::max(c.body_a, c.body_b));
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

// The options' preconditions, each named with its value when it fails: a NaN tolerance
// compares false with everything, and would quietly turn checks off (a NaN overlap
// tolerance lets every pair sink), a zero event cap would end every step at its first
// impact.
void check_options(const WorldOptions& o) {
  const auto fail = [](const std::string& name, double value, const std::string& expected) {
    std::ostringstream message;
    message << "World: option " << name << " is " << value << ", expected " << expected;
    throw std::invalid_argument(message.str());
  };
  const auto positive = [&](const char* name, double value) {
    if (!(value > 0) || !std::isfinite(value)) fail(name, value, "a positive finite number");
  };
  const auto non_negative = [&](const char* name, double value) {
    if (!(value >= 0) || !std::isfinite(value)) fail(name, value, "a finite number >= 0");
  };
  const auto at_least = [&](const char* name, long value, long least) {
    if (value < least) fail(name, static_cast<double>(value), "an integer >= " + std::to_string(least));
  };
  if (!o.gravity_m_s2.allFinite()) fail("gravity_m_s2 (its norm)", o.gravity_m_s2.norm(), "a finite vector");
  positive("contact_tolerance_m", o.contact_tolerance_m);
  non_negative("resting_unswept_motion_m", o.resting_unswept_motion_m);
  positive("overlap_tolerance_m", o.overlap_tolerance_m);
  non_negative("contact_gap_m", o.contact_gap_m);
  if (!(o.contact_gap_m < o.contact_tolerance_m))
    fail("contact_gap_m", o.contact_gap_m, "less than contact_tolerance_m (" + std::to_string(o.contact_tolerance_m) + " m)");
  positive("max_depenetration_speed_m_s", o.max_depenetration_speed_m_s);
  non_negative("restitution_threshold_m_s", o.restitution_threshold_m_s);
  at_least("max_events_per_step", o.max_events_per_step, 1);
  non_negative("launch_guard_slack_m_s", o.launch_guard_slack_m_s);
  if (!(o.max_body_speed_m_s > 0)) fail("max_body_speed_m_s", o.max_body_speed_m_s, "a positive number (may be infinite)");
  at_least("max_contacts_per_pair", o.max_contacts_per_pair, 1);
  at_least("threads", o.threads, 1);
  if (o.threads > 256) fail("threads", o.threads, "at most 256");
  non_negative("sleep_after_s", o.sleep_after_s);
  non_negative("sleep_speed_m_s", o.sleep_speed_m_s);
  at_least("solver.iterations", o.solver.iterations, 1);
  at_least("solver.provisional_friction_sweeps", o.solver.provisional_friction_sweeps, 1);
  non_negative("solver.sweep_tolerance_m_s", o.solver.sweep_tolerance_m_s);
  at_least("solver.max_exact_rows", o.solver.max_exact_rows, 0);
  positive("ccd.time_tolerance", o.ccd.time_tolerance);
  positive("ccd.min_culling_interval", o.ccd.min_culling_interval);
  positive("ccd.time_split_ratio", o.ccd.time_split_ratio);
  at_least("ccd.max_triangle_pairs", o.ccd.max_triangle_pairs, 0);
  at_least("ccd.max_search_nodes", o.ccd.max_search_nodes, 0);
}

}  // namespace


World::World(WorldOptions options) : options_((check_options(options), std::move(options))), pool_(options_.threads) {}

bool World::known_apart(const std::map<std::pair<int, int>, ApartAt>& known, int i, int j, const geometry::Pose& X_WA,
                        const geometry::Pose& X_WB) {
  const auto it = known.find({i, j});
  return it != known.end() && it->second.X_WA.matrix() == X_WA.matrix() && it->second.X_WB.matrix() == X_WB.matrix();
}

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
  radius_m_.push_back(body.bounding_radius_m());
  placed_since_step_.push_back(1);
  placed_to_wake_.push_back(0);
  quiet_s_.push_back(0);
  asleep_.push_back(0);
  touching_.emplace_back();
  bodies_.push_back(std::move(body));
  return static_cast<int>(bodies_.size()) - 1;
}

void World::place_body(int index, const geometry::Pose& X_WB) {
  RigidBody& body = bodies_.at(index);
  if (!X_WB.matrix().allFinite()) throw std::invalid_argument("World::place_body: body '" + body.id + "': non-finite pose");
  body.X_WB = X_WB;
  placed_since_step_.at(index) = 1;
  placed_to_wake_.at(index) = 1;
  wake({index});
}

void World::wake(std::vector<int> woken) {
  while (!woken.empty()) {
    const int i = woken.back();
    woken.pop_back();
    quiet_s_[i] = 0;
    if (!asleep_[i]) continue;
    asleep_[i] = 0;
    for (int j : touching_[i])
      if (asleep_[j]) woken.push_back(j);
  }
}

void World::remove_body(int index) {
  bodies_.erase(bodies_.begin() + index);
  radius_m_.erase(radius_m_.begin() + index);
  quiet_s_.erase(quiet_s_.begin() + index);
  placed_to_wake_.erase(placed_to_wake_.begin() + index);
  asleep_.erase(asleep_.begin() + index);
  touching_.erase(touching_.begin() + index);
  for (auto& partners : touching_) {
    partners.erase(std::remove(partners.begin(), partners.end(), index), partners.end());
    for (int& j : partners) j -= j > index;
  }
  contacts_.clear();
  pushed_before_.clear();
  warm_forces_.clear();
  pending_bounces_.clear();
  next_bounces_.clear();
  nearby_.clear();
  apart_at_end_.clear();
  apart_at_last_end_.clear();
  // (Pair indices shift: every body is tested again rather than the pairs renumbered.)
  placed_since_step_.assign(bodies_.size(), 1);
  placed_crossing_.clear();
}

collision::NearbyTrianglePairs* World::nearby_pairs(int i, int j) const {
  Nearby& entry = nearby_[{std::min(i, j), std::max(i, j)}];
  entry.used = true;
  return &entry.pairs;
}

int World::find(const std::string& id) const {
  for (int i = 0; i < static_cast<int>(bodies_.size()); ++i)
    if (bodies_[i].id == id) return i;
  return -1;
}

void World::set_kinematic_state(const std::vector<int>& participants, double t_s, double h_s) {
  for (int i : participants) {
    RigidBody& body = bodies_[i];
    if (body.motion != BodyMotion::kKinematic || body.trajectory.empty()) continue;
    body.X_WB = body.trajectory.pose_at(t_s);
    if (h_s > 0) {
      // The constant twist that takes it where the trajectory says it is after h (a
      // step can straddle two tracked poses: the instantaneous twist would be wrong).
      const geometry::ScrewMotion screw(body.X_WB, body.trajectory.pose_at(t_s + h_s));
      body.w_WB_rad_s = screw.angular_velocity() / h_s;
      body.v_WBcm_m_s = screw.velocity_of_point(body.com_W()) / h_s;
    } else {
      const Twist twist = body.trajectory.twist_at(t_s);
      body.w_WB_rad_s = twist.w_WB_rad_s;
      body.v_WBcm_m_s = twist.velocity_of_point(body.com_W(), body.X_WB.translation());
    }
  }
}

std::vector<geometry::Pose> World::candidate_poses(const std::vector<int>& participants, const std::vector<BodyVelocity>& u,
                                                   double elapsed, double h) const {
  std::vector<geometry::Pose> next(participants.size());
  for (std::size_t s = 0; s < participants.size(); ++s) {
    const RigidBody& body = bodies_[participants[s]];
    if (body.is_dynamic()) {
      next[s] = integrate(body, u[s], h);
    } else if (body.motion == BodyMotion::kKinematic && !body.trajectory.empty()) {
      next[s] = body.trajectory.pose_at(time_s_ + elapsed + h);
    } else {
      next[s] = body.X_WB;
    }
  }
  return next;
}

World::GroupOutcome World::advance_group(double dt_s, const std::vector<int>& participants, const FirstSolve& first,
                                         ImpactCache& first_ccd, StepReport& report) {
  GroupOutcome outcome;
  outcome.swept.assign(participants.size(), Eigen::AlignedBox3d());
  double elapsed = 0;
  int events = 0;
  Cut cut;  // the last cut's motions and answers
  bool cut_at_start = false;  // the last cut was at the start of its motion
  while (dt_s - elapsed > 1e-12 * dt_s) {
    double h = dt_s - elapsed;
    set_kinematic_state(participants, time_s_ + elapsed, h);
    // Solve, move, and let the CCD say whether anything meets inside the step. Pairs
    // that do join the constraints with every feature they can reach, and the step is
    // solved again: the impact is then a constraint of this step (its bounce a velocity
    // update at the step boundary), and nothing ends up inside anything.
    ImpactMap impacts;
    // The poses do not change while the step is re-solved: the contacts are found once.
    // The step's first solve (all groups at once) is given.
    const bool at_start = elapsed == 0;
    // (The first solve's contacts are not copied: a whole pile's are a megabyte.)
    std::vector<Contact> gathered;
    if (!at_start) gathered = gather_contacts(participants);
    const std::vector<Contact>& resting = at_start ? first.resting : gathered;
    const std::vector<std::pair<int, int>> resting_pairs = pairs_of(resting);
    // Gravity and the gyroscopic term act once per step, over all of it, in its first
    // solve: the velocities are end-of-step velocities (symplectic Euler), and a step cut
    // at a time of impact carries them on. Adding the force again over the time left
    // after each cut gave bodies with many events (two bunnies falling off the table
    // touching and spinning) up to five times the step's gravity: they fell at twice the
    // free-fall speed.
    const double force_h = at_start ? dt_s : 0.0;
    // Islands solved at these poses: a re-solve with an impact added re-solves only the
    // islands the impact touches. (At the step's start, shared with the first solve.)
    SolvedIslands fresh_islands;
    SolvedIslands& solved_islands = at_start ? first.islands : fresh_islands;
    // (At the step's start the first solve is given: the setup is built if a re-solve needs it.)
    std::optional<SolveSetup> setup;
    if (!at_start) setup = prepare_solve(h, force_h, participants, resting);
    std::vector<BodyVelocity> u;
    bool squeezed = false;
    if (at_start) {
      u = first.u;
      outcome.contacts = first.solved;
    } else {
      u = solve(*setup, participants, resting, impacts, outcome.contacts, report, &squeezed, &solved_islands);
    }
    std::vector<geometry::Pose> next = candidate_poses(participants, u, elapsed, h);
    double tau = 1.0;
    // Answers valid while the start poses are these: the step's first sweep, then fresh,
    // but for the pairs that go on as before the cut (below).
    ImpactCache fresh;
    if (!at_start) fresh = carry_over_cut(participants, u, next, cut);
    ImpactCache& cache = at_start ? first_ccd : fresh;
    // The participants' swept boxes and their overlapping pairs, for the end poses they
    // were swept to: a re-solve changes the motions of the islands it touches, so only
    // those bodies are swept again (in a 1000-box pile, one group, sweeping all of them
    // again in every round was a twentieth of the step).
    std::vector<Eigen::AlignedBox3d> swept_boxes(participants.size());
    std::vector<geometry::Pose> swept_to;
    std::vector<std::pair<int, int>> swept_pairs;
    const auto sweep = [&] {
      std::vector<char> changed(participants.size(), 1);
      for (std::size_t s = 0; s < participants.size(); ++s) {
        if (!swept_to.empty() && next[s].matrix() == swept_to[s].matrix()) {
          changed[s] = 0;
        } else {
          swept_boxes[s] = swept_box(participants[s], next[s]);
        }
      }
      swept_pairs = swept_to.empty() ? collision::overlapping_pairs(swept_boxes)
                                      : collision::overlapping_pairs_updated(swept_boxes, changed, swept_pairs);
      swept_to = next;
    };
    int projections = 0;  // rounds of this part of the step that lifted end poses instead of solving
    for (int round = 0;; ++round) {
      ImpactMap meeting;
      bool deepening = false;
      sweep();
      tau = earliest_impact(participants, next, &resting_pairs, &meeting, &cache, &deepening, report, &swept_pairs);
      // A squeezed body overlaps whatever the solve does: reported, not chased.
      if (squeezed) deepening = false;
      if (tau >= 1.0 && !deepening) break;
      ++report.impacts_resolved;
      if (round == 3) {
        // Linearised constraints still let a touching pair dig in: stop where it is no
        // deeper than allowed (halving: the linearisation's error shrinks with the square).
        // Unless that is a cut of nothing again (a mesh pair crossing at once, which three
        // re-solves did not lift) while a tracked body moves: the group's step would end
        // there (it "waits"), and the tracked box moved on into its bunnies, 4.5 mm a step,
        // up to 70 mm deep in the 20-bunny scene. The motion goes on instead (to the next
        // meeting, if any); the pair crosses by what this motion dips it (under 1 mm there)
        // and is pushed apart in the next step (mesh_crossing_depth). With nothing tracked
        // moving, waiting costs only time and the pair never crosses.
        if (deepening) {
          const double shallow = shallow_fraction(participants, next, cache, meeting);
          const bool would_wait = shallow == 0 && cut_at_start;
          const auto tracked_moving = [&] {
            return std::any_of(participants.begin(), participants.end(), [&](int i) {
              const RigidBody& body = bodies_[i];
              return body.motion == BodyMotion::kKinematic && (body.v_WBcm_m_s.squaredNorm() > 0 || body.w_WB_rad_s.squaredNorm() > 0);
            });
          };
          if (!would_wait || !tracked_moving()) tau = std::min(tau, shallow);
        }
        break;
      }
      // Nothing meets inside the step; resting pairs only end it too deep: their end poses
      // are lifted (the velocities stay the solve's), and the next round checks the motion
      // to the lifted poses as it checked this one.
      if (options_.project_deep_points && deepening && projections < kMaxProjectionsPerMotion &&
          project_deep_points(participants, next, meeting, cache, resting_pairs)) {
        ++report.projections;
        ++projections;
        --round;  // (not a re-solve: the rounds of re-solves stay three)
        continue;
      }
      bool chained = false;
      for (auto& [pair, hits] : meeting) {
        const geometry::Pose& X_A_end = next[slot_of(participants, pair.first)];
        const geometry::Pose& X_B_end = next[slot_of(participants, pair.second)];
        for (ImpactPoint& hit : hits) {
          // How deep the point ends the motion: a touching pair's as measured, a CCD
          // meeting's material points along A's normal there (the row's linearised
          // bound misses it by the turn's second-order term, micrometres in a
          // collapsing pile: re-solved with the same bound, such a pair met again in
          // every round and cut the step).
          const double end_depth_m =
              hit.end_depth_m >= 0
                  ? hit.end_depth_m
                  : (X_A_end.linear() * hit.normal_A_B).dot(X_A_end * hit.point_A_B - X_B_end * hit.point_B_B);
          // The point's normal velocity in the motion that let it in, and what lifts it out.
          const auto velocity = [&](int body, const Eigen::Vector3d& p_W) -> Eigen::Vector3d {
            const RigidBody& b = bodies_[body];
            if (!b.is_dynamic()) return b.velocity_of_point(p_W);
            const int slot = slot_of(participants, body);
            return u[slot].v_WBcm_m_s + u[slot].w_WB_rad_s.cross(p_W - b.com_W());
          };
          const Eigen::Vector3d p_A = bodies_[pair.first].X_WB * hit.point_A_B, p_B = bodies_[pair.second].X_WB * hit.point_B_B;
          const Eigen::Vector3d n = bodies_[pair.first].X_WB.linear() * hit.normal_A_B;
          // At the midpoint, as the constraint row measures it (the two material points
          // can be millimetres apart along the surface at the start of a sliding step).
          const Eigen::Vector3d m = 0.5 * (p_A + p_B);
          const double v_n = n.dot(velocity(pair.second, m) - velocity(pair.first, m));
          hit.min_normal_velocity_m_s = v_n + (end_depth_m + options_.contact_gap_m) / h;
          // A bouncing meeting that this step's solve brought about (a ball struck by
          // another within the step, which then strikes a third): the row's bounce is
          // taken from the velocities at the step's start, which do not have it, and
          // solved with the first impact at once it shares the momentum out (a chain of
          // three elastic balls ended at a third of the speed each). It is met in turn:
          // the step is cut there, and the next part bounces it from the velocities
          // it then has. Only where the bounce missed is itself one (restitution times
          // the approach the solve added, beyond gravity's over the step): in a bunny
          // pile (restitution 0.3) every solve changes approaches a little, and cutting
          // at each made it 40 % slower.
          if (hit.end_depth_m < 0 && v_n < -options_.restitution_threshold_m_s) {
            const double restitution = std::max(bodies_[pair.first].restitution, bodies_[pair.second].restitution);
            const double v_n_start =
                n.dot(bodies_[pair.second].velocity_of_point(m) - bodies_[pair.first].velocity_of_point(m));
            const double missed_bounce_m_s =
                restitution * (std::abs(v_n - v_n_start) - options_.gravity_m_s2.norm() * force_h);
            if (missed_bounce_m_s <= options_.restitution_threshold_m_s) continue;
            if (restitution >= options_.sequential_bounce_restitution) {
              chained = true;
            } else {
              next_bounces_.push_back({pair, n, missed_bounce_m_s});
            }
          }
        }
        impacts[pair].insert(impacts[pair].end(), hits.begin(), hits.end());
      }
      if (chained) {
        // Cut at the meeting, but not past where a touching pair digs in (a mesh pair
        // crossing at once: cut at the start, cut past it, it crossed and sank unseen).
        const double cut_at = deepening ? std::min(tau, shallow_fraction(participants, next, cache, meeting)) : tau;
        // Such a pair crossing at once would make it a cut of nothing, and the same again
        // after it: the group's whole step would end there, step after step (a 20-bunny
        // scene froze for a second, a bunny on the table crossing at once while another
        // bounced). The bounce is then solved with the rest, and the pair's crossing with it.
        if (cut_at > 0) {
          tau = cut_at;
          break;
        }
      }
      if (!setup) setup = prepare_solve(h, force_h, participants, resting);
      std::vector<BodyVelocity> u_resolved =
          solve(*setup, participants, resting, impacts, outcome.contacts, report, &squeezed, &solved_islands);
      if (squeezed && tau >= 1.0) break;  // asked only to stop digging in, and it cannot be had: keep the motion
      std::vector<geometry::Pose> next_resolved = candidate_poses(participants, u_resolved, elapsed, h);
      keep_motions(participants, u, next, u_resolved, next_resolved);  // (after a cut, the end poses kept there)
      u = std::move(u_resolved);
      next = std::move(next_resolved);
    }
    if (tau < 1.0) {
      // Still meeting (a turning body whose constraints were linearised): stop at the
      // impact, with the velocities of the step, and go on from there.
      tau = unswept_clear_fraction(participants, next, cache, tau, h);
      h *= tau;
      if (++events >= options_.max_events_per_step) outcome.capped = true;
      // A second cut at the start of what is left: nothing has moved since the last, the
      // step's force is spent, and the solve would give the same motion until the cap (a
      // mesh pair crossing at once, check_mesh_crossing, with nothing tracked moving: see
      // round 3 above): the group's step ends here.
      if (tau == 0 && cut_at_start) outcome.capped = true;
      cut_at_start = tau == 0;
      cut = {u, next, tau, {}};
      if (at_start) {
        // The group's answers move out of the step's first sweep (copied, they were a
        // twentieth of a 1000-box pile's step); were the group stepped again after a
        // merge, its pairs would be swept again, to the same answers.
        for (int i : participants)
          for (auto it = cache.lower_bound({i, -1}); it != cache.end() && it->first.first == i;)
            if (slot_of(participants, it->first.second) >= 0) {
              cut.answers.insert(cut.answers.end(), cache.extract(it++));
            } else {
              ++it;
            }
      } else {
        cut.answers = std::move(fresh);
      }
    }
    for (std::size_t s = 0; s < participants.size(); ++s) {
      RigidBody& body = bodies_[participants[s]];
      if (!body.is_dynamic()) continue;
      const geometry::Pose X = tau >= 1.0 ? next[s] : geometry::ScrewMotion(body.X_WB, next[s]).pose_at(tau);
      if (X.matrix().allFinite() && u[s].v_WBcm_m_s.allFinite() && u[s].w_WB_rad_s.allFinite()) {
        outcome.swept[s].extend(swept_box(participants[s], X));
        body.X_WB = X;
        body.v_WBcm_m_s = u[s].v_WBcm_m_s;
        body.w_WB_rad_s = u[s].w_WB_rad_s;
      } else {
        // Last line of defence: a numerical failure anywhere in the step (solve, CCD
        // cut, integration) leaves the body where it was, at rest. Never NaN.
        outcome.swept[s].extend(body.X_WB.translation());
        body.v_WBcm_m_s.setZero();
        body.w_WB_rad_s.setZero();
        ++report.non_finite_held;
      }
    }
    elapsed += h;
    if (outcome.capped) break;
  }
  report.events = std::max(report.events, events);
  report.events_capped |= outcome.capped;
  return outcome;
}

double World::point_speed_m_s(int i) const {
  const RigidBody& body = bodies_[i];
  return body.v_WBcm_m_s.norm() + body.w_WB_rad_s.norm() * radius_m_[i];
}

std::vector<int> World::hold_sleepers(double dt_s) {
  const int n = static_cast<int>(bodies_.size());
  const double tolerance = options_.contact_tolerance_m;
  const double fall_m = 0.5 * options_.gravity_m_s2.norm() * dt_s * dt_s;
  // What can reach a sleeper over the step, and how far (bounding radius included): a
  // moving kinematic body by its motion (this step's twist) and the contact tolerance; a
  // moving dynamic body by those and a fall under gravity. A quiet awake body wakes only
  // the sleepers it touches (it may be pushed into them, which held fixed would squeeze
  // it); by bounding balls, resting bodies near each other woke each other over and over.
  std::vector<int> sleepers, woken;
  std::vector<std::pair<int, double>> reaching;
  for (int i = 0; i < n; ++i) {
    const RigidBody& body = bodies_[i];
    const double speed_m_s = point_speed_m_s(i);
    if (asleep_[i] && body.is_dynamic() && speed_m_s == 0) {
      sleepers.push_back(i);
      continue;
    }
    if (asleep_[i]) woken.push_back(i);  // (a sleeper given a velocity from outside)
    if (placed_to_wake_[i]) {
      // Placed: it reaches what its new pose touches (a plane, everything).
      if (!std::isfinite(radius_m_[i])) {
        for (int j = 0; j < n; ++j)
          if (asleep_[j]) woken.push_back(j);
      } else {
        reaching.emplace_back(i, radius_m_[i] + speed_m_s * dt_s + tolerance);
      }
    }
    if (body.motion == BodyMotion::kKinematic && speed_m_s > 0)
      reaching.emplace_back(i, radius_m_[i] + speed_m_s * dt_s + tolerance);
    if (body.is_dynamic() && speed_m_s >= options_.sleep_speed_m_s)
      reaching.emplace_back(i, radius_m_[i] + speed_m_s * dt_s + fall_m + tolerance);
  }
  // The sleepers a moving body reaches (bounding balls), and in turn those they touched.
  for (const Contact& c : contacts_)  // (the last step's)
    for (const auto& [awake, other] : {std::pair(c.body_a, c.body_b), std::pair(c.body_b, c.body_a)})
      if (bodies_[awake].is_dynamic() && !asleep_[awake] && asleep_[other]) woken.push_back(other);
  if (!reaching.empty() && !sleepers.empty()) {
    std::vector<Eigen::AlignedBox3d> boxes;
    for (const auto& [i, reach_m] : reaching) boxes.push_back(ball_bounds(bodies_[i].X_WB.translation(), reach_m));
    for (int i : sleepers) boxes.push_back(ball_bounds(bodies_[i].X_WB.translation(), radius_m_[i]));
    const int r = static_cast<int>(reaching.size());
    for (const auto& [p, q] : collision::overlapping_pairs(boxes))
      if ((p < r) != (q < r)) woken.push_back(sleepers[std::max(p, q) - r]);
  }
  wake(std::move(woken));
  sleepers.erase(std::remove_if(sleepers.begin(), sleepers.end(), [&](int i) { return !asleep_[i]; }), sleepers.end());
  for (int i : sleepers) bodies_[i].motion = BodyMotion::kStatic;
  return sleepers;
}

void World::end_sleep_step(const std::vector<int>& held, double dt_s, StepReport& report) {
  for (int i : held) bodies_[i].motion = BodyMotion::kDynamic;
  const int n = static_cast<int>(bodies_.size());
  const auto awake = [&](int i) { return bodies_[i].is_dynamic() && !asleep_[i]; };
  for (int i = 0; i < n; ++i) {
    if (!awake(i)) continue;
    // (Counted in steps' worth of time: fifty 10 ms steps add up to just under 0.5 s.)
    quiet_s_[i] = point_speed_m_s(i) < options_.sleep_speed_m_s ? quiet_s_[i] + dt_s * (1 + 1e-9) : 0.0;
  }
  // Bodies in contact fall asleep together, once the last of them has been quiet long
  // enough: a body asleep against an awake one would be woken by it at once.
  DisjointSets islands(n);
  for (const Contact& c : contacts_)
    if (awake(c.body_a) && awake(c.body_b)) islands.join(c.body_a, c.body_b);
  std::vector<double> least_quiet_s(n, std::numeric_limits<double>::infinity());
  for (int i = 0; i < n; ++i)
    if (awake(i)) least_quiet_s[islands.find(i)] = std::min(least_quiet_s[islands.find(i)], quiet_s_[i]);
  std::vector<char> falling_asleep(n, 0);
  for (int i = 0; i < n; ++i) {
    if (!awake(i) || least_quiet_s[islands.find(i)] < options_.sleep_after_s) continue;
    falling_asleep[i] = 1;
    bodies_[i].v_WBcm_m_s.setZero();
    bodies_[i].w_WB_rad_s.setZero();
    touching_[i].clear();
  }
  for (const Contact& c : contacts_) {
    if (!bodies_[c.body_a].is_dynamic() || !bodies_[c.body_b].is_dynamic()) continue;
    if (falling_asleep[c.body_a]) touching_[c.body_a].push_back(c.body_b);
    if (falling_asleep[c.body_b]) touching_[c.body_b].push_back(c.body_a);
  }
  for (int i = 0; i < n; ++i) asleep_[i] |= falling_asleep[i];
  report.bodies_asleep = static_cast<int>(std::count(asleep_.begin(), asleep_.end(), 1));
}

StepReport World::step(double dt_s) {
  if (!(dt_s > 0) || !std::isfinite(dt_s)) throw std::invalid_argument("World::step: dt_s must be positive, got " + std::to_string(dt_s));
  StepReport report;
  const int n = static_cast<int>(bodies_.size());
  std::vector<int> everyone(n), fixed, dynamic;
  std::iota(everyone.begin(), everyone.end(), 0);
  set_kinematic_state(everyone, time_s_, dt_s);
  const std::vector<int> held = options_.sleep_after_s > 0 ? hold_sleepers(dt_s) : std::vector<int>();
  // (Should anything below throw, the sleepers are not left static.)
  struct Release {
    std::vector<RigidBody>& bodies;
    const std::vector<int>& held;
    ~Release() {
      for (int i : held) bodies[i].motion = BodyMotion::kDynamic;
    }
  } release{bodies_, held};
  for (int i = 0; i < n; ++i) {
    (bodies_[i].is_dynamic() ? dynamic : fixed).push_back(i);
  }
  // The step's first solve, for everything at once.
  apart_at_.clear();
  apart_at_last_end_ = std::move(apart_at_end_);
  apart_at_end_.clear();
  crossing_tests_ = 0;
  for (auto it = nearby_.begin(); it != nearby_.end();) {
    if (!it->second.used) {
      it = nearby_.erase(it);
    } else {
      it->second.used = false;
      ++it;
    }
  }
  pending_bounces_ = std::move(next_bounces_);
  next_bounces_.clear();
  std::stable_sort(pending_bounces_.begin(), pending_bounces_.end(),
                   [](const PendingBounce& x, const PendingBounce& y) { return x.bodies < y.bodies; });
  const std::vector<Contact> resting = gather_contacts(everyone);
  std::vector<Contact> solved;
  SolvedIslands islands_at_start;
  const std::vector<BodyVelocity> u0 = solve(prepare_solve(dt_s, dt_s, everyone, resting), everyone, resting, {}, solved,
                                             report, nullptr, &islands_at_start);
  const std::vector<geometry::Pose> next0 = candidate_poses(everyone, u0, 0, dt_s);

  // Groups: dynamic bodies in contact, or whose swept boxes overlap, may meet within the
  // step; bodies of different groups cannot, so each group is stepped on its own, its
  // events cutting only its own step and re-running only its own CCD. (Stepping them all
  // together made every time of impact in a 1000-box pile re-solve and re-sweep all of
  // it.) A group whose re-solved motion strays into another's sweep is merged with it and
  // both are stepped again.
  DisjointSets groups(n);
  const auto root = [&](int i) { return groups.find(i); };
  const auto join = [&](int i, int j) {
    if (bodies_[i].is_dynamic() && bodies_[j].is_dynamic()) groups.join(i, j);
  };
  for (const Contact& c : resting) join(c.body_a, c.body_b);
  std::vector<Eigen::AlignedBox3d> swept0(n);  // each body's swept box over the first solve's motion
  for (int i = 0; i < n; ++i) swept0[i] = swept_box(i, next0[i]);
  const std::vector<std::pair<int, int>> swept_pairs0 = collision::overlapping_pairs(swept0);
  for (const auto& [i, j] : swept_pairs0) join(i, j);  // (joins dynamic bodies only)
  // The first CCD pass, for everything at once (the same pairs the groups would sweep):
  // most groups meet nothing and just move; only the others are stepped on their own.
  ImpactCache first_ccd;
  const std::vector<std::pair<int, int>> resting_pairs = pairs_of(resting);
  earliest_impact(everyone, next0, &resting_pairs, nullptr, &first_ccd, nullptr, report, &swept_pairs0);
  std::set<int> eventful;
  for (const auto& [pair, query] : first_ccd) {
    if (query.deepens || meets_inside(query.result))
      eventful.insert(root(bodies_[pair.first].is_dynamic() ? pair.first : pair.second));
  }

  struct State {
    geometry::Pose X_WB;
    Eigen::Vector3d v, w;
  };
  std::vector<State> start(n);
  for (int i : dynamic) start[i] = {bodies_[i].X_WB, bodies_[i].v_WBcm_m_s, bodies_[i].w_WB_rad_s};
  std::vector<Eigen::AlignedBox3d> moved(n);        // each dynamic body's swept box over the step
  std::vector<char> stepped(n, 0);                  // by group root: stepped on its own
  std::vector<std::vector<Contact>> contacts_of(n);  // by group root: its last solve, when stepped
  std::vector<int> pending;                          // group roots to step
  for (int i : dynamic)
    if (root(i) == i) pending.push_back(i);
  while (!pending.empty()) {
    // The pending groups' bodies, group by group, in body order.
    std::vector<std::pair<int, int>> members;  // (root, body)
    for (int i : dynamic)
      if (std::binary_search(pending.begin(), pending.end(), root(i))) members.emplace_back(root(i), i);
    std::sort(members.begin(), members.end());
    std::vector<std::vector<int>> resting_of(n);  // by root, for the groups stepped on their own
    for (std::size_t k = 0; k < resting.size(); ++k) {
      const Contact& c = resting[k];
      const int g = root(bodies_[c.body_a].is_dynamic() ? c.body_a : c.body_b);
      if (stepped[g] || eventful.count(g)) resting_of[g].push_back(static_cast<int>(k));
    }
    for (std::size_t first_member = 0; first_member < members.size();) {
      const int g = members[first_member].first;
      std::vector<int> bodies;
      for (; first_member < members.size() && members[first_member].first == g; ++first_member)
        bodies.push_back(members[first_member].second);
      if (stepped[g]) {
        // Stepped before, merged since: start again from the step's start (and forget the
        // bounces that pass held back: this one finds its own).
        const auto in_group = [&](int i) { return bodies_[i].is_dynamic() && root(i) == g; };
        next_bounces_.erase(std::remove_if(next_bounces_.begin(), next_bounces_.end(),
                                           [&](const PendingBounce& p) {
                                             return in_group(p.bodies.first) || in_group(p.bodies.second);
                                           }),
                            next_bounces_.end());
        for (int i : bodies) {
          bodies_[i].X_WB = start[i].X_WB;
          bodies_[i].v_WBcm_m_s = start[i].v;
          bodies_[i].w_WB_rad_s = start[i].w;
        }
      } else if (!eventful.count(g)) {
        for (int i : bodies) {
          moved[i] = swept0[i];
          bodies_[i].X_WB = next0[i];
          bodies_[i].v_WBcm_m_s = u0[i].v_WBcm_m_s;
          bodies_[i].w_WB_rad_s = u0[i].w_WB_rad_s;
        }
        continue;
      }
      std::vector<int> participants;
      std::merge(bodies.begin(), bodies.end(), fixed.begin(), fixed.end(), std::back_inserter(participants));
      FirstSolve f{{}, {}, {}, islands_at_start};
      f.u.reserve(participants.size());
      for (int i : participants) f.u.push_back(u0[i]);
      f.resting.reserve(resting_of[g].size());
      f.solved.reserve(resting_of[g].size());
      for (int k : resting_of[g]) {
        f.resting.push_back(resting[k]);
        f.solved.push_back(solved[k]);
      }
      GroupOutcome outcome = advance_group(dt_s, participants, f, first_ccd, report);
      stepped[g] = 1;
      contacts_of[g] = std::move(outcome.contacts);
      for (std::size_t s = 0; s < participants.size(); ++s)
        if (bodies_[participants[s]].is_dynamic()) moved[participants[s]] = outcome.swept[s];
    }
    // Did any group's motion reach into another's? (Only a group stepped on its own can
    // have left the sweep it was grouped by.)
    if (std::none_of(members.begin(), members.end(), [&](const auto& m) { return stepped[root(m.second)]; })) break;
    // One group (a pile come to rest on itself): there is no other to reach.
    const int first_root = root(dynamic.front());
    if (std::all_of(dynamic.begin(), dynamic.end(), [&](int i) { return root(i) == first_root; })) break;
    // The other groups' boxes are their first sweeps, which overlap no other group's: only
    // a pair with a stepped group's body can join two groups.
    std::vector<Eigen::AlignedBox3d> boxes;
    std::vector<char> of_stepped;
    boxes.reserve(dynamic.size());
    for (int i : dynamic) {
      boxes.push_back(moved[i]);
      of_stepped.push_back(stepped[root(i)]);
    }
    pending.clear();
    for (const auto& [p, q] : collision::overlapping_pairs_involving(boxes, of_stepped)) {
      const int i = dynamic[p], j = dynamic[q];
      if (root(i) == root(j)) continue;
      join(i, j);
      stepped[root(i)] = 1;  // its bodies restart from the step's start
      pending.push_back(root(i));
    }
    for (int& g : pending) g = root(g);
    std::sort(pending.begin(), pending.end());
    pending.erase(std::unique(pending.begin(), pending.end()), pending.end());
  }
  // The contacts of each group's last solve: the first solve's, unless stepped on its own.
  contacts_.clear();
  for (std::size_t k = 0; k < resting.size(); ++k) {
    const Contact& c = resting[k];
    if (!stepped[root(bodies_[c.body_a].is_dynamic() ? c.body_a : c.body_b)]) contacts_.push_back(solved[k]);
  }
  for (int i : dynamic)
    if (root(i) == i && stepped[i]) contacts_.insert(contacts_.end(), contacts_of[i].begin(), contacts_of[i].end());
  report.contacts = static_cast<int>(contacts_.size());
  pushed_before_.clear();
  for (const Contact& c : contacts_)
    if (c.impulse_N_s > 0)
      pushed_before_.push_back({{std::min(c.body_a, c.body_b), std::max(c.body_a, c.body_b)},
                                row_point(c.feature)});
  std::sort(pushed_before_.begin(), pushed_before_.end(),
            [](const PushedPoint& x, const PushedPoint& y) { return x.bodies < y.bodies; });
  // Kept only where a solve can use them: the iterative solver, an exact solver's island
  // too large for it (max_exact_rows), and the exact solver's friction sweeps. (Kept
  // always, they made a 100-box drop, where every island is small and exact, 10 % slower.)
  warm_forces_.clear();
  const bool iterative = options_.solver.kind == ContactSolverKind::kProjectedGaussSeidel || report.iterative_islands > 0;
  for (const Contact& c : solved)
    if (c.impulse_N_s > 0 && (iterative || combined_friction(bodies_[c.body_a], bodies_[c.body_b]) > 0))
      warm_forces_.push_back({{std::min(c.body_a, c.body_b), std::max(c.body_a, c.body_b)}, row_point(c.feature),
                              c.impulse_W_N_s / dt_s});
  std::sort(warm_forces_.begin(), warm_forces_.end(),
            [](const PreviousForce& x, const PreviousForce& y) { return x.bodies < y.bodies; });
  if (options_.sleep_after_s > 0) end_sleep_step(held, dt_s, report);
  time_s_ += dt_s;
  placed_since_step_.assign(bodies_.size(), 0);
  placed_to_wake_.assign(bodies_.size(), 0);
  set_kinematic_state(everyone, time_s_, 0.0);
  report.mesh_crossing_tests = crossing_tests_;
  return report;
}

}  // namespace arphys::dynamics
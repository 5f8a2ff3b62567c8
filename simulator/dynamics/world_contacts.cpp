// The contacts at the current poses and the constrained solve of a step (Gauss's
// principle; simulator/dynamics/contact_solver.hpp). The stage before: the step itself
// (world.cpp); the stage after: sweeping the motions the solve gives (world_impacts.cpp).
#include "simulator/dynamics/world.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "simulator/collision/broad_phase.hpp"
#include "simulator/collision/shape_query.hpp"
#include "simulator/dynamics/disjoint_sets.hpp"
#include "simulator/dynamics/manifold_reduction.hpp"
#include "simulator/dynamics/world_internal.hpp"

namespace arphys::dynamics {

using world_internal::ball_bounds;
using world_internal::combined_friction;
using world_internal::depth_measured;
using world_internal::row_point;
using world_internal::slot_of;

namespace {

// The angular velocity after h_s of torque-free motion.
Eigen::Vector3d gyroscopic_step(const Eigen::Matrix3d& I_W, const Eigen::Vector3d& w_WB_rad_s, double h_s) {
  // Implicit midpoint on I (w' - w) + h m x I m = 0, m = (w + w') / 2, by Newton from
  // w' = w: with the inertia held over the step it keeps the kinetic energy and the
  // angular momentum's size (both quadratic invariants). The explicit step
  // w' = w - h I^-1 (w x I w) gains energy: a box spinning at 30 rad/s near its
  // intermediate axis reached 320 rad/s in 5 s at h = 10 ms, and bunnies tumbling off the
  // table fell twice as fast as free fall. (Backward Euler, one Newton step, is stable
  // but lost half the angular momentum over the same 5 s.)
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

std::vector<Contact> World::gather_contacts(const std::vector<int>& participants) const {
  const double tolerance = options_.contact_tolerance_m;
  std::vector<Eigen::AlignedBox3d> boxes;
  boxes.reserve(participants.size());
  for (int i : participants) boxes.push_back(ball_bounds(bodies_[i].X_WB.translation(), radius_m_[i] + tolerance));
  std::vector<std::pair<int, int>> pairs;
  for (const auto& [p, q] : collision::overlapping_pairs(boxes)) {
    const RigidBody& a = bodies_[participants[p]];
    const RigidBody& b = bodies_[participants[q]];
    if (!a.is_dynamic() && !b.is_dynamic()) continue;
    if (a.shape.type() == collision::Shape::Type::kPlane && b.shape.type() == collision::Shape::Type::kPlane) continue;
    pairs.emplace_back(participants[p], participants[q]);
  }
  // A depth-measured pair's manifold depends on its poses alone: on the worker threads,
  // each into its own slot. Mesh pairs share memos (nearby_, apart_at_): in order, here.
  std::vector<std::vector<collision::ManifoldPoint>> features(pairs.size());
  pool_.for_each(static_cast<int>(pairs.size()), [&](int k) {
    const RigidBody& a = bodies_[pairs[k].first];
    const RigidBody& b = bodies_[pairs[k].second];
    if (depth_measured(a, b))
      features[k] = reduce_manifold(collision::contact_manifold(a.shape, a.X_WB, b.shape, b.X_WB, tolerance),
                                    options_.max_contacts_per_pair);
  });
  std::vector<Contact> contacts;
  // (About as many as the last step had: grown from empty, a 1000-box pile's thousands of
  // contacts were copied a dozen times over.)
  contacts.reserve(participants.size() == bodies_.size() ? contacts_.size() + contacts_.size() / 4 : 0);
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const auto [i, j] = pairs[k];
    if (!depth_measured(bodies_[i], bodies_[j])) features[k] = mesh_pair_features(i, j);
    append_contacts(i, j, features[k], contacts);
  }
  return contacts;
}

std::vector<collision::ManifoldPoint> World::mesh_pair_features(int i, int j) const {
  const RigidBody& a = bodies_[i];
  const RigidBody& b = bodies_[j];
  collision::NearbyTrianglePairs* nearby = nearby_pairs(i, j);
  const std::vector<collision::ManifoldPoint> manifold =
      collision::contact_manifold(a.shape, a.X_WB, b.shape, b.X_WB, options_.contact_tolerance_m, nearby);
  std::vector<collision::ManifoldPoint> features = reduce_manifold(manifold, options_.max_contacts_per_pair);
  bool apart = false;
  const bool placed = placed_since_step_[i] || placed_since_step_[j] || placed_crossing_.count({i, j});
  // (Proven apart at these poses where the last step ended: see apart_at_end_.)
  const bool ended_apart = known_apart(apart_at_last_end_, i, j, a.X_WB, b.X_WB);
  const auto crossing = ended_apart ? std::nullopt : mesh_crossing_depth(a, b, manifold, &apart, nearby, placed);
  apart |= ended_apart;
  if (apart) apart_at_[{i, j}] = {a.X_WB, b.X_WB};  // (i < j: participants are sorted)
  if (crossing && placed) {
    placed_crossing_.insert({i, j});
  } else if (!crossing) {
    placed_crossing_.erase({i, j});
  }
  if (crossing) {
    // The crossing features' normals point to the side their vertex is on, which for
    // a vertex gone through is the wrong one: such rows held the pair crossed (the
    // push out was infeasible against them). Those opposing the way out are dropped.
    features.erase(std::remove_if(features.begin(), features.end(),
                                  [&](const auto& f) { return f.normal_W.dot(crossing->normal_W) < 0; }),
                   features.end());
    features.push_back(*crossing);
  }
  return features;
}

namespace {
// A held-back bounce acts on the pair's contacts whose normals are within about 25 degrees of
// the meeting's (the pair turns a little over the step it waited).
constexpr double kSameBounceNormal = 0.9;
}  // namespace

void World::append_contacts(int i, int j, const std::vector<collision::ManifoldPoint>& features,
                            std::vector<Contact>& contacts) const {
  const double tolerance = options_.contact_tolerance_m;
  const std::pair<int, int> key{std::min(i, j), std::max(i, j)};
  const auto pushed = std::lower_bound(pushed_before_.begin(), pushed_before_.end(), key,
                                       [](const PushedPoint& p, const std::pair<int, int>& k) { return p.bodies < k; });
  const auto warm = std::lower_bound(warm_forces_.begin(), warm_forces_.end(), key,
                                     [](const PreviousForce& p, const std::pair<int, int>& k) { return p.bodies < k; });
  const auto bounces =
      std::lower_bound(pending_bounces_.begin(), pending_bounces_.end(), key,
                       [](const PendingBounce& p, const std::pair<int, int>& k) { return p.bodies < k; });
  for (const auto& feature : features) {
    Contact contact{i, j, feature, 0.0};
    const Eigen::Vector3d point_W = row_point(feature);
    for (auto it = pushed; it != pushed_before_.end() && it->bodies == key && !contact.pushed_before; ++it)
      contact.pushed_before = (it->point_W - point_W).norm() <= tolerance;
    // (Held back for the pair as (i, j): its normal points from i to j, as the feature's does.)
    for (auto it = bounces; it != pending_bounces_.end() && it->bodies == key; ++it)
      if (key == std::make_pair(i, j) && it->normal_W.dot(feature.normal_W) > kSameBounceNormal)
        contact.min_normal_velocity_m_s = std::max(contact.min_normal_velocity_m_s, it->speed_m_s);
    double nearest_m = tolerance;
    for (auto it = warm; it != warm_forces_.end() && it->bodies == key; ++it)
      if (const double d = (it->point_W - point_W).norm(); d <= nearest_m) {
        nearest_m = d;
        contact.warm_force_W_N = it->force_W_N;
      }
    contacts.push_back(contact);
  }
}

std::optional<collision::ManifoldPoint> World::mesh_crossing_depth(const RigidBody& a, const RigidBody& b,
                                                                  const std::vector<collision::ManifoldPoint>& manifold,
                                                                  bool* apart,
                                                                  collision::NearbyTrianglePairs* nearby,
                                                                  bool placed) const {
  // Only pairs within the contact tolerance (with a manifold) can cross, once stepped.
  // (Their features do not show it: a mesh's distances are unsigned, and crossing edges
  // pass through faces, not through edges: two bunnies 0.3 mm into each other had none
  // closer than 5 um.)
  if (manifold.empty() && !placed) return std::nullopt;
  const collision::CollisionMesh& mesh_a = *a.shape.triangles();
  const collision::CollisionMesh& mesh_b = *b.shape.triangles();
  // (The answer "apart" is shared with the CCD of the pair's motions from these poses:
  // see apart_at_.)
  ++crossing_tests_;
  const auto crossing = collision::find_intersection(mesh_a, a.X_WB, mesh_b, b.X_WB, nearby);
  if (!crossing) {
    if (apart) *apart = true;
    return std::nullopt;
  }
  Eigen::Vector3d ta[3], tb[3];
  mesh_a.corners(crossing->triangle_A, ta);
  mesh_b.corners(crossing->triangle_B, tb);
  for (auto& corner : ta) corner = a.X_WB * corner;
  for (auto& corner : tb) corner = b.X_WB * corner;
  // Directions to try, both ways: the crossing triangles' normals and the line between
  // the bodies' centres of mass (a triangle's normal can lie along the crossing, where
  // no shift clears it).
  const Eigen::Vector3d line_W = b.com_W() - a.com_W();
  std::vector<Eigen::Vector3d> directions = {(ta[1] - ta[0]).cross(ta[2] - ta[0]).normalized(),
                                             (tb[1] - tb[0]).cross(tb[2] - tb[0]).normalized()};
  if (line_W.norm() > 0) directions.push_back(line_W.normalized());
  const auto clears = [&](const Eigen::Vector3d& shift_W) {
    geometry::Pose X_B = b.X_WB;
    X_B.translation() += shift_W;
    return !collision::intersects(mesh_a, a.X_WB, mesh_b, X_B);
  };
  // How far B must move (the shortest of those ways, to a factor of two) to clear A.
  for (double shift_m = options_.overlap_tolerance_m; shift_m <= kDeepestCrossingMeasured_m; shift_m *= 2)
    for (const Eigen::Vector3d& direction : directions)
      for (const double sign : {1.0, -1.0}) {
        if (!clears(sign * shift_m * direction)) continue;
        // Where the triangles cross; for a placed pair (see placed_crossing_) at the dynamic
        // body's centre of mass (midway between two dynamic ones'): the crossing
        // triangles can be anywhere on either (a table's top triangle spans the table),
        // and a push at their middle turned a sunken cube about its rim instead of
        // lifting it. (Pushed so, bunnies that a stepped pile leaves a few micrometres
        // inside the table or the box crossed each other ten times as often.)
        Eigen::Vector3d where = (ta[0] + ta[1] + ta[2] + tb[0] + tb[1] + tb[2]) / 6.0;
        if (placed && !a.is_dynamic()) {
          where = b.com_W();
        } else if (placed && !b.is_dynamic()) {
          where = a.com_W();
        } else if (placed) {
          where = 0.5 * (a.com_W() + b.com_W());
        }
        return collision::ManifoldPoint{where, where, sign * direction, -shift_m, *crossing};
      }
  return std::nullopt;
}

std::vector<Contact> World::impact_contacts(const ImpactMap& impacts) const {
  // Where the CCD found pairs meeting within the step: the material points that meet
  // (fixed in each body at the time of impact) and the normal there, at the current poses.
  std::vector<Contact> contacts;
  for (const auto& [pair, hits] : impacts) {
    const RigidBody& a = bodies_[pair.first];
    const RigidBody& b = bodies_[pair.second];
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

World::SolveSetup World::prepare_solve(double h, double force_h, const std::vector<int>& participants,
                                      const std::vector<Contact>& resting) const {
  SolveSetup setup;
  setup.h = h;
  setup.warm_h_s = force_h > 0 ? h : 0.0;
  setup.unknown_of_slot.assign(participants.size(), -1);
  for (std::size_t s = 0; s < participants.size(); ++s) {
    const RigidBody& body = bodies_[participants[s]];
    if (!body.is_dynamic()) continue;
    setup.unknown_of_slot[s] = static_cast<int>(setup.u_unconstrained.size());
    setup.slot_of_unknown.push_back(static_cast<int>(s));
    setup.body_of_unknown.push_back(participants[s]);
    BodyInertia in;
    in.inverse_mass_1_kg = 1.0 / body.mass.mass_kg;
    in.inverse_inertia_W = body.inverse_inertia_W();
    in.com_W = body.com_W();
    setup.inertia.push_back(in);
    // Unconstrained: gravity, and the gyroscopic term I dw/dt = -w x I w, implicitly.
    BodyVelocity v;
    v.v_WBcm_m_s = body.v_WBcm_m_s + force_h * options_.gravity_m_s2;
    v.w_WB_rad_s = gyroscopic_step(body.inertia_W(), body.w_WB_rad_s, force_h);
    setup.u_unconstrained.push_back(v);
  }
  setup.resting_rows.reserve(resting.size());
  for (const Contact& c : resting) {
    setup.resting_rows.push_back(row_of(c, setup, participants));
    setup.deepest_m = std::max(setup.deepest_m, -c.feature.distance_m);
  }
  return setup;
}

ContactRow World::row_of(const Contact& c, const SolveSetup& setup, const std::vector<int>& participants) const {
  const auto unknown = [&](int body) {
    const int slot = slot_of(participants, body);
    return slot < 0 ? -1 : setup.unknown_of_slot[slot];
  };
  const double h = setup.h;
  const RigidBody& a = bodies_[c.body_a];
  const RigidBody& b = bodies_[c.body_b];
  ContactRow row;
  row.body_a = unknown(c.body_a);
  row.body_b = unknown(c.body_b);
  row.normal_W = c.feature.normal_W;
  row.point_W = row_point(c.feature);
  // The non-dynamic bodies' point velocities (a dynamic body's are unknowns of the solve).
  const Eigen::Vector3d v_a = a.is_dynamic() ? Eigen::Vector3d::Zero() : a.velocity_of_point(row.point_W);
  const Eigen::Vector3d v_b = b.is_dynamic() ? Eigen::Vector3d::Zero() : b.velocity_of_point(row.point_W);
  row.known_normal_velocity_m_s = -row.normal_W.dot(v_a) + row.normal_W.dot(v_b);
  const Eigen::Vector3d known_W = v_b - v_a;
  row.known_tangent_velocity_W_m_s = known_W - row.normal_W.dot(known_W) * row.normal_W;
  const double gap = c.feature.distance_m;
  // Close at most to the resting gap within h; undo an overlap, but not violently.
  row.min_normal_velocity_m_s = std::min(-(gap - options_.contact_gap_m) / h, options_.max_depenetration_speed_m_s);
  // An impact: closing fast enough to bounce and, at that speed, meeting within h.
  // The bounce then happens at the step boundary, as the velocity update of a
  // symplectic Euler step, which keeps an elastic ball's apex.
  const double approach = row.normal_W.dot(b.velocity_of_point(row.point_W) - a.velocity_of_point(row.point_W));
  if (approach < -options_.restitution_threshold_m_s && -approach * h >= gap - options_.contact_gap_m)
    row.min_normal_velocity_m_s = std::max(row.min_normal_velocity_m_s, -std::max(a.restitution, b.restitution) * approach);
  row.min_normal_velocity_m_s = std::max(row.min_normal_velocity_m_s, c.min_normal_velocity_m_s);
  row.friction = combined_friction(a, b);
  row.pushed_before = c.pushed_before;
  row.warm_impulse_W_N_s = setup.warm_h_s * c.warm_force_W_N;
  return row;
}

std::vector<BodyVelocity> World::solve(const SolveSetup& setup, const std::vector<int>& participants,
                                       const std::vector<Contact>& resting, const ImpactMap& impacts,
                                       std::vector<Contact>& solved, StepReport& report, bool* infeasible,
                                       SolvedIslands* memo) const {
  const std::vector<Contact> meeting = impact_contacts(impacts);
  solved.clear();
  solved.reserve(resting.size() + meeting.size());
  solved.insert(solved.end(), resting.begin(), resting.end());
  solved.insert(solved.end(), meeting.begin(), meeting.end());
  std::vector<BodyVelocity> u = setup.u_unconstrained;
  std::vector<ContactRow> rows;
  rows.reserve(solved.size());
  rows.insert(rows.end(), setup.resting_rows.begin(), setup.resting_rows.end());
  for (const Contact& c : meeting) rows.push_back(row_of(c, setup, participants));
  // The resting contacts' overlaps only: a meeting's material points, taken at the start
  // poses, say how they will meet, not that they overlap (a turning pair's can be half a
  // millimetre "deep" there while nothing overlaps at any time).
  report.max_penetration_m = std::max(report.max_penetration_m, setup.deepest_m);
  const std::vector<BodyVelocity>& u_unconstrained = setup.u_unconstrained;
  const std::vector<int>& slot_of_unknown = setup.slot_of_unknown;
  const ContactSolveResult result = solve_contacts(setup.inertia, u, rows, options_.solver, memo, &setup.body_of_unknown);
  // Launch guard. Contacts are passive: with restitution <= 1 a solve can at most
  // reverse (and pass on) the fastest motion among the bodies it couples, plus what
  // moving non-dynamic bodies and depenetration impose. A body left with more kinetic
  // energy than twice that speed gives it (or non-finite) marks a solver failure (a
  // degenerate squeeze, an ill-conditioned frictional island): it is slowed to the
  // bound, never launched, never NaN, and counted. The speed a body's energy gives it,
  // sqrt(|v|^2 + w.I.w / m), not its point speed |v| + |w| r: an off-centre impact
  // rightly turns a fall into a spin whose point speed (r the bounding radius about the
  // body origin) is several times the fall's: every bunny of the 20-bunny scene landing
  // on one point was held back at 56 % of its correct motion, from an exact solve.
  DisjointSets island(static_cast<int>(u.size()));
  const auto root = [&](int k) { return island.find(k); };
  for (const ContactRow& row : rows) {
    if (row.body_a >= 0 && row.body_b >= 0) island.join(row.body_a, row.body_b);
  }
  std::vector<double> radius(u.size(), 0.0), island_speed(u.size(), 0.0);
  for (std::size_t k = 0; k < u.size(); ++k) radius[k] = radius_m_[participants[slot_of_unknown[k]]];
  const auto point_speed = [&](const BodyVelocity& v, std::size_t k) { return v.v_WBcm_m_s.norm() + v.w_WB_rad_s.norm() * radius[k]; };
  const auto energy_speed = [&](const BodyVelocity& v, std::size_t k) {
    const RigidBody& body = bodies_[setup.body_of_unknown[k]];
    const double turning = v.w_WB_rad_s.dot(body.inertia_W() * v.w_WB_rad_s) / body.mass.mass_kg;
    return std::sqrt(v.v_WBcm_m_s.squaredNorm() + std::max(0.0, turning));
  };
  for (std::size_t k = 0; k < u.size(); ++k) {
    const double speed = point_speed(u_unconstrained[k], k);
    if (std::isfinite(speed)) island_speed[root(static_cast<int>(k))] = std::max(island_speed[root(static_cast<int>(k))], speed);
  }
  for (const ContactRow& row : rows) {
    const int k = row.body_a >= 0 ? row.body_a : row.body_b;
    if (k >= 0 && std::isfinite(row.known_normal_velocity_m_s)) {
      island_speed[root(k)] = std::max(island_speed[root(k)], std::abs(row.known_normal_velocity_m_s));
    }
  }
  for (std::size_t k = 0; k < u.size(); ++k) {
    // Twice the island's fastest motion bounds one solve, not a sequence of them: a body
    // bumped a little faster every step would still run away. max_body_speed_m_s caps
    // its points' speed absolutely (a desk-scale scene has nothing faster).
    const double bound = 2.0 * island_speed[root(static_cast<int>(k))] + options_.max_depenetration_speed_m_s +
                         options_.launch_guard_slack_m_s;
    const double energy = energy_speed(u[k], k), speed = point_speed(u[k], k);
    if (std::isfinite(energy) && std::isfinite(speed) && energy <= bound && speed <= options_.max_body_speed_m_s) continue;
    if (std::isfinite(energy) && std::isfinite(speed)) {
      const double scale = std::min(energy > bound ? bound / energy : 1.0,
                                    speed > options_.max_body_speed_m_s ? options_.max_body_speed_m_s / speed : 1.0);
      u[k].v_WBcm_m_s *= scale;
      u[k].w_WB_rad_s *= scale;
    } else {
      u[k] = u_unconstrained[k];
    }
    ++report.launches_prevented;
  }
  report.kkt_residual_m_s = std::max(report.kkt_residual_m_s, result.kkt_residual_m_s);
  report.infeasible |= result.infeasible;
  if (infeasible) *infeasible = result.infeasible;
  report.iterative_islands += result.iterative_islands;
  report.solver_iterations += result.iterations;
  for (std::size_t k = 0; k < solved.size(); ++k) {
    solved[k].impulse_N_s = result.normal_impulses_N_s[k];
    solved[k].impulse_W_N_s = result.impulses_W_N_s[k];
  }
  std::vector<BodyVelocity> by_slot(participants.size());
  for (std::size_t k = 0; k < u.size(); ++k) by_slot[slot_of_unknown[k]] = u[k];
  return by_slot;
}

}  // namespace arphys::dynamics

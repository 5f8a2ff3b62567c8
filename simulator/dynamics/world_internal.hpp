#pragma once
// What World's files and its stages share. The stages with typed inputs and outputs:
// step_contacts.hpp (the contacts at the current poses), step_solve.hpp (the constrained
// velocities), step_sweep.hpp (the CCD and end checks of the motions). World's own files:
// world.cpp the bodies, the step's first pass and its groups; world_group.cpp a group's
// parts (rounds of re-solves, cuts); world_impacts.cpp lifts of too-deep points and where
// to cut; world_sleep.cpp sleep. Not part of the library's interface.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "simulator/collision/continuous_query.hpp"
#include "simulator/collision/discrete_query.hpp"
#include "simulator/dynamics/rigid_body.hpp"
#include "simulator/dynamics/world.hpp"

namespace arphys::dynamics::world_internal {

// The axis-aligned box of the ball about `centre` (all of space for an unbounded body).
inline Eigen::AlignedBox3d ball_bounds(const Eigen::Vector3d& centre, double radius) {
  if (!std::isfinite(radius)) {
    const double inf = std::numeric_limits<double>::infinity();
    return Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-inf), Eigen::Vector3d::Constant(inf));
  }
  return Eigen::AlignedBox3d(centre.array() - radius, centre.array() + radius);
}

// The CCD says the pair meets inside the motion (a time of impact the step can be cut at).
inline bool meets_inside(const collision::ContinuousResult& r) {
  return r.collides && r.time_of_impact > 0 && r.features.kind != collision::FeaturePair::kOverlapAtStart;
}

// Where a contact's constraint row acts: midway between its two features' points (they
// can be millimetres apart along the surface on a sliding pair).
inline Eigen::Vector3d row_point(const collision::ManifoldPoint& feature) { return 0.5 * (feature.point_A_W + feature.point_B_W); }

// Whether the pair's contact manifold measures how deep the bodies overlap (signed
// distances): every pair but those of a mesh with a mesh or a box.
inline bool depth_measured(const RigidBody& a, const RigidBody& b) {
  const auto is_mesh = [](const RigidBody& body) { return body.shape.type() == collision::Shape::Type::kMesh; };
  return !(is_mesh(a) || is_mesh(b)) || !a.shape.triangles() || !b.shape.triangles();
}

// A participant's place in the (sorted) participants, -1 if it is not one.
inline int slot_of(const std::vector<int>& participants, int body) {
  const auto it = std::lower_bound(participants.begin(), participants.end(), body);
  return it != participants.end() && *it == body ? static_cast<int>(it - participants.begin()) : -1;
}

// The Coulomb coefficient of a pair: the geometric mean of the two bodies', or the one given.
inline double combined_friction(const RigidBody& a, const RigidBody& b) {
  if (a.friction && b.friction) return std::sqrt(*a.friction * *b.friction);
  if (a.friction) return *a.friction;
  if (b.friction) return *b.friction;
  return 0;
}

// The body pairs of the contacts, sorted, once each.
inline std::vector<std::pair<int, int>> pairs_of(const std::vector<Contact>& contacts) {
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(contacts.size());
  for (const Contact& c : contacts) pairs.emplace_back(std::min(c.body_a, c.body_b), std::max(c.body_a, c.body_b));
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

}  // namespace arphys::dynamics::world_internal

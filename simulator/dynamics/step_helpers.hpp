#pragma once
// Small functions World's files and the step's stages share: preconditions, geometry of a
// row, pair bookkeeping. Not part of the library's interface.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "simulator/collision/continuous_query.hpp"
#include "simulator/collision/discrete_query.hpp"
#include "simulator/dynamics/contact.hpp"
#include "simulator/dynamics/world_model.hpp"

namespace arphys::dynamics::step_helpers {

// A stage's precondition on the size of one of its inputs: std::invalid_argument naming the
// stage, the input, its size and the size expected.
inline void require_size(const char* stage, const char* input, std::size_t size, std::size_t expected) {
  if (size != expected)
    throw std::invalid_argument(std::string(stage) + ": " + input + " has " + std::to_string(size) +
                                " entries, expected " + std::to_string(expected));
}

// A stage's participants: body indices, increasing, each below n_bodies (std::invalid_argument
// naming the stage and the first that is not).
inline void require_participants(const char* stage, const std::vector<int>& participants, std::size_t n_bodies) {
  for (std::size_t s = 0; s < participants.size(); ++s)
    if (participants[s] < 0 || static_cast<std::size_t>(participants[s]) >= n_bodies ||
        (s > 0 && participants[s] <= participants[s - 1]))
      throw std::invalid_argument(std::string(stage) + ": participant " + std::to_string(s) + " is body " +
                                  std::to_string(participants[s]) + ", expected increasing indices below " +
                                  std::to_string(n_bodies));
}

// A stage's world: a state for each of the model's bodies, and a bounding radius each
// (std::invalid_argument naming the stage otherwise).
inline void require_model(const char* stage, const WorldModel& model, const std::vector<BodyState>& state) {
  require_size(stage, "state", state.size(), model.bodies.size());
  require_size(stage, "model.radius_m", model.radius_m.size(), model.bodies.size());
}

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
inline Eigen::Vector3d row_point(const collision::ManifoldPoint& feature) {
  return 0.5 * (feature.point_A_W + feature.point_B_W);
}

// Whether the pair's contact manifold measures how deep the bodies overlap (signed
// distances): every pair but those of a mesh with a mesh or a box.
inline bool depth_measured(const BodyModel& a, const BodyModel& b) {
  const auto is_mesh = [](const BodyModel& body) { return body.shape.type() == collision::Shape::Type::kMesh; };
  return !(is_mesh(a) || is_mesh(b)) || !a.shape.triangles() || !b.shape.triangles();
}

// A participant's place in the (sorted) participants, -1 if it is not one.
inline int slot_of(const std::vector<int>& participants, int body) {
  const auto it = std::lower_bound(participants.begin(), participants.end(), body);
  return it != participants.end() && *it == body ? static_cast<int>(it - participants.begin()) : -1;
}

// The Coulomb coefficient of a pair: the geometric mean of the two bodies', or the one given.
inline double combined_friction(const BodyModel& a, const BodyModel& b) {
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

}  // namespace arphys::dynamics::step_helpers

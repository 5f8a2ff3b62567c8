// The contacts stage of a step: manifolds of the pairs within reach, their hints, and the
// crossing contacts of mesh pairs.
#include "simulator/dynamics/step_contacts.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "simulator/collision/broad_phase.hpp"
#include "simulator/collision/shape_query.hpp"
#include "simulator/dynamics/manifold_reduction.hpp"
#include "simulator/dynamics/step_helpers.hpp"

namespace arphys::dynamics {

using step_helpers::ball_bounds;
using step_helpers::depth_measured;
using step_helpers::row_point;

bool MeshCrossingMemo::known_apart(const std::map<BodyPair, ApartAt>& known, int i, int j, const geometry::Pose& X_WA,
                                   const geometry::Pose& X_WB) {
  const auto it = known.find({i, j});
  return it != known.end() && it->second.X_WA.matrix() == X_WA.matrix() && it->second.X_WB.matrix() == X_WB.matrix();
}

collision::NearbyTrianglePairs* MeshCrossingMemo::nearby_pairs(int i, int j) {
  Nearby& entry = nearby[{std::min(i, j), std::max(i, j)}];
  entry.used = true;
  return &entry.pairs;
}

void MeshCrossingMemo::begin_step() {
  apart_at.clear();
  apart_at_last_end = std::move(apart_at_end);
  apart_at_end.clear();
  crossing_tests = 0;
  for (auto it = nearby.begin(); it != nearby.end();) {
    if (!it->second.used) {
      it = nearby.erase(it);
    } else {
      it->second.used = false;
      ++it;
    }
  }
}

namespace {

// A held-back bounce acts on the pair's contacts whose normals are within about 25 degrees of
// the meeting's (the pair turns a little over the step it waited).
constexpr double kSameBounceNormal = 0.9;

// Two meshes whose surfaces cross at their poses (`manifold`: theirs within the contact
// tolerance): a contact that pushes B out of A along the shortest of a few ways that clear
// them, as deep as B must move that way (to a factor of two, up to
// kDeepestCrossingMeasured_m). apart: set when they do not cross at all. A `placed` pair is
// tested with no feature within the tolerance too, and its contact acts at the dynamic
// body's centre of mass (midway between two dynamic ones'), so that it lifts a sunken body
// instead of turning it.
std::optional<collision::ManifoldPoint> mesh_crossing_depth(const WorldOptions& options, const BodyModel& a,
                                                            const BodyState& sa, const BodyModel& b,
                                                            const BodyState& sb,
                                                            const std::vector<collision::ManifoldPoint>& manifold,
                                                            int& crossing_tests, bool* apart,
                                                            collision::NearbyTrianglePairs* nearby, bool placed) {
  // Only pairs within the contact tolerance (with a manifold) can cross, once stepped.
  // (Their features do not show it: crossing edges pass through faces, not edges.)
  if (manifold.empty() && !placed) return std::nullopt;
  const collision::CollisionMesh& mesh_a = *a.shape.triangles();
  const collision::CollisionMesh& mesh_b = *b.shape.triangles();
  ++crossing_tests;
  const auto crossing = collision::find_intersection(mesh_a, sa.X_WB, mesh_b, sb.X_WB, nearby);
  if (!crossing) {
    if (apart) *apart = true;
    return std::nullopt;
  }
  Eigen::Vector3d ta[3], tb[3];
  mesh_a.corners(crossing->triangle_A, ta);
  mesh_b.corners(crossing->triangle_B, tb);
  for (auto& corner : ta) corner = sa.X_WB * corner;
  for (auto& corner : tb) corner = sb.X_WB * corner;
  // Directions to try, both ways: the crossing triangles' normals and the line between
  // the bodies' centres of mass (a triangle's normal can lie along the crossing, where
  // no shift clears it).
  const Eigen::Vector3d line_W = com_W(b, sb) - com_W(a, sa);
  std::vector<Eigen::Vector3d> directions = {(ta[1] - ta[0]).cross(ta[2] - ta[0]).normalized(),
                                             (tb[1] - tb[0]).cross(tb[2] - tb[0]).normalized()};
  if (line_W.norm() > 0) directions.push_back(line_W.normalized());
  const auto clears = [&](const Eigen::Vector3d& shift_W) {
    geometry::Pose X_B = sb.X_WB;
    X_B.translation() += shift_W;
    return !collision::intersects(mesh_a, sa.X_WB, mesh_b, X_B);
  };
  // How far B must move (the shortest of those ways, to a factor of two) to clear A.
  for (double shift_m = options.overlap_tolerance_m; shift_m <= kDeepestCrossingMeasured_m; shift_m *= 2)
    for (const Eigen::Vector3d& direction : directions)
      for (const double sign : {1.0, -1.0}) {
        if (!clears(sign * shift_m * direction)) continue;
        // Where the triangles cross; for a placed pair at the dynamic body's centre of mass:
        // the crossing triangles can be anywhere on either (a table's top triangle spans
        // the table), and a push at their middle turns a sunken body about its rim.
        Eigen::Vector3d where = (ta[0] + ta[1] + ta[2] + tb[0] + tb[1] + tb[2]) / 6.0;
        if (placed && !moves(a, sa)) {
          where = com_W(b, sb);
        } else if (placed && !moves(b, sb)) {
          where = com_W(a, sa);
        } else if (placed) {
          where = 0.5 * (com_W(a, sa) + com_W(b, sb));
        }
        return collision::ManifoldPoint{where, where, sign * direction, -shift_m, *crossing};
      }
  return std::nullopt;
}

// A mesh pair's reduced manifold at the bodies' poses, with the contact that pushes crossed
// surfaces apart; updates the pair's memos.
std::vector<collision::ManifoldPoint> mesh_pair_features(const WorldModel& model, const std::vector<BodyState>& state,
                                                         MeshCrossingMemo& memo, int i, int j) {
  const WorldOptions& options = model.options;
  const BodyModel& a = model.bodies[i];
  const BodyModel& b = model.bodies[j];
  const BodyState& sa = state[i];
  const BodyState& sb = state[j];
  collision::NearbyTrianglePairs* nearby = memo.nearby_pairs(i, j);
  const std::vector<collision::ManifoldPoint> manifold =
      collision::contact_manifold(a.shape, sa.X_WB, b.shape, sb.X_WB, options.contact_tolerance_m, nearby);
  std::vector<collision::ManifoldPoint> features = reduce_manifold(manifold, options.max_contacts_per_pair);
  bool apart = false;
  const bool placed = memo.placed_since_step[i] || memo.placed_since_step[j] || memo.placed_crossing.count({i, j});
  const bool ended_apart = MeshCrossingMemo::known_apart(memo.apart_at_last_end, i, j, sa.X_WB, sb.X_WB);
  const auto crossing =
      ended_apart ? std::nullopt
                  : mesh_crossing_depth(options, a, sa, b, sb, manifold, memo.crossing_tests, &apart, nearby, placed);
  apart |= ended_apart;
  if (apart) memo.apart_at[{i, j}] = {sa.X_WB, sb.X_WB};  // (i < j: participants are sorted)
  if (crossing && placed) {
    memo.placed_crossing.insert({i, j});
  } else if (!crossing) {
    memo.placed_crossing.erase({i, j});
  }
  if (crossing) {
    // The crossing features' normals point to the side their vertex is on, which for a
    // vertex gone through is the wrong one: rows along them would hold the pair crossed.
    // Those opposing the way out are dropped.
    features.erase(std::remove_if(features.begin(), features.end(),
                                  [&](const auto& f) { return f.normal_W.dot(crossing->normal_W) < 0; }),
                   features.end());
    features.push_back(*crossing);
  }
  return features;
}

// Contacts of pair (i, j) at these features, with their hints from the last step.
void append_contacts(const WorldOptions& options, const ContactHints& hints, int i, int j,
                     const std::vector<collision::ManifoldPoint>& features, std::vector<Contact>& contacts) {
  const double tolerance = options.contact_tolerance_m;
  const BodyPair key{std::min(i, j), std::max(i, j)};
  const auto by_pair = [](const auto& hint, const BodyPair& k) { return hint.bodies < k; };
  const auto pushed = std::lower_bound(hints.pushed_before.begin(), hints.pushed_before.end(), key, by_pair);
  const auto warm = std::lower_bound(hints.warm_forces.begin(), hints.warm_forces.end(), key, by_pair);
  const auto bounces = std::lower_bound(hints.pending_bounces.begin(), hints.pending_bounces.end(), key, by_pair);
  for (const auto& feature : features) {
    Contact contact{i, j, feature, 0.0};
    const Eigen::Vector3d point_W = row_point(feature);
    for (auto it = pushed; it != hints.pushed_before.end() && it->bodies == key && !contact.pushed_before; ++it)
      contact.pushed_before = (it->point_W - point_W).norm() <= tolerance;
    // (Held back for the pair as (i, j): its normal points from i to j, as the feature's does.)
    for (auto it = bounces; it != hints.pending_bounces.end() && it->bodies == key; ++it)
      if (key == std::make_pair(i, j) && it->normal_W.dot(feature.normal_W) > kSameBounceNormal)
        contact.min_normal_velocity_m_s = std::max(contact.min_normal_velocity_m_s, it->speed_m_s);
    double nearest_m = tolerance;
    for (auto it = warm; it != hints.warm_forces.end() && it->bodies == key; ++it)
      if (const double d = (it->point_W - point_W).norm(); d <= nearest_m) {
        nearest_m = d;
        contact.warm_force_W_N = it->force_W_N;
      }
    contacts.push_back(contact);
  }
}

}  // namespace

std::vector<Contact> gather_contacts(const WorldModel& model, const std::vector<BodyState>& state,
                                     const ContactHints& hints, MeshCrossingMemo& memo, const WorkerPool& pool,
                                     const std::vector<int>& participants, std::size_t expected) {
  step_helpers::require_model("gather_contacts", model, state);
  step_helpers::require_participants("gather_contacts", participants, state.size());
  step_helpers::require_size("gather_contacts", "memo.placed_since_step", memo.placed_since_step.size(), state.size());
  const WorldOptions& options = model.options;
  const double tolerance = options.contact_tolerance_m;
  std::vector<Eigen::AlignedBox3d> boxes;
  boxes.reserve(participants.size());
  for (int i : participants) boxes.push_back(ball_bounds(state[i].X_WB.translation(), model.radius_m[i] + tolerance));
  std::vector<BodyPair> pairs;
  for (const auto& [p, q] : collision::overlapping_pairs(boxes)) {
    const int i = participants[p], j = participants[q];
    const BodyModel& a = model.bodies[i];
    const BodyModel& b = model.bodies[j];
    if (!moves(a, state[i]) && !moves(b, state[j])) continue;
    if (a.shape.type() == collision::Shape::Type::kPlane && b.shape.type() == collision::Shape::Type::kPlane) continue;
    pairs.emplace_back(i, j);
  }
  // A depth-measured pair's manifold depends on its poses alone: on the worker threads,
  // each into its own slot. Mesh pairs share the memo: in order, here.
  std::vector<std::vector<collision::ManifoldPoint>> features(pairs.size());
  pool.for_each(static_cast<int>(pairs.size()), [&](int k) {
    const auto [i, j] = pairs[k];
    const BodyModel& a = model.bodies[i];
    const BodyModel& b = model.bodies[j];
    if (depth_measured(a, b))
      features[k] =
          reduce_manifold(collision::contact_manifold(a.shape, state[i].X_WB, b.shape, state[j].X_WB, tolerance),
                          options.max_contacts_per_pair);
  });
  std::vector<Contact> contacts;
  contacts.reserve(expected);
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const auto [i, j] = pairs[k];
    if (!depth_measured(model.bodies[i], model.bodies[j])) features[k] = mesh_pair_features(model, state, memo, i, j);
    append_contacts(options, hints, i, j, features[k], contacts);
  }
  return contacts;
}

}  // namespace arphys::dynamics

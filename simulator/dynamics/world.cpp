#include "simulator/dynamics/world.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>

#include "simulator/collision/broad_phase.hpp"
#include "simulator/collision/discrete_query.hpp"
#include "simulator/collision/separation_certificate.hpp"
#include "simulator/collision/shape_query.hpp"
#include "simulator/dynamics/disjoint_sets.hpp"
#include "simulator/dynamics/manifold_reduction.hpp"
#include "simulator/dynamics/position_projection.hpp"

namespace arphys::dynamics {
namespace {

// Rounding allowance of a gap between boxes computed from metre-sized coordinates.
constexpr double kGapRounding_m = 1e-9;
// Gauss-Seidel sweeps of a projection (World::project_deep_points): the lifted points
// are a few dozen in a pile's round, most settled in two or three.
constexpr int kProjectionSweeps = 50;
// Rounds of a projection: lift, measure every touched pair at the lifted poses, lift the
// pairs found too deep with the rest.
constexpr int kProjectionRounds = 8;
// Projections before a part of a step falls back to re-solving its deep points.
constexpr int kMaxProjectionsPerMotion = 4;

// The angular velocity after h_s of torque-free motion.
Eigen::Vector3d gyroscopic_step(const Eigen::Matrix3d& I_W, const Eigen::Vector3d& w_W_rad_s, double h_s) {
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
  Eigen::Vector3d w = w_W_rad_s;
  for (int iteration = 0; iteration < 6; ++iteration) {
    const Eigen::Vector3d m = 0.5 * (w_W_rad_s + w);
    const Eigen::Vector3d Im = I_W * m;
    const Eigen::Vector3d g = I_W * (w - w_W_rad_s) + h_s * m.cross(Im);
    const Eigen::Matrix3d J = I_W + 0.5 * h_s * (skew(m) * I_W - skew(Im));
    const Eigen::Vector3d step = J.partialPivLu().solve(g);
    if (!step.allFinite()) return w_W_rad_s;
    w -= step;
    if (step.norm() <= 1e-14 * (1 + w.norm())) break;
  }
  return w;
}



Eigen::AlignedBox3d ball_bounds(const Eigen::Vector3d& centre, double radius) {
  if (!std::isfinite(radius)) {
    const double inf = std::numeric_limits<double>::infinity();
    return Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-inf), Eigen::Vector3d::Constant(inf));
  }
  return Eigen::AlignedBox3d(centre.array() - radius, centre.array() + radius);
}

// A body's pose after moving its centre of mass with v and turning with w for h.
geometry::Pose integrate(const RigidBody& body, const BodyVelocity& u, double h) {
  return moved_about_com(body.X_WB, body.mass.center_of_mass_m, u.v_WC_m_s * h, u.w_W_rad_s, u.w_W_rad_s.norm() * h);
}

// The CCD says the pair meets inside the motion (a time of impact the step can be cut at).
bool meets_inside(const collision::ContinuousResult& r) {
  return r.collides && r.time_of_impact > 0 && r.features.kind != collision::FeaturePair::kOverlapAtStart;
}
// The CCD says the pair already touches (or overlaps) at the start: it cannot time anything after.
bool touching_at_start(const collision::ContinuousResult& r) {
  return r.collides && !meets_inside(r);
}

// Where a contact's constraint row acts: midway between its two features' points (they
// can be millimetres apart along the surface on a sliding pair).
Eigen::Vector3d row_point(const collision::ManifoldPoint& feature) { return 0.5 * (feature.point_A_W + feature.point_B_W); }

// The body pairs of the contacts, sorted, once each.
std::vector<std::pair<int, int>> pairs_of(const std::vector<Contact>& contacts) {
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(contacts.size());
  for (const Contact& c : contacts) pairs.emplace_back(std::min(c.body_a, c.body_b), std::max(c.body_a, c.body_b));
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

// Whether the pair's contact manifold measures how deep the bodies overlap (signed
// distances): every pair but those of a mesh with a mesh or a box.
bool depth_measured(const RigidBody& a, const RigidBody& b) {
  const auto is_mesh = [](const RigidBody& body) { return body.shape.type() == collision::Shape::Type::kMesh; };
  return !(is_mesh(a) || is_mesh(b)) || !a.shape.triangles() || !b.shape.triangles();
}

// A participant's place in the (sorted) participants, -1 if it is not one.
int slot_of(const std::vector<int>& participants, int body) {
  const auto it = std::lower_bound(participants.begin(), participants.end(), body);
  return it != participants.end() && *it == body ? static_cast<int>(it - participants.begin()) : -1;
}

double combined_friction(const RigidBody& a, const RigidBody& b) {
  if (a.friction && b.friction) return std::sqrt(*a.friction * *b.friction);
  if (a.friction) return *a.friction;
  if (b.friction) return *b.friction;
  return 0;
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

World::World(WorldOptions options) : options_(std::move(options)) { check_options(options_); }

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
    if (!body.v_WC_m_s.allFinite() || !body.w_W_rad_s.allFinite())
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
      body.w_W_rad_s = screw.angular_velocity() / h_s;
      body.v_WC_m_s = screw.velocity_of_point(body.com_W()) / h_s;
    } else {
      const Twist twist = body.trajectory.twist_at(t_s);
      body.w_W_rad_s = twist.w_W_rad_s;
      body.v_WC_m_s = twist.velocity_of_point(body.com_W(), body.X_WB.translation());
    }
  }
}

std::vector<Contact> World::gather_contacts(const std::vector<int>& participants) const {
  const double tolerance = options_.contact_tolerance_m;
  std::vector<Eigen::AlignedBox3d> boxes;
  boxes.reserve(participants.size());
  for (int i : participants) boxes.push_back(ball_bounds(bodies_[i].X_WB.translation(), radius_m_[i] + tolerance));
  std::vector<Contact> contacts;
  // (About as many as the last step had: grown from empty, a 1000-box pile's thousands of
  // contacts were copied a dozen times over.)
  contacts.reserve(participants.size() == bodies_.size() ? contacts_.size() + contacts_.size() / 4 : 0);
  for (const auto& [p, q] : collision::overlapping_pairs(boxes)) {
    const int i = participants[p], j = participants[q];
    const RigidBody& a = bodies_[i];
    const RigidBody& b = bodies_[j];
    if (!a.is_dynamic() && !b.is_dynamic()) continue;
    if (a.shape.type() == collision::Shape::Type::kPlane && b.shape.type() == collision::Shape::Type::kPlane) continue;
    collision::NearbyTrianglePairs* nearby = depth_measured(a, b) ? nullptr : nearby_pairs(i, j);
    std::vector<collision::ManifoldPoint> manifold =
        collision::contact_manifold(a.shape, a.X_WB, b.shape, b.X_WB, tolerance, nearby);
    std::vector<collision::ManifoldPoint> features = reduce_manifold(manifold, options_.max_contacts_per_pair);
    if (!depth_measured(a, b)) {
      bool apart = false;
      const bool placed = placed_since_step_[i] || placed_since_step_[j] || placed_crossing_.count({i, j});
      // (Proven apart at these poses where the last step ended: see apart_at_end_.)
      const bool ended_apart = known_apart(apart_at_last_end_, i, j, a.X_WB, b.X_WB);
      const auto crossing =
          ended_apart ? std::nullopt : mesh_crossing_depth(a, b, manifold, &apart, nearby, placed);
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
    }
    const std::pair<int, int> key{std::min(i, j), std::max(i, j)};
    const auto pushed = std::lower_bound(pushed_before_.begin(), pushed_before_.end(), key,
                                         [](const PushedPoint& p, const std::pair<int, int>& k) { return p.bodies < k; });
    const auto warm = std::lower_bound(warm_forces_.begin(), warm_forces_.end(), key,
                                       [](const PreviousForce& p, const std::pair<int, int>& k) { return p.bodies < k; });
    for (const auto& feature : features) {
      Contact contact{i, j, feature, 0.0};
      const Eigen::Vector3d point_W = row_point(feature);
      for (auto it = pushed; it != pushed_before_.end() && it->bodies == key && !contact.pushed_before; ++it)
        contact.pushed_before = (it->point_W - point_W).norm() <= tolerance;
      double nearest_m = tolerance;
      for (auto it = warm; it != warm_forces_.end() && it->bodies == key; ++it)
        if (const double d = (it->point_W - point_W).norm(); d <= nearest_m) {
          nearest_m = d;
          contact.warm_force_W_N = it->force_W_N;
        }
      contacts.push_back(contact);
    }
  }
  return contacts;
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
    v.v_WC_m_s = body.v_WC_m_s + force_h * options_.gravity_m_s2;
    v.w_W_rad_s = gyroscopic_step(body.inertia_W(), body.w_W_rad_s, force_h);
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
  if (!a.is_dynamic()) row.known_normal_velocity_m_s -= row.normal_W.dot(a.velocity_of_point(row.point_W));
  if (!b.is_dynamic()) row.known_normal_velocity_m_s += row.normal_W.dot(b.velocity_of_point(row.point_W));
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
  const auto point_speed = [&](const BodyVelocity& v, std::size_t k) { return v.v_WC_m_s.norm() + v.w_W_rad_s.norm() * radius[k]; };
  const auto energy_speed = [&](const BodyVelocity& v, std::size_t k) {
    const RigidBody& body = bodies_[setup.body_of_unknown[k]];
    const double turning = v.w_W_rad_s.dot(body.inertia_W() * v.w_W_rad_s) / body.mass.mass_kg;
    return std::sqrt(v.v_WC_m_s.squaredNorm() + std::max(0.0, turning));
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
      u[k].v_WC_m_s *= scale;
      u[k].w_W_rad_s *= scale;
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

Eigen::AlignedBox3d World::swept_box(int body, const geometry::Pose& next) const {
  return collision::swept_bounds(geometry::ScrewMotion(bodies_[body].X_WB, next), Eigen::Vector3d::Zero(), radius_m_[body]);
}

double World::earliest_impact(const std::vector<int>& participants, const std::vector<geometry::Pose>& next,
                              const std::vector<std::pair<int, int>>* resting_pairs, ImpactMap* meeting,
                              ImpactCache* cache, bool* deepening, StepReport& report,
                              const std::vector<std::pair<int, int>>* swept_pairs) const {
  std::vector<std::pair<int, int>> own;
  if (!swept_pairs) {
    std::vector<Eigen::AlignedBox3d> swept;
    swept.reserve(participants.size());
    for (std::size_t s = 0; s < participants.size(); ++s) swept.push_back(swept_box(participants[s], next[s]));
    own = collision::overlapping_pairs(swept);
  }
  // How far each body's points can move over the step: its origin's displacement and
  // its rotation angle times its radius about the origin.
  std::vector<Eigen::Vector3d> shift(participants.size());
  std::vector<double> turn(participants.size()), curve(participants.size());
  for (std::size_t s = 0; s < participants.size(); ++s) {
    const RigidBody& body = bodies_[participants[s]];
    shift[s] = next[s].translation() - body.X_WB.translation();
    const double angle = Eigen::AngleAxisd(next[s].linear() * body.X_WB.linear().transpose()).angle();
    turn[s] = angle > 0 ? angle * radius_m_[participants[s]] : 0.0;
    // On its screw the origin strays from moving along its shift uniformly by less than
    // this (the arc's sagitta, and its uneven pace along the chord, are both below it).
    curve[s] = angle > 0 ? angle * shift[s].norm() : 0.0;
  }
  // Each participant's screw motion, built when a pair first needs it (a body in a pile
  // is in a dozen pairs: built per pair, they were 7 % of its time).
  std::vector<std::optional<geometry::ScrewMotion>> motions(participants.size());
  const auto motion_of = [&](int slot) -> const geometry::ScrewMotion& {
    if (!motions[slot]) motions[slot].emplace(bodies_[participants[slot]].X_WB, next[slot]);
    return *motions[slot];
  };
  // The pairs come in the cache's order: a pair's entry is usually the one after the
  // last pair's (looked up from the root each time, the tree's pointer chase was a
  // third of this function's own time in a 1000-box pile).
  ImpactCache::iterator last = cache ? cache->end() : ImpactCache::iterator();
  const auto cached = [&](int i, int j) -> CachedImpact& {
    const std::pair<int, int> key{i, j};
    ImpactCache::iterator it = last == cache->end() ? cache->begin() : std::next(last);
    if (it == cache->end() || it->first != key) {
      it = cache->lower_bound(key);
      if (it == cache->end() || it->first != key) it = cache->try_emplace(it, key);
    }
    last = it;
    return it->second;
  };
  double earliest = 1.0;
  for (const auto& [p, q] : swept_pairs ? *swept_pairs : own) {
    const int i = participants[p], j = participants[q];
    const RigidBody& a = bodies_[i];
    const RigidBody& b = bodies_[j];
    if (!a.is_dynamic() && !b.is_dynamic()) continue;
    if (a.shape.type() == collision::Shape::Type::kPlane && b.shape.type() == collision::Shape::Type::kPlane) continue;
    // Resting pairs barely move relative to each other: a relative motion below half
    // the resting gap cannot close it, so the CCD query is skipped (a pile of boxes is
    // almost all such pairs). The price: a pair closer than that may end up to half
    // the gap (0.5 um) inside each other.
    const double relative_motion_m = (shift[q] - shift[p]).norm() + turn[p] + turn[q];
    if (relative_motion_m < 0.5 * options_.contact_gap_m) continue;
    // A resting pair (constraints of the step already) whose points move less than
    // max_unswept_motion_m relative to each other is held by its contacts, and its motion
    // checked at the end like a touching pair's: a point that ends outside the other
    // body and moved less than that can have been at most half of it inside in between
    // (a box clipping another's corner), which matters only where the step is cut
    // mid-motion (unswept_clear_fraction). The CCD of such
    // pairs (surfaces 1 um apart, edges nearly parallel) took thousands of search nodes
    // and cut steps at times of impact of 1e-6: most of a 1000-box pile's step.
    // Primitives are checked by their contact manifolds, which measure depth exactly. A
    // mesh pair (a mesh's manifold can miss a vertex that went in: a bunny dropped 2 cm
    // onto a table then sank 0.6 mm) is checked by whether its surfaces cross at the end
    // (check_mesh_crossing), so only when the contact pass found them apart at these
    // start poses: in a pile of 16 resting bunnies the CCD of such pairs, 250-400 queries
    // a frame, was 40 % of the live simulator's time and put it seconds behind the camera.
    const auto primitive = [](const RigidBody& body) { return body.shape.type() != collision::Shape::Type::kMesh; };
    // A re-solve changes the motions of the island it touches only; every other pair's
    // motions, and so its answer, are as in the last round.
    CachedImpact fresh;
    CachedImpact& query = cache ? cached(i, j) : fresh;
    if (!query.valid || query.next_A.matrix() != next[p].matrix() || query.next_B.matrix() != next[q].matrix()) {
      const bool apart_at_start = known_apart(apart_at_, i, j, a.X_WB, b.X_WB);  // (i < j: participants are sorted)
      const bool resting_slowly =
          resting_pairs && ((primitive(a) && primitive(b)) || apart_at_start) &&
          relative_motion_m <= max_unswept_motion_m(a, b) &&
          std::binary_search(resting_pairs->begin(), resting_pairs->end(), std::make_pair(i, j));
      // Two bodies whose bounding boxes are further apart at the start than their points
      // move relative to each other cannot meet in the step (in a tumbling pile, most of
      // the pairs whose swept boxes overlap): proven without building their motions.
      const bool far_apart = !resting_slowly && collision::gap_lower_bound_m(a.shape, a.X_WB, b.shape, b.X_WB) >
                                                    relative_motion_m + curve[p] + curve[q] + kGapRounding_m;
      const bool swept_by_ccd = !resting_slowly && !far_apart;
      collision::ContinuousOptions ccd = options_.ccd;
      ccd.apart_at_start = apart_at_start;
      const double start_depth_m = query.start_depth_m;  // (-1 for a pair not asked before)
      query = {true, next[p], next[q],
               swept_by_ccd ? collision::time_of_impact(a.shape, motion_of(p), b.shape, motion_of(q), ccd)
                            : collision::ContinuousResult{},
               {}};
      if (swept_by_ccd) ++report.ccd_queries;
      const collision::ContinuousResult& r = query.result;
      query.swept = !resting_slowly && !touching_at_start(r);
      // Swept from apart without meeting: apart at the end (apart_at_end_).
      if (query.swept && !r.collides && !depth_measured(a, b)) apart_at_end_[{i, j}] = {next[p], next[q]};
      if (meets_inside(r) && r.features.kind != collision::FeaturePair::kNone) {
        // The meeting point as material points of both bodies, and A's normal there.
        const geometry::Pose X_A = motion_of(p).pose_at(r.time_of_impact);
        const geometry::Pose X_B = motion_of(q).pose_at(r.time_of_impact);
        query.hits = {{X_A.inverse() * r.point_W, X_B.inverse() * r.point_W, X_A.linear().transpose() * r.normal_W}};
      }
      if (resting_slowly || touching_at_start(r)) {
        // Touching or overlapping already: the CCD cannot time a meeting of surfaces
        // that meet at the start, and the contacts, linearised, let a turning body dig
        // in (1e-5 m in a pile of 1000 boxes). So the end of the motion is checked:
        // points deeper than overlap_tolerance_m (and than the pair was at the start)
        // become constraints of a re-solve, as a CCD meeting would.
        query.hits.clear();
        if (depth_measured(a, b)) {
          const double start_depth = query.start_depth_m =
              start_depth_m >= 0 ? start_depth_m : deepest_overlap(i, a.X_WB, j, b.X_WB);
          // (A tenth of the tolerance over the start depth keeps a pair that rounding
          // deepens by nanometres from being cut into ever smaller steps, in which the
          // depenetration speed can no longer undo anything.)
          const double allowed = query.allowed_depth_m =
              std::max(start_depth + 0.1 * options_.overlap_tolerance_m, options_.overlap_tolerance_m);
          for (const auto& point : collision::contact_manifold(a.shape, next[p], b.shape, next[q], 0.0)) {
            if (-point.distance_m <= allowed) continue;
            query.hits.push_back({next[p].inverse() * point.point_A_W, next[q].inverse() * point.point_B_W,
                                  next[p].linear().transpose() * point.normal_W, -point.distance_m});
          }
        } else if (r.features.kind != collision::FeaturePair::kOverlapAtStart) {
          check_mesh_crossing(a, motion_of(p), b, motion_of(q), relative_motion_m, query, nearby_pairs(i, j));
          if (query.free_until == 1) apart_at_end_[{i, j}] = {next[p], next[q]};
        }
        query.deepens = !query.hits.empty() || query.free_until < 1;
      }
    }
    if (query.deepens) {
      if (deepening) *deepening = true;
      if (meeting) (*meeting)[{i, j}].insert((*meeting)[{i, j}].end(), query.hits.begin(), query.hits.end());
      continue;
    }
    if (!meets_inside(query.result)) continue;
    earliest = std::min(earliest, query.result.time_of_impact);
    if (meeting) (*meeting)[{i, j}].insert((*meeting)[{i, j}].end(), query.hits.begin(), query.hits.end());
  }
  return earliest;
}

double World::deepest_overlap(int a, const geometry::Pose& X_WA, int b, const geometry::Pose& X_WB) const {
  double deepest = 0;
  for (const auto& point : collision::contact_manifold(bodies_[a].shape, X_WA, bodies_[b].shape, X_WB, 0.0))
    deepest = std::max(deepest, -point.distance_m);
  return deepest;
}

void World::check_mesh_crossing(const RigidBody& a, const geometry::ScrewMotion& motion_a, const RigidBody& b,
                                const geometry::ScrewMotion& motion_b, double relative_motion_m,
                                CachedImpact& query, collision::NearbyTrianglePairs* nearby) const {
  // A mesh's manifold cannot say how deep a point went (a scanned bunny has no inside:
  // its distances are unsigned), and the CCD, touching at the start, times nothing after
  // it. Whether the surfaces cross it can say. If they do at the end, the last fraction
  // of the motion where they do not is bisected, and the features that touch there
  // become constraints of a re-solve, as a CCD meeting's would; if they still cross, the
  // step is cut there (shallow_fraction). (Unchecked, a pair of resting bunnies rolled
  // into each other by 5 mm over ten steps: new features met as they turned.)
  // No crossing is allowed, not even a tolerated micrometre as for primitives: a pair left
  // crossing starts its next motion overlapping, where neither the CCD nor this can follow
  // it (tried: measuring and allowing crossings along the touching normal, pairs crept
  // 300 um deep cut by cut).
  const collision::CollisionMesh& mesh_a = *a.shape.triangles();
  const collision::CollisionMesh& mesh_b = *b.shape.triangles();
  const auto crosses = [&](double t) {
    return collision::intersects(mesh_a, motion_a.pose_at(t), mesh_b, motion_b.pose_at(t), nearby);
  };
  if (!crosses(1.0)) return;
  double free = 0, crossing = 1;
  for (int halving = 0; halving < 8; ++halving) {
    const double t = 0.5 * (free + crossing);
    (crosses(t) ? crossing : free) = t;
  }
  query.free_until = free;
  const geometry::Pose X_A = motion_a.pose_at(free), X_B = motion_b.pose_at(free);
  // What can touch within the bisection's last interval.
  const double reach_m = options_.contact_gap_m + relative_motion_m * (crossing - free);
  for (const auto& point :
       reduce_manifold(collision::contact_manifold(a.shape, X_A, b.shape, X_B, reach_m, nearby), options_.max_contacts_per_pair))
    query.hits.push_back({X_A.inverse() * point.point_A_W, X_B.inverse() * point.point_B_W,
                          X_A.linear().transpose() * point.normal_W});
}

bool World::project_deep_points(const std::vector<int>& participants, std::vector<geometry::Pose>& next,
                                const ImpactMap& meeting, const ImpactCache& cache,
                                const std::vector<std::pair<int, int>>& resting_pairs) const {
  // The pairs to lift: those ending too deep. A CCD meeting's points (end_depth_m < 0) are
  // an impact, left for the re-solve, which bounces it; a mesh pair ending too deep is
  // left to it too (its depth is not measured), and then so is everything.
  std::set<std::pair<int, int>> lifted;
  for (const auto& [pair, hits] : meeting) {
    if (std::none_of(hits.begin(), hits.end(), [](const ImpactPoint& hit) { return hit.end_depth_m >= 0; })) continue;
    if (!depth_measured(bodies_[pair.first], bodies_[pair.second]) || !cache.count(pair)) return false;
    lifted.insert(pair);
  }
  if (lifted.empty()) return false;
  const double tolerance = options_.overlap_tolerance_m;
  // How deep a pair may end: as the end check allows, the deeper of the tolerance and a
  // tenth of it over the pair's start depth (measured here for a pair the check skipped:
  // one that barely moved).
  const auto allowed_depth = [&](const std::pair<int, int>& pair) {
    const auto it = cache.find(pair);
    if (it != cache.end() && it->second.allowed_depth_m > 0) return it->second.allowed_depth_m;
    const double start_depth = deepest_overlap(pair.first, bodies_[pair.first].X_WB, pair.second, bodies_[pair.second].X_WB);
    return std::max(start_depth + 0.1 * tolerance, tolerance);
  };
  std::vector<ProjectedBody> moved;
  std::vector<int> slot_of_moved;                       // participant slot of each projected body
  std::vector<int> index(bodies_.size(), -1);           // body -> index in moved
  const auto body_index = [&](int body) {
    if (index[body] < 0) {
      const RigidBody& b = bodies_[body];
      const int slot = slot_of(participants, body);
      ProjectedBody projected;
      projected.X_WB = next[slot];  // (a non-dynamic body's end pose, which it keeps)
      projected.center_of_mass_B = b.mass.center_of_mass_m;
      if (b.is_dynamic()) {
        projected.inverse_mass_1_kg = 1.0 / b.mass.mass_kg;
        projected.inverse_inertia_W = b.inverse_inertia_W();
      }
      index[body] = static_cast<int>(moved.size());
      moved.push_back(projected);
      slot_of_moved.push_back(slot);
    }
    return index[body];
  };
  const auto pose_of = [&](int body) { return moved[body_index(body)].X_WB; };
  // Every point of a lifted pair within a few tolerances (lifting a box's deepest corner
  // turns it onto its others) is held at half a tolerance under what the pair may end at:
  // held at the resting gap instead, pairs resting within the tolerance were pushed apart
  // too and the lift spread through a pile. Pairs that the lifts deepen beyond what they
  // may join them, round by round.
  for (int round = 0; round < kProjectionRounds; ++round) {
    std::vector<ProjectedPoint> points;
    for (const auto& pair : lifted) {
      const RigidBody& a = bodies_[pair.first];
      const RigidBody& b = bodies_[pair.second];
      const geometry::Pose X_A = pose_of(pair.first), X_B = pose_of(pair.second);
      const double allowed = allowed_depth(pair);
      const double target = allowed - 0.5 * tolerance;
      for (const auto& f : collision::contact_manifold(a.shape, X_A, b.shape, X_B, 4 * tolerance))
        points.push_back({body_index(pair.first), body_index(pair.second), X_A.inverse() * f.point_A_W,
                          X_B.inverse() * f.point_B_W, X_A.linear().transpose() * f.normal_W, target});
    }
    // A quarter of the tolerance over the targets: the pairs are measured again below.
    if (!project_points(moved, points, 0.25 * tolerance, kProjectionSweeps).converged) return false;
    // Every resting pair of a body the lifts moved, measured at the lifted poses. (Which
    // bodies moved is settled once per round: the group's resting pairs are thousands in
    // a pile, and a pose comparison per pair was most of a lift's own time.)
    std::vector<char> lifted_body(bodies_.size(), 0);
    for (std::size_t k = 0; k < moved.size(); ++k)
      if (moved[k].X_WB.matrix() != next[slot_of_moved[k]].matrix()) lifted_body[participants[slot_of_moved[k]]] = 1;
    bool settled = true;
    for (const auto& pair : resting_pairs) {
      if (!(lifted_body[pair.first] || lifted_body[pair.second]) ||
          !depth_measured(bodies_[pair.first], bodies_[pair.second]))
        continue;
      const double allowed = allowed_depth(pair);
      for (const auto& f : collision::contact_manifold(bodies_[pair.first].shape, pose_of(pair.first),
                                                       bodies_[pair.second].shape, pose_of(pair.second), 0.0))
        if (-f.distance_m > allowed) {
          settled = false;
          lifted.insert(pair);
          break;
        }
    }
    if (settled) {
      for (std::size_t k = 0; k < moved.size(); ++k)
        if (moved[k].inverse_mass_1_kg > 0) next[slot_of_moved[k]] = moved[k].X_WB;
      return true;
    }
  }
  return false;
}

double World::max_unswept_motion_m(const RigidBody& a, const RigidBody& b) const {
  // Two kinds of pair keep to the contact tolerance, as before the two were separate
  // options: a mesh's, whose thinnest part is not known (a bunny's ear, a cup's wall); and
  // a bouncing one's, because what the end check finds is held, not bounced (a point that
  // starts within the tolerance is a contact row, which bounces; with motion below it,
  // nothing from further away can reach).
  if (a.shape.type() == collision::Shape::Type::kMesh || b.shape.type() == collision::Shape::Type::kMesh ||
      std::max(a.restitution, b.restitution) > 0)
    return std::min(options_.resting_unswept_motion_m, options_.contact_tolerance_m);
  // A point moving less than a quarter of a body's thickness cannot pass through it: it
  // ends outside, or inside on its own side, where the end check finds it.
  const auto half_thickness_m = [](const RigidBody& body) {
    switch (body.shape.type()) {
      case collision::Shape::Type::kBox: return 0.5 * body.shape.size_m().minCoeff();
      case collision::Shape::Type::kSphere: return body.shape.radius_m();
      default: return std::numeric_limits<double>::infinity();
    }
  };
  return std::min(options_.resting_unswept_motion_m, 0.5 * std::min(half_thickness_m(a), half_thickness_m(b)));
}

double World::unswept_clear_fraction(const std::vector<int>& participants, const std::vector<geometry::Pose>& next,
                                     const ImpactCache& cache, double tau, double h_s) const {
  // (The group's pairs only: at the step's start the cache holds every group's.)
  for (int p = 0; p < static_cast<int>(participants.size()) && tau > 0; ++p)
    for (auto it = cache.lower_bound({participants[p], -1}); it != cache.end() && it->first.first == participants[p]; ++it) {
      const auto& [pair, query] = *it;
      if (!query.valid || query.swept || !depth_measured(bodies_[pair.first], bodies_[pair.second])) continue;
      const int q = slot_of(participants, pair.second);
      if (q < 0) continue;  // another group's pair
      if (query.next_A.matrix() != next[p].matrix() || query.next_B.matrix() != next[q].matrix()) continue;
      const geometry::ScrewMotion motion_a(bodies_[pair.first].X_WB, next[p]), motion_b(bodies_[pair.second].X_WB, next[q]);
      // (Twelve halvings: a pair that moved a centimetre is then within 3 um of its start.)
      const double allowed_m = query.allowed_depth_m;
      tau = halved_until_within(pair, motion_a, motion_b, tau, 12, [&](double fraction) {
        // What the rest of the step undoes (at half the depenetration speed) may be left:
        // halving to the end check's micrometre made cut after cut, to the event cap.
        return std::max(allowed_m, 0.5 * options_.max_depenetration_speed_m_s * h_s * (1 - fraction));
      });
    }
  return tau;
}

double World::halved_until_within(const std::pair<int, int>& pair, const geometry::ScrewMotion& motion_a,
                                  const geometry::ScrewMotion& motion_b, double fraction, int max_halvings,
                                  const std::function<double(double)>& allowed_depth_m) const {
  for (int halving = 0; halving < max_halvings; ++halving) {
    const double depth_m = deepest_overlap(pair.first, motion_a.pose_at(fraction), pair.second, motion_b.pose_at(fraction));
    if (depth_m <= allowed_depth_m(fraction)) break;
    fraction *= 0.5;
  }
  return fraction;
}

double World::shallow_fraction(const std::vector<int>& participants, const std::vector<geometry::Pose>& next,
                               const ImpactCache& cache, const ImpactMap& meeting) const {
  double fraction = 1.0;
  // (In the pairs' order, as the cache holds them: each pair halves from where the last
  // one left the fraction.)
  for (const auto& entry : meeting) {
    const std::pair<int, int>& pair = entry.first;
    const auto found = cache.find(pair);
    if (found == cache.end()) continue;
    const CachedImpact& query = found->second;
    if (!query.valid || !query.deepens) continue;
    const int p = slot_of(participants, pair.first), q = slot_of(participants, pair.second);
    if (p < 0 || q < 0) continue;  // another group's pair
    if (query.next_A.matrix() != next[p].matrix() || query.next_B.matrix() != next[q].matrix()) continue;
    if (query.free_until < 1) {
      fraction = std::min(fraction, query.free_until);  // a mesh pair: where its surfaces last did not cross
      continue;
    }
    const geometry::ScrewMotion motion_a(bodies_[pair.first].X_WB, next[p]), motion_b(bodies_[pair.second].X_WB, next[q]);
    fraction = halved_until_within(pair, motion_a, motion_b, fraction, 6, [&](double) { return query.allowed_depth_m; });
  }
  return fraction;
}

std::vector<char> World::keep_motions(const std::vector<int>& participants, const std::vector<BodyVelocity>& u_before,
                                      const std::vector<geometry::Pose>& next_before,
                                      const std::vector<BodyVelocity>& u, std::vector<geometry::Pose>& next) const {
  std::vector<char> kept(participants.size(), 0);
  for (std::size_t s = 0; s < participants.size(); ++s) {
    const RigidBody& body = bodies_[participants[s]];
    if (body.motion == BodyMotion::kStatic) {
      kept[s] = 1;
    } else if (body.is_dynamic() && u[s].v_WC_m_s == u_before[s].v_WC_m_s && u[s].w_W_rad_s == u_before[s].w_W_rad_s) {
      // Exactly: a pair a thousandth of the overlap tolerance too deep is corrected by a
      // velocity change of that size (keeping motions that changed by less than 1 nm, such
      // pairs stayed deep round after round: the 100-bunny spawn took 1.9 s per step).
      kept[s] = 1;
      next[s] = next_before[s];
    }
  }
  return kept;
}

World::ImpactCache World::carry_over_cut(const std::vector<int>& participants, const std::vector<BodyVelocity>& u,
                                         std::vector<geometry::Pose>& next, Cut& cut) const {
  // A dynamic body the solve after a cut left as it was goes on along the same screw
  // motion (integrate's constant twist): its end pose is the one before the cut, and a
  // pair of such bodies (or of one and a static body) moves over the rest of the step
  // as it did over that part of the motion. Its CCD answer carries over, its time
  // rescaled. (Queried afresh after every cut, a spawn of 100 bunnies made 8,000 mesh
  // queries per step.)
  const std::vector<char> goes_on = keep_motions(participants, cut.u, cut.next, u, next);
  for (auto it = cut.answers.begin(); it != cut.answers.end();) {
    const int a = slot_of(participants, it->first.first), b = slot_of(participants, it->first.second);
    CachedImpact& query = it->second;
    // Only answers for the motion the cut was made in, that timed it and met nothing
    // until well after the cut.
    bool keep = goes_on[a] && goes_on[b] && query.valid && query.swept &&
                query.next_A.matrix() == cut.next[a].matrix() && query.next_B.matrix() == cut.next[b].matrix() &&
                (!query.result.collides || query.result.time_of_impact > cut.tau + 1e-9);
    if (keep && query.result.collides)
      query.result.time_of_impact = (query.result.time_of_impact - cut.tau) / (1 - cut.tau);
    query.start_depth_m = -1;  // (the cut moved the start poses)
    it = keep ? std::next(it) : cut.answers.erase(it);
  }
  return std::move(cut.answers);
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
              return body.motion == BodyMotion::kKinematic && (body.v_WC_m_s.squaredNorm() > 0 || body.w_W_rad_s.squaredNorm() > 0);
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
            return u[slot].v_WC_m_s + u[slot].w_W_rad_s.cross(p_W - b.com_W());
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
            chained |= missed_bounce_m_s > options_.restitution_threshold_m_s;
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
      if (X.matrix().allFinite() && u[s].v_WC_m_s.allFinite() && u[s].w_W_rad_s.allFinite()) {
        outcome.swept[s].extend(swept_box(participants[s], X));
        body.X_WB = X;
        body.v_WC_m_s = u[s].v_WC_m_s;
        body.w_W_rad_s = u[s].w_W_rad_s;
      } else {
        // Last line of defence: a numerical failure anywhere in the step (solve, CCD
        // cut, integration) leaves the body where it was, at rest. Never NaN.
        outcome.swept[s].extend(body.X_WB.translation());
        body.v_WC_m_s.setZero();
        body.w_W_rad_s.setZero();
        ++report.launches_prevented;
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
  return body.v_WC_m_s.norm() + body.w_W_rad_s.norm() * radius_m_[i];
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
    bodies_[i].v_WC_m_s.setZero();
    bodies_[i].w_W_rad_s.setZero();
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
  for (int i : dynamic) start[i] = {bodies_[i].X_WB, bodies_[i].v_WC_m_s, bodies_[i].w_W_rad_s};
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
        // Stepped before, merged since: start again from the step's start.
        for (int i : bodies) {
          bodies_[i].X_WB = start[i].X_WB;
          bodies_[i].v_WC_m_s = start[i].v;
          bodies_[i].w_W_rad_s = start[i].w;
        }
      } else if (!eventful.count(g)) {
        for (int i : bodies) {
          moved[i] = swept0[i];
          bodies_[i].X_WB = next0[i];
          bodies_[i].v_WC_m_s = u0[i].v_WC_m_s;
          bodies_[i].w_W_rad_s = u0[i].w_W_rad_s;
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

#include "simulator/collision/continuous_query.hpp"

#include <algorithm>
#include <vector>

#include "simulator/collision/discrete_query.hpp"
#include "simulator/collision/feature_toi.hpp"
#include "simulator/collision/obb_culling.hpp"
#include "simulator/collision/screw_enclosure.hpp"
#include "simulator/collision/triangle_distance.hpp"

namespace arphys::collision {

namespace {

struct Task {
  int node_A, node_B;
  double t0, t1;
  int snapshot;    // index of the relative motion's snapshot over [t0, t1]
  double sweep_m;  // how far B's box can move over [t0, t1]
};
struct LaterFirst {  // min-heap on the start of the time interval
  bool operator()(const Task& x, const Task& y) const { return x.t0 > y.t0; }
};

class Search {
 public:
  Search(const CollisionMesh& A, const geometry::ScrewMotion& motion_A, const CollisionMesh& B,
         const geometry::ScrewMotion& motion_B, const ContinuousOptions& options)
      : A_(A), B_(B), rel_AB_(motion_A, motion_B), rel_BA_(motion_B, motion_A), options_(options) {}

  // Earliest contact time in [0, 1], or kNoContact.
  double run(ContinuousStats& stats, ContactFeatures& features) {
    const auto& na = A_.tree().nodes();
    const auto& nb = B_.tree().nodes();
    // The queue and the snapshots live in per-thread buffers reused across queries:
    // allocating them afresh costs more than a small query.
    thread_local std::vector<Task> heap;
    heap.clear();
    auto push = [&](const Task& t) {
      heap.push_back(t);
      std::push_heap(heap.begin(), heap.end(), LaterFirst{});
    };
    // Snapshots of the relative motion, one per time interval the culling creates; the
    // tasks refer to them by index. A snapshot over a longer interval than a task's
    // (after best_ shrank) stays a valid, slightly looser, enclosure.
    thread_local std::vector<RelativeMotion::Snapshot> snapshots;
    snapshots.clear();
    snapshots.push_back(rel_AB_.snapshot({0.0, 1.0}));
    // A node pair is tested when it is created and queued only when it survives, so
    // culled pairs never touch the queue.
    auto consider = [&](int node_A, int node_B, double t0, double t1, int snapshot) {
      const ObbNode& a = na[node_A];
      const ObbNode& b = nb[node_B];
      ++stats.node_pairs_tested;
      const MovingPoint center = rel_AB_.moving_point(b.box.center, snapshots[snapshot]);
      if (obbs_separated(a.box, b.box, snapshots[snapshot].R_AB.mid, center, angular_speed_)) return;
      push({node_A, node_B, t0, t1, snapshot, obb_sweep_m(b.box, center, angular_speed_)});
    };
    consider(0, 0, 0.0, 1.0, 0);
    while (!heap.empty()) {
      std::pop_heap(heap.begin(), heap.end(), LaterFirst{});
      const Task task = heap.back();
      heap.pop_back();
      // Every remaining interval starts no earlier, so none can improve on best_; with a
      // strict test, a query whose answer is 0 (a held proxy) went on through every pair
      // touching at 0.
      if (task.t0 >= best_) break;
      const Interval T{task.t0, std::min(task.t1, best_)};
      const ObbNode& a = na[task.node_A];
      const ObbNode& b = nb[task.node_B];
      if (a.is_leaf() && b.is_leaf()) {
        if ((options_.max_triangle_pairs > 0 && stats.triangle_pairs_tested >= options_.max_triangle_pairs) ||
            (options_.max_search_nodes > 0 && stats.search_nodes >= options_.max_search_nodes)) {
          // Out of budget: what came before T.lo is proven free of contact.
          stats.budget_exhausted = true;
          if (T.lo < best_) {
            best_ = T.lo;
            features_ = {};
          }
          break;
        }
        ++stats.triangle_pairs_tested;
        stats.search_nodes += triangle_pair(a.triangle, b.triangle, T);
        continue;
      }
      const double size_a = a.is_leaf() ? 0.0 : a.box.half_extents_m.maxCoeff();
      const double size_b = b.is_leaf() ? 0.0 : b.box.half_extents_m.maxCoeff();
      // Split time when the motion over T, not the boxes, keeps the test from deciding:
      // the spread of B's box over T (its centre, and its corners turning) against the sizes.
      if (2 * task.sweep_m > options_.time_split_ratio * std::max(size_a, size_b) &&
          T.width() > options_.min_culling_interval) {
        ++stats.time_splits;
        const double mid = T.mid();
        const int first = static_cast<int>(snapshots.size());
        snapshots.push_back(rel_AB_.snapshot({T.lo, mid}));
        snapshots.push_back(rel_AB_.snapshot({mid, T.hi}));
        consider(task.node_A, task.node_B, T.lo, mid, first);
        consider(task.node_A, task.node_B, mid, T.hi, first + 1);
      } else if (size_a >= size_b) {
        consider(a.first_child, task.node_B, T.lo, T.hi, task.snapshot);
        consider(a.first_child + 1, task.node_B, T.lo, T.hi, task.snapshot);
      } else {
        consider(task.node_A, b.first_child, T.lo, T.hi, task.snapshot);
        consider(task.node_A, b.first_child + 1, T.lo, T.hi, task.snapshot);
      }
    }
    features = features_;
    return best_;
  }

 private:
  // Returns the search nodes the pair took.
  long triangle_pair(int tri_A, int tri_B, const Interval& T) {
    Eigen::Vector3d a[3], b[3];
    A_.corners(tri_A, a);
    B_.corners(tri_B, b);
    long nodes = 0;
    const FeatureContact contact =
        triangle_pair_toi(rel_AB_, rel_BA_, a, b, {T.lo, std::min(T.hi, best_)}, options_.time_tolerance, &nodes,
                          feature_pairs(A_.owned_features(tri_A), B_.owned_features(tri_B)));
    if (contact.time < best_) {
      best_ = contact.time;
      features_ = {contact.kind, tri_A, tri_B, contact.corner_A, contact.corner_B};
    }
    return nodes;
  }

  const CollisionMesh& A_;
  const CollisionMesh& B_;
  RelativeMotion rel_AB_, rel_BA_;
  const ContinuousOptions& options_;
  double best_ = kNoContact;
  double angular_speed_ = rel_AB_.angular_speed();
  ContactFeatures features_;
};

// Normal of a vertex meeting a triangle: the direction from the triangle's closest
// point to the vertex just before the contact. Inside the face that is the face
// normal; at the face's boundary (a vertex meeting an edge or another vertex) it is
// the direction the two actually closed along, where the face normal of whichever
// adjacent triangle was found first would be arbitrary. `sign` +1 when the vertex is
// B's (normal from A to B), -1 when it is A's.
Eigen::Vector3d approach_normal(const Eigen::Vector3d& vertex_W, const geometry::Pose& X_W_face,
                                const Eigen::Vector3d corners[3], const Eigen::Vector3d& face_normal_W, double sign) {
  Eigen::Vector3d c[3];
  for (int k = 0; k < 3; ++k) c[k] = X_W_face * corners[k];
  const Eigen::Vector3d away = vertex_W - closest_point_on_triangle(vertex_W, c[0], c[1], c[2]);
  Eigen::Vector3d n = away.norm() > 1e-14 * (1 + vertex_W.norm()) ? away : face_normal_W;
  if (n.dot(away) < 0) n = -n;
  return sign * n.normalized();
}

// Contact point and normal (A towards B) of the features at time t, in the world.
void describe_contact(const CollisionMesh& A, const geometry::ScrewMotion& motion_A, const CollisionMesh& B,
                      const geometry::ScrewMotion& motion_B, double t, ContinuousResult& result) {
  const ContactFeatures& f = result.features;
  const geometry::Pose X_WA = motion_A.pose_at(t), X_WB = motion_B.pose_at(t);
  // Just before the contact, to orient the normal from the side the features came from.
  const double t_before = std::max(0.0, t - 1e-6);
  const geometry::Pose X_WA_before = motion_A.pose_at(t_before), X_WB_before = motion_B.pose_at(t_before);
  Eigen::Vector3d a[3], b[3];
  A.corners(f.triangle_A, a);
  B.corners(f.triangle_B, b);
  auto orient = [](Eigen::Vector3d n, const Eigen::Vector3d& from_A_to_B) {
    n.normalize();
    return n.dot(from_A_to_B) < 0 ? Eigen::Vector3d(-n) : n;
  };
  switch (f.kind) {
    case FeaturePair::kVertexFace: {
      result.point_W = X_WB * b[f.corner_B];
      const Eigen::Vector3d n = X_WA.linear() * (a[1] - a[0]).cross(a[2] - a[0]);
      result.normal_W = approach_normal(X_WB_before * b[f.corner_B], X_WA_before, a, n, +1);
      break;
    }
    case FeaturePair::kFaceVertex: {
      result.point_W = X_WA * a[f.corner_A];
      const Eigen::Vector3d n = X_WB.linear() * (b[1] - b[0]).cross(b[2] - b[0]);
      result.normal_W = approach_normal(X_WA_before * a[f.corner_A], X_WB_before, b, n, -1);
      break;
    }
    case FeaturePair::kEdgeEdge: {
      const Eigen::Vector3d p0 = X_WA * a[f.corner_A], p1 = X_WA * a[(f.corner_A + 1) % 3];
      const Eigen::Vector3d q0 = X_WB * b[f.corner_B], q1 = X_WB * b[(f.corner_B + 1) % 3];
      Eigen::Vector3d cp, cq;
      segment_segment_distance(p0, p1, q0, q1, &cp, &cq);
      result.point_W = 0.5 * (cp + cq);
      Eigen::Vector3d n = (p1 - p0).cross(q1 - q0);
      const Eigen::Vector3d p0b = X_WA_before * a[f.corner_A], p1b = X_WA_before * a[(f.corner_A + 1) % 3];
      const Eigen::Vector3d q0b = X_WB_before * b[f.corner_B], q1b = X_WB_before * b[(f.corner_B + 1) % 3];
      Eigen::Vector3d cp0, cq0;
      segment_segment_distance(p0b, p1b, q0b, q1b, &cp0, &cq0);
      // The common normal of the edges is the contact normal only where they cross
      // inside both; at an end (edge on vertex, parallel edges) use the direction the
      // closest points closed along.
      auto inside = [](const Eigen::Vector3d& x, const Eigen::Vector3d& e0, const Eigen::Vector3d& e1) {
        const double s = (x - e0).dot(e1 - e0) / (e1 - e0).squaredNorm();
        return s > 1e-6 && s < 1 - 1e-6;
      };
      if (n.norm() < 1e-9 * (p1 - p0).norm() * (q1 - q0).norm() || !inside(cp0, p0b, p1b) || !inside(cq0, q0b, q1b))
        n = cq0 - cp0;
      result.normal_W = orient(n, cq0 - cp0);
      break;
    }
    case FeaturePair::kOverlapAtStart: {
      Eigen::Vector3d pa;
      for (auto& p : a) p = X_WA * p;
      for (auto& p : b) p = X_WB * p;
      triangle_triangle_distance(a, b, &pa, nullptr);
      result.point_W = pa;
      result.normal_W = ((a[1] - a[0]).cross(a[2] - a[0])).normalized();
      break;
    }
    case FeaturePair::kPrimitive:  // (not from meshes)
    case FeaturePair::kNone: break;
  }
}

}  // namespace

ContinuousResult time_of_impact(const CollisionMesh& A, const geometry::ScrewMotion& motion_A, const CollisionMesh& B,
                                const geometry::ScrewMotion& motion_B, const ContinuousOptions& options) {
  ContinuousResult result;
  if (const auto pair = options.apart_at_start ? std::nullopt : find_intersection(A, motion_A.start(), B, motion_B.start())) {
    result.collides = true;
    result.time_of_impact = 0.0;
    result.features = {FeaturePair::kOverlapAtStart, pair->triangle_A, pair->triangle_B, -1, -1};
    describe_contact(A, motion_A, B, motion_B, 0.0, result);
    return result;
  }
  Search search(A, motion_A, B, motion_B, options);
  const double toi = search.run(result.stats, result.features);
  if (toi == kNoContact) return result;
  result.collides = true;
  result.time_of_impact = std::clamp(toi, 0.0, 1.0);
  if (result.features.kind != FeaturePair::kNone) describe_contact(A, motion_A, B, motion_B, result.time_of_impact, result);
  return result;
}

}  // namespace arphys::collision

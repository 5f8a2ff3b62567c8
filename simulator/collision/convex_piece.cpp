#include "simulator/collision/convex_piece.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <utility>

#include <Eigen/Geometry>

#include "simulator/collision/collision_mesh.hpp"

namespace arphys::collision {
namespace {

using Eigen::Vector3d;

std::string text(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", x);
  return buffer;
}

// The vertices the triangles use, renumbered in order of first use.
geometry::TriangleMesh without_unused_vertices(const geometry::TriangleMesh& mesh) {
  geometry::TriangleMesh out;
  std::vector<int> renumbered(mesh.num_vertices(), -1);
  for (const Eigen::Vector3i& t : mesh.triangles) {
    Eigen::Vector3i u;
    for (int k = 0; k < 3; ++k) {
      if (t[k] < 0 || t[k] >= static_cast<int>(mesh.num_vertices()))
        throw std::invalid_argument("a triangle names vertex " + std::to_string(t[k]) + ", which does not exist");
      int& slot = renumbered[t[k]];
      if (slot < 0) {
        slot = static_cast<int>(out.vertices_m.size());
        out.vertices_m.push_back(mesh.vertices_m[t[k]]);
      }
      u[k] = slot;
    }
    out.triangles.push_back(u);
  }
  return out;
}

// For each directed edge (a, b) of a triangle, that triangle; throws unless every edge
// is used once in each direction (a closed, consistently oriented surface).
std::map<std::pair<int, int>, int> directed_edges(const geometry::TriangleMesh& hull) {
  std::map<std::pair<int, int>, int> owner;
  for (int i = 0; i < static_cast<int>(hull.num_triangles()); ++i)
    for (int k = 0; k < 3; ++k) {
      const std::pair<int, int> e{hull.triangles[i][k], hull.triangles[i][(k + 1) % 3]};
      if (!owner.emplace(e, i).second)
        throw std::invalid_argument("not closed: edge " + std::to_string(e.first) + "-" + std::to_string(e.second) +
                                    " runs the same way in two triangles (inconsistent orientation or non-manifold)");
    }
  for (const auto& [e, triangle] : owner)
    if (!owner.count({e.second, e.first}))
      throw std::invalid_argument("not closed: edge " + std::to_string(e.first) + "-" + std::to_string(e.second) +
                                  " of triangle " + std::to_string(triangle) + " borders no other triangle");
  return owner;
}

}  // namespace

ConvexPiece::ConvexPiece(geometry::TriangleMesh mesh) {
  if (mesh.num_vertices() < 4 || mesh.num_triangles() < 4)
    throw std::invalid_argument("empty: " + std::to_string(mesh.num_vertices()) + " vertices and " +
                                std::to_string(mesh.num_triangles()) + " triangles (a polyhedron needs at least 4 of each)");
  for (const Vector3d& v : mesh.vertices_m)
    if (!v.allFinite()) throw std::invalid_argument("non-finite vertex coordinate");
  hull_ = without_unused_vertices(mesh);
  const auto owner = directed_edges(hull_);
  const double diagonal = hull_.bounds().diagonal().norm();
  const double eps = 1e-7 * diagonal;
  // Triangle planes; each must have every vertex behind it (convexity).
  std::vector<Vector3d> normal(hull_.num_triangles());
  for (std::size_t i = 0; i < hull_.num_triangles(); ++i) {
    const Eigen::Vector3i& t = hull_.triangles[i];
    const Vector3d& a = hull_.vertices_m[t[0]];
    const Vector3d n = (hull_.vertices_m[t[1]] - a).cross(hull_.vertices_m[t[2]] - a);
    if (!(n.norm() > 1e-12 * diagonal * diagonal))
      throw std::invalid_argument("degenerate: triangle " + std::to_string(i) + " has no area");
    normal[i] = n.normalized();
    for (std::size_t v = 0; v < hull_.num_vertices(); ++v) {
      const double out = normal[i].dot(hull_.vertices_m[v] - a);
      if (out > eps)
        throw std::invalid_argument("not convex: vertex " + std::to_string(v) + " lies " + text(out * 1e3) +
                                    " mm outside the plane of triangle " + std::to_string(i));
    }
    volume_m3_ += a.dot(hull_.vertices_m[t[1]].cross(hull_.vertices_m[t[2]])) / 6.0;
  }
  if (!(volume_m3_ > 1e-9 * diagonal * diagonal * diagonal))
    throw std::invalid_argument("degenerate: volume " + text(volume_m3_) +
                                " m^3 (flat, or triangles wound inward: they must run counter-clockwise seen from outside)");
  // Faces: triangles joined across edges where their planes agree.
  std::vector<int> face_of(hull_.num_triangles(), -1);
  for (std::size_t seed = 0; seed < hull_.num_triangles(); ++seed) {
    if (face_of[seed] >= 0) continue;
    const int f = static_cast<int>(faces_.size());
    faces_.push_back({});
    std::vector<int> stack{static_cast<int>(seed)};
    face_of[seed] = f;
    Vector3d sum = Vector3d::Zero();
    while (!stack.empty()) {
      const int i = stack.back();
      stack.pop_back();
      sum += normal[i];
      for (int k = 0; k < 3; ++k) {
        const int j = owner.at({hull_.triangles[i][(k + 1) % 3], hull_.triangles[i][k]});
        if (face_of[j] >= 0 || normal[j].dot(normal[seed]) < 1 - 1e-9) continue;
        face_of[j] = f;
        stack.push_back(j);
      }
    }
    faces_[f].normal = sum.normalized();
  }
  // Each face's boundary (edges whose twin is in another face) as a loop, and the edges.
  std::vector<std::map<int, int>> boundary(faces_.size());
  for (const auto& [e, triangle] : owner) {
    const int other = owner.at({e.second, e.first});
    if (face_of[triangle] == face_of[other]) continue;
    boundary[face_of[triangle]][e.first] = e.second;
    if (e.first < e.second) edges_.push_back({e.first, e.second, face_of[triangle], face_of[other]});
  }
  for (std::size_t f = 0; f < faces_.size(); ++f) {
    Face& face = faces_[f];
    const std::map<int, int>& next = boundary[f];
    if (next.empty()) throw std::invalid_argument("degenerate: face " + std::to_string(f) + " has no boundary");
    int v = next.begin()->first;
    do {
      face.polygon.push_back(v);
      const auto it = next.find(v);
      if (it == next.end() || face.polygon.size() > next.size())
        throw std::invalid_argument("not convex: face " + std::to_string(f) + "'s boundary is not one loop");
      v = it->second;
    } while (v != face.polygon.front());
    if (face.polygon.size() != next.size())
      throw std::invalid_argument("not convex: face " + std::to_string(f) + "'s boundary is not one loop");
    face.offset_m = -std::numeric_limits<double>::infinity();
    for (int k : face.polygon) face.offset_m = std::max(face.offset_m, face.normal.dot(hull_.vertices_m[k]));
  }
  for (const Vector3d& v : hull_.vertices_m) centroid_m_ += v;
  centroid_m_ /= static_cast<double>(hull_.num_vertices());
  for (const Vector3d& v : hull_.vertices_m) radius_m_ = std::max(radius_m_, (v - centroid_m_).norm());
  for (const Vector3d& v : hull_.vertices_m) box_m_.extend(v);
  half_thickness_m_ = std::numeric_limits<double>::infinity();
  for (const Face& face : faces_) {
    double lowest = std::numeric_limits<double>::infinity();
    for (const Vector3d& v : hull_.vertices_m) lowest = std::min(lowest, face.normal.dot(v));
    half_thickness_m_ = std::min(half_thickness_m_, 0.5 * (face.offset_m - lowest));
  }
}

double box_gap_lower_bound_m(const Eigen::AlignedBox3d& a, const Eigen::AlignedBox3d& b,
                             const Eigen::Isometry3d& X_AB) {
  const Eigen::Matrix3d& R = X_AB.linear();
  const Vector3d half_a = 0.5 * a.sizes(), half_b = 0.5 * b.sizes();
  const Vector3d d_A = X_AB * b.center() - a.center();  // centre to centre, A's frame
  const Eigen::Matrix3d R_abs = R.cwiseAbs();
  const Vector3d gap_A = d_A.cwiseAbs() - half_a - R_abs * half_b;
  const Vector3d gap_B = (R.transpose() * d_A).cwiseAbs() - half_b - R_abs.transpose() * half_a;
  return std::max(gap_A.maxCoeff(), gap_B.maxCoeff());
}

int ConvexPiece::support(const Eigen::Vector3d& d) const {
  int best = 0;
  double best_dot = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < static_cast<int>(hull_.num_vertices()); ++i) {
    const double x = d.dot(hull_.vertices_m[i]);
    if (x > best_dot) {
      best_dot = x;
      best = i;
    }
  }
  return best;
}

std::shared_ptr<const ConvexSet> make_convex_set(std::vector<ConvexPiece> pieces) {
  if (pieces.empty()) throw std::invalid_argument("make_convex_set: no pieces");
  geometry::TriangleMesh all;
  for (const ConvexPiece& piece : pieces) {
    const int base = static_cast<int>(all.vertices_m.size());
    all.vertices_m.insert(all.vertices_m.end(), piece.vertices_m().begin(), piece.vertices_m().end());
    for (const Eigen::Vector3i& t : piece.hull().triangles) all.triangles.push_back(t.array() + base);
  }
  auto set = std::make_shared<ConvexSet>();
  set->half_thickness_m = std::numeric_limits<double>::infinity();
  for (const ConvexPiece& piece : pieces) set->half_thickness_m = std::min(set->half_thickness_m, piece.half_thickness_m());
  for (const ConvexPiece& piece : pieces) {
    set->piece_hulls.push_back(std::make_shared<const CollisionMesh>(piece.hull(), /*test_each_feature_once=*/true));
  }
  set->pieces = std::move(pieces);
  // Each vertex and edge tested once, as for a box: the pieces' depths are measured by
  // their separating axes, which catch what a touch culled at a motion's start leaves.
  set->hulls = std::make_shared<const CollisionMesh>(std::move(all), /*test_each_feature_once=*/true);
  return set;
}

std::shared_ptr<const ConvexSet> load_convex_set(const std::string& path, const Eigen::Vector3d& scale) {
  std::vector<geometry::TriangleMesh> parts;
  try {
    parts = geometry::load_mesh_parts(path, scale);
  } catch (const std::runtime_error& e) {
    throw std::invalid_argument(e.what());
  }
  std::vector<ConvexPiece> pieces;
  pieces.reserve(parts.size());
  for (std::size_t k = 0; k < parts.size(); ++k) {
    try {
      pieces.emplace_back(std::move(parts[k]));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("convex-piece file '" + path + "': piece " + std::to_string(k) + ": " + e.what());
    }
  }
  return make_convex_set(std::move(pieces));
}

}  // namespace arphys::collision

#include "tools/models/approximation_error.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <utility>

#include "simulator/collision/convex_manifold.hpp"
#include "simulator/collision/triangle_distance.hpp"

namespace arphys::tools {
namespace {

using Eigen::Vector3d;
using Intervals = std::vector<std::pair<double, double>>;

// Points on the triangles, spread by area, after every vertex.
std::vector<Vector3d> surface_samples(const geometry::TriangleMesh& mesh, int count, std::mt19937& random) {
  std::vector<double> area;
  for (const auto& t : mesh.triangles)
    area.push_back(0.5 * (mesh.vertices_m[t[1]] - mesh.vertices_m[t[0]]).cross(mesh.vertices_m[t[2]] - mesh.vertices_m[t[0]]).norm());
  std::discrete_distribution<int> pick(area.begin(), area.end());
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<Vector3d> out(mesh.vertices_m.begin(), mesh.vertices_m.end());
  for (int k = 0; k < count; ++k) {
    const auto& t = mesh.triangles[pick(random)];
    double u = unit(random), v = unit(random);
    if (u + v > 1) u = 1 - u, v = 1 - v;
    const Vector3d& a = mesh.vertices_m[t[0]];
    out.push_back(a + u * (mesh.vertices_m[t[1]] - a) + v * (mesh.vertices_m[t[2]] - a));
  }
  return out;
}

// Ray parity along a direction no mesh edge or face is likely to line up with.
bool inside_mesh(const geometry::TriangleMesh& mesh, const Vector3d& p) {
  const Vector3d d = Vector3d(0.1234, 0.5678, 0.8137).normalized();
  int crossings = 0;
  for (const auto& t : mesh.triangles) {  // Moller-Trumbore
    const Vector3d& a = mesh.vertices_m[t[0]];
    const Vector3d e1 = mesh.vertices_m[t[1]] - a, e2 = mesh.vertices_m[t[2]] - a;
    const Vector3d h = d.cross(e2);
    const double det = e1.dot(h);
    if (std::abs(det) < 1e-300) continue;
    const Vector3d s = p - a;
    const double u = s.dot(h) / det;
    if (u < 0 || u > 1) continue;
    const Vector3d q = s.cross(e1);
    const double v = d.dot(q) / det;
    if (v < 0 || u + v > 1) continue;
    if (e2.dot(q) / det > 0) ++crossings;
  }
  return crossings % 2 == 1;
}

double distance_to_mesh(const geometry::TriangleMesh& mesh, const Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : mesh.triangles)
    best = std::min(best, collision::point_triangle_distance(p, mesh.vertices_m[t[0]], mesh.vertices_m[t[1]], mesh.vertices_m[t[2]]));
  return best;
}

double distance_to_pieces(const std::vector<collision::ConvexPiece>& pieces, const Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& piece : pieces) best = std::min(best, std::max(0.0, collision::signed_distance(piece, p)));
  return best;
}

double length(const Intervals& intervals) {
  double sum = 0;
  for (const auto& [lo, hi] : intervals) sum += hi - lo;
  return sum;
}

// The vertical line through (x, y) inside the mesh (parity of its crossings) and inside
// the pieces' union.
std::pair<Intervals, Intervals> column(const geometry::TriangleMesh& mesh, const std::vector<collision::ConvexPiece>& pieces,
                                       double x, double y) {
  std::vector<double> z;
  for (const auto& t : mesh.triangles) {
    const Vector3d &a = mesh.vertices_m[t[0]], &b = mesh.vertices_m[t[1]], &c = mesh.vertices_m[t[2]];
    const double det = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
    if (det == 0) continue;
    const double u = ((x - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (y - a.y())) / det;
    const double v = ((b.x() - a.x()) * (y - a.y()) - (x - a.x()) * (b.y() - a.y())) / det;
    if (u < 0 || v < 0 || u + v > 1) continue;
    z.push_back(a.z() + u * (b.z() - a.z()) + v * (c.z() - a.z()));
  }
  std::sort(z.begin(), z.end());
  Intervals in_mesh;
  if (z.size() % 2 == 0)
    for (std::size_t k = 0; k < z.size(); k += 2) in_mesh.emplace_back(z[k], z[k + 1]);
  Intervals in_pieces;
  for (const auto& piece : pieces) {
    double lo = -std::numeric_limits<double>::infinity(), hi = -lo;
    for (const auto& f : piece.faces()) {
      const double rhs = f.offset_m - f.normal.x() * x - f.normal.y() * y;
      if (std::abs(f.normal.z()) < 1e-12) {
        if (rhs < 0) hi = lo - 1;
      } else if (f.normal.z() > 0) {
        hi = std::min(hi, rhs / f.normal.z());
      } else {
        lo = std::max(lo, rhs / f.normal.z());
      }
    }
    if (hi > lo) in_pieces.emplace_back(lo, hi);
  }
  std::sort(in_pieces.begin(), in_pieces.end());
  Intervals merged;
  for (const auto& i : in_pieces)
    if (!merged.empty() && i.first <= merged.back().second)
      merged.back().second = std::max(merged.back().second, i.second);
    else
      merged.push_back(i);
  return {in_mesh, merged};
}

Intervals intersection(const Intervals& a, const Intervals& b) {
  Intervals out;
  for (std::size_t i = 0, j = 0; i < a.size() && j < b.size();) {
    const double lo = std::max(a[i].first, b[j].first), hi = std::min(a[i].second, b[j].second);
    if (hi > lo) out.emplace_back(lo, hi);
    (a[i].second < b[j].second) ? ++i : ++j;
  }
  return out;
}

}  // namespace

ApproximationError approximation_error(const geometry::TriangleMesh& mesh, const std::vector<collision::ConvexPiece>& pieces,
                                       int samples_per_side, int columns) {
  ApproximationError e;
  e.samples = samples_per_side;
  std::mt19937 random(1);
  for (const Vector3d& p : surface_samples(mesh, samples_per_side, random))
    e.mesh_to_pieces_m = std::max(e.mesh_to_pieces_m, distance_to_pieces(pieces, p));
  for (const auto& piece : pieces)
    for (const Vector3d& p : surface_samples(piece.hull(), samples_per_side / static_cast<int>(pieces.size()), random))
      if (!inside_mesh(mesh, p)) e.pieces_to_mesh_m = std::max(e.pieces_to_mesh_m, distance_to_mesh(mesh, p));
  for (const auto& t : mesh.triangles)
    e.mesh_volume_m3 += mesh.vertices_m[t[0]].dot(mesh.vertices_m[t[1]].cross(mesh.vertices_m[t[2]])) / 6.0;
  Eigen::AlignedBox3d box = mesh.bounds();
  for (const auto& piece : pieces) {
    e.pieces_volume_sum_m3 += piece.volume_m3();
    box.extend(piece.hull().bounds());
  }
  const double dx = box.sizes().x() / columns, dy = box.sizes().y() / columns;
  for (int i = 0; i < columns; ++i)
    for (int j = 0; j < columns; ++j) {
      const auto [in_mesh, in_pieces] = column(mesh, pieces, box.min().x() + (i + 0.5) * dx, box.min().y() + (j + 0.5) * dy);
      e.union_volume_m3 += length(in_pieces) * dx * dy;
      e.intersection_volume_m3 += length(intersection(in_mesh, in_pieces)) * dx * dy;
    }
  return e;
}

}  // namespace arphys::tools

#include "tools/models/convex_decomposition.hpp"

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include <HACD/hacdHACD.h>

#include <cstdio>
#include <stdexcept>

namespace arphys::tools {

geometry::TriangleMesh convex_hull(const std::vector<Eigen::Vector3d>& points) {
  if (points.size() < 4) throw std::runtime_error("convex_hull: " + std::to_string(points.size()) + " points, need 4");
  std::vector<coordT> coordinates;
  coordinates.reserve(3 * points.size());
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) {
    coordinates.insert(coordinates.end(), {p.x(), p.y(), p.z()});
    centroid += p / static_cast<double>(points.size());
  }
  qhT context;
  qhT* qh = &context;
  qh_zero(qh, stderr);
  char command[] = "qhull Qt";  // triangulated facets; coplanar ones are merged back by ConvexPiece
  const int code = qh_new_qhull(qh, 3, static_cast<int>(points.size()), coordinates.data(), False, command, nullptr, stderr);
  geometry::TriangleMesh hull;
  if (code == 0) {
    std::vector<int> renumbered(points.size(), -1);
    facetT* facet;
    FORALLfacets {
      vertexT *vertex, **vertexp;
      Eigen::Vector3i t;
      int k = 0;
      FOREACHvertex_(facet->vertices) {
        if (k == 3) break;
        const int id = qh_pointid(qh, vertex->point);
        if (renumbered[id] < 0) {
          renumbered[id] = static_cast<int>(hull.vertices_m.size());
          hull.vertices_m.push_back(points[id]);
        }
        t[k++] = renumbered[id];
      }
      if (k != 3) continue;
      const Eigen::Vector3d& a = hull.vertices_m[t[0]];
      const Eigen::Vector3d n = (hull.vertices_m[t[1]] - a).cross(hull.vertices_m[t[2]] - a);
      if (n.dot(a - centroid) < 0) std::swap(t[1], t[2]);  // wound outward
      hull.triangles.push_back(t);
    }
  }
  qh_freeqhull(qh, !qh_ALL);
  int still_long = 0, total_long = 0;
  qh_memfreeshort(qh, &still_long, &total_long);
  if (code != 0 || hull.triangles.size() < 4) throw std::runtime_error("convex_hull: qhull failed (flat point set?)");
  return hull;
}

std::vector<geometry::TriangleMesh> decompose_convex(const geometry::TriangleMesh& mesh,
                                                     const DecompositionOptions& options) {
  std::vector<HACD::Vec3<HACD::Real>> points;
  for (const Eigen::Vector3d& v : mesh.vertices_m) points.emplace_back(v.x(), v.y(), v.z());
  std::vector<HACD::Vec3<long>> triangles;
  for (const Eigen::Vector3i& t : mesh.triangles) triangles.emplace_back(t[0], t[1], t[2]);
  HACD::HACD hacd;
  hacd.SetPoints(points.data());
  hacd.SetNPoints(points.size());
  hacd.SetTriangles(triangles.data());
  hacd.SetNTriangles(triangles.size());
  hacd.SetCompacityWeight(0.1);
  hacd.SetVolumeWeight(0.0);
  hacd.SetNClusters(static_cast<std::size_t>(options.min_pieces));
  hacd.SetNVerticesPerCH(static_cast<std::size_t>(options.max_vertices_per_piece));
  // HACD measures concavity in its normalised frame (the mesh scaled to a diagonal of
  // its scale factor, 1000 by default).
  hacd.SetConcavity(options.max_concavity * hacd.GetScaleFactor());
  hacd.SetAddExtraDistPoints(true);
  hacd.SetAddFacesPoints(true);
  hacd.SetAddNeighboursDistPoints(false);
  if (!hacd.Compute()) throw std::runtime_error("HACD failed on the mesh");
  std::vector<geometry::TriangleMesh> pieces;
  for (std::size_t c = 0; c < hacd.GetNClusters(); ++c) {
    std::vector<HACD::Vec3<HACD::Real>> hull_points(hacd.GetNPointsCH(c));
    std::vector<HACD::Vec3<long>> hull_triangles(hacd.GetNTrianglesCH(c));
    hacd.GetCH(c, hull_points.data(), hull_triangles.data());
    std::vector<Eigen::Vector3d> cloud;
    for (const auto& p : hull_points) cloud.emplace_back(p.X(), p.Y(), p.Z());
    try {
      pieces.push_back(convex_hull(cloud));
    } catch (const std::runtime_error& e) {
      std::fprintf(stderr, "convex-decompose: cluster %zu skipped (%s)\n", c, e.what());
    }
  }
  if (pieces.empty()) throw std::runtime_error("HACD gave no usable cluster");
  return pieces;
}

}  // namespace arphys::tools

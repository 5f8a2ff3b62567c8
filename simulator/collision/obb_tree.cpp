#include "simulator/collision/obb_tree.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <limits>
#include <stdexcept>

namespace arphys::collision {
namespace {

Obb box_with_axes(const geometry::TriangleMesh& mesh, const int* triangles, int count, const Eigen::Matrix3d& axes) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector3i& t = mesh.triangles[triangles[i]];
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d p = axes.transpose() * mesh.vertices_m[t[k]];
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  Obb box;
  box.axes = axes;
  box.center = axes * (0.5 * (lo + hi));
  box.half_extents_m = 0.5 * (hi - lo);
  box.radius_m = box.half_extents_m.norm() * (1 + 1e-15);
  return box;
}

}  // namespace

Obb fit_obb(const geometry::TriangleMesh& mesh, const int* triangles, int count) {
  if (count == 1) {
    // A single triangle: its own frame gives a box of zero thickness.
    const Eigen::Vector3i& t = mesh.triangles[triangles[0]];
    const Eigen::Vector3d a = mesh.vertices_m[t[0]], b = mesh.vertices_m[t[1]], c = mesh.vertices_m[t[2]];
    Eigen::Vector3d x = b - a;
    if ((c - b).squaredNorm() > x.squaredNorm()) x = c - b;
    if ((a - c).squaredNorm() > x.squaredNorm()) x = a - c;
    const Eigen::Vector3d z = (b - a).cross(c - a).normalized();
    x.normalize();
    Eigen::Matrix3d axes;
    axes << x, z.cross(x), z;
    return box_with_axes(mesh, triangles, count, axes);
  }
  // Covariance of the union of triangle surfaces (Gottschalk 1996, eq. for the
  // continuous covariance of a triangle: area/12 (9 m m^T + sum p p^T) ).
  double total_area = 0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector3i& t = mesh.triangles[triangles[i]];
    const Eigen::Vector3d a = mesh.vertices_m[t[0]], b = mesh.vertices_m[t[1]], c = mesh.vertices_m[t[2]];
    const double area = 0.5 * (b - a).cross(c - a).norm();
    const Eigen::Vector3d m = (a + b + c) / 3.0;
    total_area += area;
    mean += area * m;
    second += (area / 12.0) * (9.0 * m * m.transpose() + a * a.transpose() + b * b.transpose() + c * c.transpose());
  }
  mean /= total_area;
  const Eigen::Matrix3d covariance = second / total_area - mean * mean.transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  Eigen::Matrix3d axes = solver.eigenvectors();
  if (!axes.allFinite()) axes.setIdentity();
  axes.col(2) = axes.col(0).cross(axes.col(1));  // right-handed, orthonormal
  return box_with_axes(mesh, triangles, count, axes);
}

ObbTree::ObbTree(const geometry::TriangleMesh& mesh) : mesh_(&mesh) {
  const double diagonal = mesh.bounds().diagonal().norm();
  const double min_area = 1e-12 * diagonal * diagonal;
  std::vector<int> triangles;
  triangles.reserve(mesh.triangles.size());
  for (int i = 0; i < static_cast<int>(mesh.triangles.size()); ++i) {
    const Eigen::Vector3i& t = mesh.triangles[i];
    const bool repeated = t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
    const double area = repeated ? 0.0
                                 : 0.5 * (mesh.vertices_m[t[1]] - mesh.vertices_m[t[0]])
                                             .cross(mesh.vertices_m[t[2]] - mesh.vertices_m[t[0]])
                                             .norm();
    if (repeated || !(area > min_area)) {
      ++degenerate_skipped_;
      continue;
    }
    triangles.push_back(i);
  }
  if (triangles.empty()) throw std::invalid_argument("ObbTree: the mesh has no non-degenerate triangle");
  nodes_.reserve(2 * triangles.size());
  nodes_.emplace_back();
  build(0, triangles, 0, static_cast<int>(triangles.size()), 0);
  for (const ObbNode& node : nodes_)
    reach_m_ = std::max(reach_m_, (node.box.center - root().box.center).norm() + node.box.radius_m);
}

void ObbTree::build(int node, std::vector<int>& triangles, int begin, int end, int depth) {
  depth_ = std::max(depth_, depth);
  const int count = end - begin;
  nodes_[node].box = fit_obb(*mesh_, triangles.data() + begin, count);
  if (count == 1) {
    nodes_[node].triangle = triangles[begin];
    return;
  }
  // Split at the mean centroid along the box's longest axis; fall back to the other
  // axes, then to the median, so that both halves are never empty.
  const Obb& box = nodes_[node].box;
  auto centroid = [&](int tri) {
    const Eigen::Vector3i& t = mesh_->triangles[tri];
    return (mesh_->vertices_m[t[0]] + mesh_->vertices_m[t[1]] + mesh_->vertices_m[t[2]]) / 3.0;
  };
  int order[3] = {0, 1, 2};
  std::sort(order, order + 3, [&](int a, int b) { return box.half_extents_m[a] > box.half_extents_m[b]; });
  int middle = begin;
  for (int axis_index : order) {
    const Eigen::Vector3d axis = box.axes.col(axis_index);
    double mean = 0;
    for (int i = begin; i < end; ++i) mean += axis.dot(centroid(triangles[i]));
    mean /= count;
    middle = static_cast<int>(std::partition(triangles.begin() + begin, triangles.begin() + end,
                                             [&](int tri) { return axis.dot(centroid(tri)) < mean; }) -
                              triangles.begin());
    if (middle > begin && middle < end) break;
  }
  if (middle == begin || middle == end) {
    middle = begin + count / 2;
    const Eigen::Vector3d axis = box.axes.col(order[0]);
    std::nth_element(triangles.begin() + begin, triangles.begin() + middle, triangles.begin() + end,
                     [&](int a, int b) { return axis.dot(centroid(a)) < axis.dot(centroid(b)); });
  }
  const int first_child = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  nodes_.emplace_back();
  nodes_[node].first_child = first_child;
  build(first_child, triangles, begin, middle, depth + 1);
  build(first_child + 1, triangles, middle, end, depth + 1);
}

}  // namespace arphys::collision

#pragma once
// Exact (double precision) distances between triangle features, for the discrete
// queries, the verification of candidate contacts, and the tests' oracles.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace arphys::collision {

Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a0,
                                         const Eigen::Vector3d& a1, const Eigen::Vector3d& a2);
double point_triangle_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a0, const Eigen::Vector3d& a1,
                               const Eigen::Vector3d& a2);
double segment_segment_distance(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& q0,
                                const Eigen::Vector3d& q1, Eigen::Vector3d* closest_on_p = nullptr,
                                Eigen::Vector3d* closest_on_q = nullptr);

// True when the segment p0 p1 passes through the closed triangle (a segment lying in
// the triangle's plane does not count: such contacts are edge/edge ones).
bool segment_crosses_triangle(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& a,
                              const Eigen::Vector3d& b, const Eigen::Vector3d& c);

// Distance between two triangles, 0 when they intersect; optionally the closest points.
double triangle_triangle_distance(const Eigen::Vector3d a[3], const Eigen::Vector3d b[3],
                                  Eigen::Vector3d* closest_on_a = nullptr, Eigen::Vector3d* closest_on_b = nullptr);

}  // namespace arphys::collision

#include "simulator/collision/triangle_distance.hpp"

#include <algorithm>
#include <limits>

namespace arphys::collision {

Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                         const Eigen::Vector3d& c) {
  // Ericson, Real-Time Collision Detection, 5.1.5 (closest point by Voronoi regions).
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

double point_triangle_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                               const Eigen::Vector3d& c) {
  return (p - closest_point_on_triangle(p, a, b, c)).norm();
}

double segment_segment_distance(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& q0,
                                const Eigen::Vector3d& q1, Eigen::Vector3d* closest_on_p, Eigen::Vector3d* closest_on_q) {
  // Ericson 5.1.9, with the parallel and degenerate cases clamped.
  const Eigen::Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0, t = 0;
  if (a <= 0 && e <= 0) {
    s = t = 0;
  } else if (a <= 0) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= 0) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  const Eigen::Vector3d cp = p0 + s * d1, cq = q0 + t * d2;
  if (closest_on_p) *closest_on_p = cp;
  if (closest_on_q) *closest_on_q = cq;
  return (cp - cq).norm();
}

bool segment_crosses_triangle(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& a,
                              const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d n = (b - a).cross(c - a);
  const double d0 = n.dot(p0 - a), d1 = n.dot(p1 - a);
  if ((d0 > 0 && d1 > 0) || (d0 < 0 && d1 < 0) || d0 == d1) return false;  // same side, or in the plane
  const Eigen::Vector3d x = p0 + (d0 / (d0 - d1)) * (p1 - p0);
  // Inside when x is on the inner side of all three edges (closed triangle).
  return n.dot((b - a).cross(x - a)) >= 0 && n.dot((c - b).cross(x - b)) >= 0 && n.dot((a - c).cross(x - c)) >= 0;
}

double triangle_triangle_distance(const Eigen::Vector3d a[3], const Eigen::Vector3d b[3], Eigen::Vector3d* closest_on_a,
                                  Eigen::Vector3d* closest_on_b) {
  for (int i = 0; i < 3; ++i) {
    if (segment_crosses_triangle(a[i], a[(i + 1) % 3], b[0], b[1], b[2]) ||
        segment_crosses_triangle(b[i], b[(i + 1) % 3], a[0], a[1], a[2])) {
      if (closest_on_a) *closest_on_a = a[i];
      if (closest_on_b) *closest_on_b = a[i];
      return 0.0;
    }
  }
  // Disjoint triangles: the closest pair is a vertex/face or an edge/edge pair.
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector3d best_a = a[0], best_b = b[0];
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d on_b = closest_point_on_triangle(a[i], b[0], b[1], b[2]);
    if (const double d = (a[i] - on_b).norm(); d < best) best = d, best_a = a[i], best_b = on_b;
    const Eigen::Vector3d on_a = closest_point_on_triangle(b[i], a[0], a[1], a[2]);
    if (const double d = (b[i] - on_a).norm(); d < best) best = d, best_a = on_a, best_b = b[i];
    for (int j = 0; j < 3; ++j) {
      Eigen::Vector3d pa, pb;
      const double d = segment_segment_distance(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3], &pa, &pb);
      if (d < best) best = d, best_a = pa, best_b = pb;
    }
  }
  if (closest_on_a) *closest_on_a = best_a;
  if (closest_on_b) *closest_on_b = best_b;
  return best;
}

}  // namespace arphys::collision

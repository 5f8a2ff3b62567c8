#include "simulator/collision/convex_distance.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace arphys::collision {
namespace {

using Eigen::Vector3d;

// A simplex of points of the Minkowski difference B - A, reduced after each step to the
// smallest face that holds its point nearest the origin.
struct Simplex {
  std::array<Vector3d, 4> p;
  int size = 0;
};

// The point of triangle abc nearest the origin, keeping in s only the corners it needs
// (Ericson, Real-Time Collision Detection, 5.1.5, with the origin as the query point).
Vector3d nearest_on_triangle(Simplex& s) {
  const Vector3d a = s.p[0], b = s.p[1], c = s.p[2];
  const Vector3d ab = b - a, ac = c - a, ap = -a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  const auto keep = [&](std::initializer_list<Vector3d> corners) {
    s.size = 0;
    for (const Vector3d& x : corners) s.p[s.size++] = x;
  };
  if (d1 <= 0 && d2 <= 0) {
    keep({a});
    return a;
  }
  const Vector3d bp = -b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) {
    keep({b});
    return b;
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    keep({a, b});
    return Vector3d(a + (d1 / (d1 - d3)) * ab);
  }
  const Vector3d cp = -c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) {
    keep({c});
    return c;
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    keep({a, c});
    return Vector3d(a + (d2 / (d2 - d6)) * ac);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    {
    keep({b, c});
    return Vector3d(b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b));
  }
  const double denominator = 1 / (va + vb + vc);
  return a + ab * (vb * denominator) + ac * (vc * denominator);
}

Vector3d nearest_on_segment(Simplex& s) {
  const Vector3d a = s.p[0], ab = s.p[1] - s.p[0];
  const double t = -a.dot(ab) / ab.squaredNorm();
  if (!(t > 0)) {
    s.size = 1;
    return a;
  }
  if (t >= 1) {
    s.p[0] = s.p[1];
    s.size = 1;
    return s.p[0];
  }
  return a + t * ab;
}

// The point of the simplex nearest the origin; false when the origin is inside it.
bool nearest(Simplex& s, Vector3d* v) {
  switch (s.size) {
    case 1: *v = s.p[0]; return true;
    case 2: *v = nearest_on_segment(s); return true;
    case 3: *v = nearest_on_triangle(s); return true;
    default: break;
  }
  // A tetrahedron: the origin is inside unless some face separates it from the opposite corner.
  static constexpr int kFaces[4][4] = {{0, 1, 2, 3}, {0, 1, 3, 2}, {0, 2, 3, 1}, {1, 2, 3, 0}};
  double best = std::numeric_limits<double>::infinity();
  Simplex best_face;
  bool outside = false;
  for (const auto& f : kFaces) {
    const Vector3d n = (s.p[f[1]] - s.p[f[0]]).cross(s.p[f[2]] - s.p[f[0]]);
    const double origin_side = -n.dot(s.p[f[0]]), corner_side = n.dot(s.p[f[3]] - s.p[f[0]]);
    if (origin_side * corner_side >= 0) continue;  // the origin is on the corner's side of this face
    outside = true;
    Simplex face;
    face.size = 3;
    face.p = {s.p[f[0]], s.p[f[1]], s.p[f[2]], Vector3d::Zero()};
    const Vector3d x = nearest_on_triangle(face);
    if (x.squaredNorm() < best) {
      best = x.squaredNorm();
      best_face = face;
      *v = x;
    }
  }
  if (!outside) return false;
  s = best_face;
  return true;
}

}  // namespace

ConvexDistance convex_distance(const ConvexPiece& A, const geometry::Pose& X_WA, const ConvexPiece& B,
                               const geometry::Pose& X_WB, double enough_m, double tolerance_m) {
  const geometry::Pose X_AB = X_WA.inverse() * X_WB;
  const Eigen::Matrix3d R_BA = X_AB.linear().transpose();
  // The point of B - A (A's frame) furthest along -u: its gap along u is the lower bound.
  const auto support = [&](const Vector3d& u) {
    return Vector3d(X_AB * B.vertices_m()[B.support(-(R_BA * u))] - A.vertices_m()[A.support(u)]);
  };
  ConvexDistance out;
  out.lower_m = -std::numeric_limits<double>::infinity();
  Simplex s;
  Vector3d v = support(X_AB * B.centroid_m() - A.centroid_m());
  s.p[0] = v;
  s.size = 1;
  for (out.iterations = 1; out.iterations <= 64; ++out.iterations) {
    const double length = v.norm();
    out.upper_m = length;
    if (length == 0) break;  // the origin is a point of the difference: touching
    const Vector3d u = v / length;
    const Vector3d w = support(u);
    if (const double gap = u.dot(w); gap > out.lower_m) {
      out.lower_m = gap;
      out.axis_W = X_WA.linear() * u;
    }
    if (out.lower_m > enough_m || length - out.lower_m <= tolerance_m) break;
    s.p[s.size++] = w;
    Vector3d next;
    if (!nearest(s, &next)) {  // the origin inside: overlapping
      out.upper_m = 0;
      break;
    }
    if (next.norm() >= length * (1 - 1e-12)) break;  // no progress left in double precision
    v = next;
  }
  return out;
}

bool convex_sets_apart_by(const ConvexSet& A, const geometry::Pose& X_WA, const ConvexSet& B,
                          const geometry::Pose& X_WB, double gap_m) {
  for (const ConvexPiece& a : A.pieces) {
    const Vector3d c_a = X_WA * a.centroid_m();
    for (const ConvexPiece& b : B.pieces) {
      if ((X_WB * b.centroid_m() - c_a).norm() - a.radius_m() - b.radius_m() > gap_m) continue;
      if (!(convex_distance(a, X_WA, b, X_WB, gap_m).lower_m > gap_m)) return false;
    }
  }
  return true;
}

}  // namespace arphys::collision

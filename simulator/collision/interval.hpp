#pragma once
// Interval arithmetic with outward rounding (Moore; Snyder, SIGGRAPH 1992), for the
// continuous culling and the certified root isolation of the elementary tests.
//
// Rounding: every operation is computed in round-to-nearest and its bounds are then
// pushed outwards by |x| * 2^-51 + 2 * denorm_min. For a normal result x of one
// rounded operation, the exact value lies within 0.5 ulp(x) <= |x| 2^-53 of x, and
// the push (>= 1 ulp(x)) survives its own rounding with at least 0.5 ulp to spare,
// so [lo, hi] always contains the exact result (proof in docs/ccd.md). Overflow to
// infinity stays infinite, which is still an enclosure. This costs one FMA-able
// multiply-add per bound instead of a change of the FPU rounding mode.
#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace arphys::collision {

namespace interval_detail {
constexpr double kRelative = 0x1p-51;
constexpr double kAbsolute = 2 * std::numeric_limits<double>::denorm_min();
inline double down(double x) { return x - (std::abs(x) * kRelative + kAbsolute); }
inline double up(double x) { return x + (std::abs(x) * kRelative + kAbsolute); }
}  // namespace interval_detail

struct Interval {
  double lo = 0, hi = 0;

  Interval() = default;
  constexpr explicit Interval(double point) : lo(point), hi(point) {}
  constexpr Interval(double lower, double upper) : lo(lower), hi(upper) {}

  double width() const { return hi - lo; }
  double mid() const { return 0.5 * (lo + hi); }
  bool contains(double x) const { return lo <= x && x <= hi; }
  bool contains_zero() const { return lo <= 0 && 0 <= hi; }
  // Magnitude (largest |x|) and mignitude (smallest |x|) over the interval.
  double mag() const { return std::max(std::abs(lo), std::abs(hi)); }
  double mig() const { return contains_zero() ? 0.0 : std::min(std::abs(lo), std::abs(hi)); }
  // Outward-rounded enclosure of a value computed with an error of at most `ulps` ulps.
  static Interval around(double value, double ulps) {
    const double e = std::abs(value) * ulps * 0x1p-52 + interval_detail::kAbsolute;
    return {interval_detail::down(value - e), interval_detail::up(value + e)};
  }
};

inline Interval hull(const Interval& a, const Interval& b) { return {std::min(a.lo, b.lo), std::max(a.hi, b.hi)}; }

inline Interval operator+(const Interval& a, const Interval& b) {
  return {interval_detail::down(a.lo + b.lo), interval_detail::up(a.hi + b.hi)};
}
// [a, b] - [c, d] = [a - d, b - c]  (docs/method.md notes the paper's equation (7) typo).
inline Interval operator-(const Interval& a, const Interval& b) {
  return {interval_detail::down(a.lo - b.hi), interval_detail::up(a.hi - b.lo)};
}
inline Interval operator-(const Interval& a) { return {-a.hi, -a.lo}; }
inline Interval operator*(const Interval& a, const Interval& b) {
  const double p1 = a.lo * b.lo, p2 = a.lo * b.hi, p3 = a.hi * b.lo, p4 = a.hi * b.hi;
  return {interval_detail::down(std::min(std::min(p1, p2), std::min(p3, p4))),
          interval_detail::up(std::max(std::max(p1, p2), std::max(p3, p4)))};
}
inline Interval operator*(double s, const Interval& a) {
  return s >= 0 ? Interval{interval_detail::down(s * a.lo), interval_detail::up(s * a.hi)}
                : Interval{interval_detail::down(s * a.hi), interval_detail::up(s * a.lo)};
}
inline Interval operator+(const Interval& a, double s) { return {interval_detail::down(a.lo + s), interval_detail::up(a.hi + s)}; }
inline Interval operator-(const Interval& a, double s) { return {interval_detail::down(a.lo - s), interval_detail::up(a.hi - s)}; }
// 1 / [a, b] = [1/b, 1/a] when 0 is not in [a, b]; the whole line otherwise.
inline Interval reciprocal(const Interval& a) {
  if (a.contains_zero()) return {-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  return {interval_detail::down(1.0 / a.hi), interval_detail::up(1.0 / a.lo)};
}
inline Interval operator/(const Interval& a, const Interval& b) { return a * reciprocal(b); }
inline Interval abs(const Interval& a) { return {a.mig(), a.mag()}; }
inline Interval square(const Interval& a) {
  const double m = a.mig(), M = a.mag();
  return {interval_detail::down(m * m), interval_detail::up(M * M)};
}

// sin and cos of the angle interval [a, b] (radians, any range), enclosing the libm
// error (glibc: < 1 ulp) and the extrema reached inside the interval.
Interval sin(const Interval& angle_rad);
Interval cos(const Interval& angle_rad);

// Interval 3-vectors and 3x3 matrices, and their products with exact (double) ones.
struct IVec3 {
  Interval v[3];
  Interval& operator[](int i) { return v[i]; }
  const Interval& operator[](int i) const { return v[i]; }
  static IVec3 point(const Eigen::Vector3d& p) { return {{Interval(p.x()), Interval(p.y()), Interval(p.z())}}; }
  Eigen::Vector3d mid() const { return {v[0].mid(), v[1].mid(), v[2].mid()}; }
  double max_width() const { return std::max({v[0].width(), v[1].width(), v[2].width()}); }
};

inline IVec3 operator+(const IVec3& a, const IVec3& b) { return {{a[0] + b[0], a[1] + b[1], a[2] + b[2]}}; }
inline IVec3 operator-(const IVec3& a, const IVec3& b) { return {{a[0] - b[0], a[1] - b[1], a[2] - b[2]}}; }
inline IVec3 operator-(const IVec3& a, const Eigen::Vector3d& b) { return {{a[0] - b.x(), a[1] - b.y(), a[2] - b.z()}}; }
inline IVec3 operator+(const IVec3& a, const Eigen::Vector3d& b) { return {{a[0] + b.x(), a[1] + b.y(), a[2] + b.z()}}; }
// Interval scalar times an exact vector.
inline IVec3 operator*(const Interval& s, const Eigen::Vector3d& v) { return {{v.x() * s, v.y() * s, v.z() * s}}; }
inline Interval dot(const IVec3& a, const Eigen::Vector3d& b) { return b.x() * a[0] + b.y() * a[1] + b.z() * a[2]; }
inline Interval dot(const IVec3& a, const IVec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline IVec3 cross(const IVec3& a, const IVec3& b) {
  return {{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}};
}
inline IVec3 cross(const Eigen::Vector3d& a, const IVec3& b) {
  return {{a.y() * b[2] - a.z() * b[1], a.z() * b[0] - a.x() * b[2], a.x() * b[1] - a.y() * b[0]}};
}

struct IMat3 {
  Interval m[3][3];
  static IMat3 point(const Eigen::Matrix3d& M) {
    IMat3 out;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) out.m[i][j] = Interval(M(i, j));
    return out;
  }
  IMat3 transpose() const {
    IMat3 out;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) out.m[i][j] = m[j][i];
    return out;
  }
};

inline IVec3 operator*(const IMat3& A, const IVec3& x) {
  IVec3 out;
  for (int i = 0; i < 3; ++i) out[i] = A.m[i][0] * x[0] + A.m[i][1] * x[1] + A.m[i][2] * x[2];
  return out;
}
inline IVec3 operator*(const IMat3& A, const Eigen::Vector3d& x) {
  IVec3 out;
  for (int i = 0; i < 3; ++i) out[i] = x.x() * A.m[i][0] + x.y() * A.m[i][1] + x.z() * A.m[i][2];
  return out;
}
inline IVec3 operator*(const Eigen::Matrix3d& A, const IVec3& x) {
  IVec3 out;
  for (int i = 0; i < 3; ++i) out[i] = A(i, 0) * x[0] + A(i, 1) * x[1] + A(i, 2) * x[2];
  return out;
}
inline IMat3 operator*(const IMat3& A, const IMat3& B) {
  IMat3 out;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out.m[i][j] = A.m[i][0] * B.m[0][j] + A.m[i][1] * B.m[1][j] + A.m[i][2] * B.m[2][j];
  return out;
}
inline IMat3 operator*(const IMat3& A, const Eigen::Matrix3d& B) {
  IMat3 out;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out.m[i][j] = B(0, j) * A.m[i][0] + B(1, j) * A.m[i][1] + B(2, j) * A.m[i][2];
  return out;
}
inline IMat3 operator*(const Eigen::Matrix3d& A, const IMat3& B) {
  IMat3 out;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out.m[i][j] = A(i, 0) * B.m[0][j] + A(i, 1) * B.m[1][j] + A(i, 2) * B.m[2][j];
  return out;
}

// An interval matrix or vector in midpoint-radius form (Rump): every value it stands
// for lies within `rad` (componentwise, rounded up) of `mid`.
struct MidRadMatrix {
  Eigen::Matrix3d mid, rad;
  IMat3 to_interval() const;
};
struct MidRadVector {
  Eigen::Vector3d mid, rad;
  static MidRadVector from(const IVec3& v);
  IVec3 to_interval() const;
};

}  // namespace arphys::collision

#include "simulator/collision/interval.hpp"

namespace arphys::collision {
namespace {

// glibc's sin/cos are correctly rounded to within 1 ulp; allow 2, plus an absolute
// term for results near zero where ulps shrink.
constexpr double kLibmUlps = 2.0;

Interval libm_enclosure(double value) {
  Interval r = Interval::around(value, kLibmUlps);
  r.lo -= 0x1p-60;
  r.hi += 0x1p-60;
  return {std::max(r.lo, -1.0), std::min(r.hi, 1.0)};
}

// Encloses f over [lo, hi] for f = cos or sin, given the phase where f reaches its
// maximum (0 for cos, pi/2 for sin); the minima are half a period later. The extremum
// tests compare outward-rounded quantities, so a boundary extremum is never missed.
Interval periodic_enclosure(const Interval& angle, double (*f)(double), double max_phase) {
  if (!(angle.width() < 2 * M_PI)) return {-1, 1};
  Interval out = hull(libm_enclosure(f(angle.lo)), libm_enclosure(f(angle.hi)));
  const double k_max = std::ceil(interval_detail::down((interval_detail::down(angle.lo - max_phase)) / (2 * M_PI)));
  if (interval_detail::down(k_max * 2 * M_PI + max_phase) <= angle.hi) out.hi = 1.0;
  const double min_phase = max_phase + M_PI;
  const double k_min = std::ceil(interval_detail::down((interval_detail::down(angle.lo - min_phase)) / (2 * M_PI)));
  if (interval_detail::down(k_min * 2 * M_PI + min_phase) <= angle.hi) out.lo = -1.0;
  return out;
}

}  // namespace

Interval cos(const Interval& angle) { return periodic_enclosure(angle, static_cast<double (*)(double)>(std::cos), 0.0); }
Interval sin(const Interval& angle) { return periodic_enclosure(angle, static_cast<double (*)(double)>(std::sin), M_PI_2); }

MidRadVector MidRadVector::from(const IVec3& v) {
  MidRadVector out;
  for (int i = 0; i < 3; ++i) {
    out.mid[i] = v[i].mid();
    out.rad[i] = interval_detail::up(std::max(v[i].hi - out.mid[i], out.mid[i] - v[i].lo));
  }
  return out;
}

IMat3 MidRadMatrix::to_interval() const {
  IMat3 out;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      out.m[i][j] = {interval_detail::down(mid(i, j) - rad(i, j)), interval_detail::up(mid(i, j) + rad(i, j))};
  return out;
}

IVec3 MidRadVector::to_interval() const {
  IVec3 out;
  for (int i = 0; i < 3; ++i) out[i] = {interval_detail::down(mid[i] - rad[i]), interval_detail::up(mid[i] + rad[i])};
  return out;
}

}  // namespace arphys::collision

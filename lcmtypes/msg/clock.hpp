#pragma once
#include <cstdint>

namespace arphys::msg {

// Wall-clock time in microseconds since the Unix epoch: the `utime` of every message.
// System clock (not steady) so that stamps from different machines are comparable.
int64_t now_utime();
// Monotonic seconds (steady clock, arbitrary origin): for rates, periods and timeouts within a process.
double steady_s();

// Seconds between two utimes.
inline double utime_diff_s(int64_t later_utime, int64_t earlier_utime) {
  return static_cast<double>(later_utime - earlier_utime) * 1e-6;
}

}  // namespace arphys::msg

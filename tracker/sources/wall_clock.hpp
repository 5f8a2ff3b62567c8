#pragma once
#include <chrono>
#include <cstdint>

namespace arphys::tracking {

// Wall-clock time in microseconds since the Unix epoch, the time base of Frame::capture_utime
// and of the tracker's reports. The system clock, not the steady one, so that stamps taken on
// different machines compare (the same base as msg::now_utime, which this LCM-free library
// cannot use).
inline int64_t wall_clock_utime() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace arphys::tracking

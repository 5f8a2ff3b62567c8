#include "lcmtypes/msg/clock.hpp"

#include <chrono>

namespace arphys::msg {

int64_t now_utime() {
  using namespace std::chrono;
  return duration_cast<microseconds>(system_clock::now().time_since_epoch()).count();
}

double steady_s() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

}  // namespace arphys::msg

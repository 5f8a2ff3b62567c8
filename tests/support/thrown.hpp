#pragma once
// What a call throws as std::invalid_argument, for tests of refusals that name the value
// ("no exception" when it throws nothing; another exception propagates).
#include <functional>
#include <stdexcept>
#include <string>

namespace arphys::testing {

inline std::string invalid_argument_message(const std::function<void()>& call) {
  try {
    call();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no exception";
}

}  // namespace arphys::testing

#include "renderer/process/world_state_matcher.hpp"

#include <stdexcept>

namespace arphys::rendering {

MatchPolicy match_policy_from(const std::string& name) {
  if (name == "exact") return MatchPolicy::kExact;
  if (name == "nearest-earlier") return MatchPolicy::kNearestEarlier;
  if (name == "latest") return MatchPolicy::kLatest;
  throw std::invalid_argument("world-state match '" + name + "' (expected exact, nearest-earlier or latest)");
}

const char* to_string(MatchPolicy policy) {
  switch (policy) {
    case MatchPolicy::kExact: return "exact";
    case MatchPolicy::kNearestEarlier: return "nearest-earlier";
    case MatchPolicy::kLatest: return "latest";
  }
  return "?";
}

}  // namespace arphys::rendering

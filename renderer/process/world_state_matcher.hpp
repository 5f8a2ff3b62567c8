#pragma once
#include <algorithm>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>

namespace arphys::rendering {

// How the renderer picks the world state to draw over a camera frame.
enum class MatchPolicy {
  kExact,           // only the state computed from this very frame (same capture utime)
  kNearestEarlier,  // that one, else the newest state from an earlier frame (default)
  kLatest,          // the newest state received, whatever frame it came from
};
MatchPolicy match_policy_from(const std::string& name);  // throws std::invalid_argument naming the value
const char* to_string(MatchPolicy policy);

enum class MatchKind { kNone, kExact, kNearestEarlier, kLatest };

// A bounded history of states keyed by the capture utime they were computed from.
// States arrive in any order relative to frames; the history keeps the newest
// `capacity` by arrival.
template <class State>
class WorldStateMatcher {
 public:
  explicit WorldStateMatcher(std::size_t capacity = 256) : capacity_(capacity) {}

  // stamp: what tells this state from another computed from the same frame (the step's
  // end time); a state whose capture utime and stamp are both in the history already is a
  // re-sent or replayed copy, not kept: returns false. Stamp 0 is never a copy.
  bool add(int64_t capture_utime, State state, int64_t stamp = 0) {
    if (stamp != 0 && std::any_of(history_.begin(), history_.end(),
                                  [&](const Entry& e) { return e.utime == capture_utime && e.stamp == stamp; })) {
      return false;
    }
    history_.push_back({capture_utime, stamp, std::move(state)});
    if (history_.size() > capacity_) history_.pop_front();
    return true;
  }

  struct Match {
    MatchKind kind = MatchKind::kNone;
    const State* state = nullptr;
    int64_t capture_utime = 0;
  };

  Match match(int64_t frame_utime, MatchPolicy policy) const {
    Match best;
    if (history_.empty()) return best;
    if (policy == MatchPolicy::kLatest) return {MatchKind::kLatest, &history_.back().state, history_.back().utime};
    for (auto it = history_.rbegin(); it != history_.rend(); ++it) {
      if (it->utime == frame_utime) return {MatchKind::kExact, &it->state, it->utime};
      if (policy == MatchPolicy::kNearestEarlier && it->utime < frame_utime &&
          (best.kind == MatchKind::kNone || it->utime > best.capture_utime)) {
        best = {MatchKind::kNearestEarlier, &it->state, it->utime};
      }
    }
    return best;
  }

  // Whether the producer has gone past this frame: a state computed from it or from a
  // later frame has arrived. Until then, the frame's own state may still come; after, it
  // never will (two frames within one simulator step share the later one's state).
  bool has_reached(int64_t frame_utime) const {
    return std::any_of(history_.begin(), history_.end(), [&](const Entry& e) { return e.utime >= frame_utime; });
  }

  bool empty() const { return history_.empty(); }

 private:
  struct Entry {
    int64_t utime;
    int64_t stamp;
    State state;
  };
  std::size_t capacity_;
  std::deque<Entry> history_;
};

}  // namespace arphys::rendering

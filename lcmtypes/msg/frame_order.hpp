#pragma once
#include <cstdint>
#include <map>
#include <string>

namespace arphys::msg {

// Whether a frame (tracking or camera) from a source is new: its capture time is later than
// that of the newest frame accepted from the same source. The same sequence number and
// capture time again is a duplicate (a replayed or re-sent message); any other frame not
// newer is out of order (older, or a second frame of the same instant). Sources are told
// apart by id (a camera's, a tracker's), at most kMaxSources of them: beyond that the rest
// share one entry, so ids taken from messages cannot grow the table without bound.
class FrameOrder {
 public:
  enum class Verdict { kNew, kDuplicate, kOutOfOrder };
  static constexpr int kMaxSources = 64;

  // Records the frame when it is new.
  Verdict check(const std::string& source, int64_t seq, int64_t capture_utime);

 private:
  struct Newest {
    int64_t seq = 0;
    int64_t capture_utime = 0;
  };
  std::map<std::string, Newest> newest_;
};

// "duplicate" or "out-of-order" (empty for kNew), for counted refusal reasons.
const char* to_string(FrameOrder::Verdict verdict);

}  // namespace arphys::msg

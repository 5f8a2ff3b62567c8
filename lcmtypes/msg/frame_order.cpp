#include "lcmtypes/msg/frame_order.hpp"

#include <tuple>

namespace arphys::msg {

FrameOrder::Verdict FrameOrder::check(const std::string& source, int64_t seq, int64_t capture_utime) {
  auto it = newest_.find(source);
  if (it == newest_.end()) {
    // Past the bound, unknown sources share the entry of the empty id.
    const bool room = static_cast<int>(newest_.size()) < kMaxSources;
    bool inserted = false;
    std::tie(it, inserted) = newest_.try_emplace(room ? source : std::string(), Newest{seq, capture_utime});
    if (inserted) return Verdict::kNew;
  }
  Newest& n = it->second;
  if (seq == n.seq && capture_utime == n.capture_utime) return Verdict::kDuplicate;
  if (capture_utime <= n.capture_utime) return Verdict::kOutOfOrder;
  n = {seq, capture_utime};
  return Verdict::kNew;
}

const char* to_string(FrameOrder::Verdict verdict) {
  switch (verdict) {
    case FrameOrder::Verdict::kDuplicate: return "duplicate";
    case FrameOrder::Verdict::kOutOfOrder: return "out-of-order";
    default: return "";
  }
}

}  // namespace arphys::msg

#include "lcmtypes/msg/frame_order.hpp"

namespace arphys::msg {

FrameOrder::Verdict FrameOrder::check(const std::string& source, int64_t seq, int64_t capture_utime) {
  auto it = newest_.find(source);
  if (it == newest_.end() && static_cast<int>(newest_.size()) >= kMaxSources) it = newest_.find(std::string());
  if (it == newest_.end()) {
    const bool full = static_cast<int>(newest_.size()) >= kMaxSources;
    newest_.emplace(full ? std::string() : source, Newest{seq, capture_utime});
    return Verdict::kNew;
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

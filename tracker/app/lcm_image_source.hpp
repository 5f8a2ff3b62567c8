#pragma once
#include <optional>
#include <string>

#include "arphys/image_t.hpp"
#include "lcmtypes/msg/bus.hpp"
#include "lcmtypes/msg/frame_order.hpp"
#include "tracker/sources/frame_source.hpp"

namespace arphys::tracking {

// Frames from an LCM image channel (the synthetic camera, a remote camera, or a log
// played back by lcm-logplayer). Keeps only the newest frame: a tracker that falls
// behind drops old frames (counted) rather than adding latency. Raw GRAY8/BGR8/RGB8
// and JPEG are accepted; an image whose bytes do not match its header or whose JPEG
// does not decode is counted and skipped, and so is a frame not newer than the newest
// from its camera (a duplicate or replayed message, msg::FrameOrder).
class LcmImageSource final : public FrameSource {
 public:
  LcmImageSource(msg::Bus& bus, const std::string& channel);

  std::optional<Frame> next(int timeout_ms) override;
  bool finished() const override { return false; }
  std::string describe() const override { return "lcm:" + channel_; }
  int64_t skipped_frames() const override { return undecodable_; }
  int64_t dropped_frames() const { return dropped_; }
  int64_t out_of_order_frames() const { return out_of_order_; }

 private:
  void on_image(const arphys::image_t& image);

  msg::Bus& bus_;
  std::string channel_;
  std::optional<Frame> pending_;
  int64_t undecodable_ = 0;
  int64_t dropped_ = 0;
  int64_t out_of_order_ = 0;
  msg::FrameOrder order_;
};

}  // namespace arphys::tracking

#include "tracker/app/lcm_image_source.hpp"

#include "lcmtypes/msg/image_message.hpp"

namespace arphys::tracking {

LcmImageSource::LcmImageSource(msg::Bus& bus, const std::string& channel) : bus_(bus), channel_(channel) {
  bus_.subscribe<arphys::image_t>(channel, [this](const arphys::image_t& image, const lcm::ReceiveBuffer&,
                                                  const std::string&) { on_image(image); });
}

void LcmImageSource::on_image(const arphys::image_t& image) {
  // A frame already seen (re-sent, replayed) or older than one is not tracked again.
  if (order_.check(image.camera_id, image.seq, image.utime) != msg::FrameOrder::Verdict::kNew) {
    ++out_of_order_;
    return;
  }
  Frame frame;
  frame.capture_utime = image.utime;
  frame.seq = image.seq;
  try {
    frame.image = msg::decode_image_message(image);
  } catch (const std::invalid_argument&) {
    ++undecodable_;
    return;
  }
  if (pending_) ++dropped_;
  pending_ = std::move(frame);
}

std::optional<Frame> LcmImageSource::next(int timeout_ms) {
  if (!pending_) bus_.handle_timeout_ms(timeout_ms);
  bus_.handle_pending();
  std::optional<Frame> out = std::move(pending_);
  pending_.reset();
  return out;
}

}  // namespace arphys::tracking

#include "tracker/app/lcm_image_source.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace arphys::tracking {

LcmImageSource::LcmImageSource(msg::Bus& bus, const std::string& channel) : bus_(bus), channel_(channel) {
  bus_.subscribe<arphys::image_t>(channel, [this](const arphys::image_t& image, const lcm::ReceiveBuffer&,
                                                  const std::string&) { on_image(image); });
}

void LcmImageSource::on_image(const arphys::image_t& image) {
  Frame frame;
  frame.capture_utime = image.utime;
  frame.seq = image.seq;
  const auto bad = [this] { ++undecodable_; };
  if (image.pixel_format == arphys::image_t::PIXEL_FORMAT_JPEG) {
    frame.image = cv::imdecode(image.data, cv::IMREAD_UNCHANGED);
    if (frame.image.empty()) return bad();
  } else {
    int type = 0, channels = 0;
    switch (image.pixel_format) {
      case arphys::image_t::PIXEL_FORMAT_GRAY8: type = CV_8UC1; channels = 1; break;
      case arphys::image_t::PIXEL_FORMAT_RGB8:
      case arphys::image_t::PIXEL_FORMAT_BGR8: type = CV_8UC3; channels = 3; break;
      default: return bad();
    }
    if (image.width <= 0 || image.height <= 0 || image.row_stride < image.width * channels ||
        static_cast<int64_t>(image.row_stride) * image.height > static_cast<int64_t>(image.data.size())) {
      return bad();
    }
    cv::Mat view(image.height, image.width, type, const_cast<uint8_t*>(image.data.data()), image.row_stride);
    if (image.pixel_format == arphys::image_t::PIXEL_FORMAT_RGB8) {
      cv::cvtColor(view, frame.image, cv::COLOR_RGB2BGR);
    } else {
      frame.image = view.clone();
    }
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

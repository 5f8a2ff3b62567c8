#include "lcmtypes/msg/image_message.hpp"

#include <stdexcept>
#include <string>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace arphys::msg {

cv::Mat decode_image_message(const arphys::image_t& m) {
  if (m.pixel_format == arphys::image_t::PIXEL_FORMAT_JPEG) {
    if (m.data.empty()) throw std::invalid_argument("empty JPEG");
    cv::Mat image = cv::imdecode(m.data, cv::IMREAD_UNCHANGED);
    if (image.empty() || image.depth() != CV_8U) throw std::invalid_argument("JPEG does not decode");
    return image;
  }
  int channels = 0;
  switch (m.pixel_format) {
    case arphys::image_t::PIXEL_FORMAT_GRAY8: channels = 1; break;
    case arphys::image_t::PIXEL_FORMAT_RGB8:
    case arphys::image_t::PIXEL_FORMAT_BGR8: channels = 3; break;
    default: throw std::invalid_argument("unknown pixel format " + std::to_string(m.pixel_format));
  }
  const int64_t width = m.width, height = m.height, stride = m.row_stride;
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384 || stride < width * channels ||
      stride * height > static_cast<int64_t>(m.data.size())) {
    throw std::invalid_argument("image header (" + std::to_string(m.width) + "x" + std::to_string(m.height) + ", stride " +
                                std::to_string(m.row_stride) + ") does not match its " + std::to_string(m.data.size()) +
                                " bytes");
  }
  const cv::Mat view(m.height, m.width, channels == 1 ? CV_8UC1 : CV_8UC3, const_cast<uint8_t*>(m.data.data()),
                     static_cast<size_t>(m.row_stride));
  cv::Mat out;
  if (m.pixel_format == arphys::image_t::PIXEL_FORMAT_RGB8) {
    cv::cvtColor(view, out, cv::COLOR_RGB2BGR);
  } else {
    out = view.clone();
  }
  return out;
}

}  // namespace arphys::msg

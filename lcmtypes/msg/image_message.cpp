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

arphys::image_t encode_image_message(const cv::Mat& image, int64_t capture_utime, int64_t seq,
                                     const std::string& camera_id, int jpeg_quality) {
  if (image.empty() || image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3)) {
    throw std::invalid_argument("encode_image_message: expected a non-empty 8-bit grey or BGR image");
  }
  if (jpeg_quality < 0 || jpeg_quality > 100) {
    throw std::invalid_argument("encode_image_message: jpeg_quality = " + std::to_string(jpeg_quality) +
                                ": expected 0 (raw) .. 100");
  }
  arphys::image_t m{};
  m.utime = capture_utime;
  m.seq = seq;
  m.camera_id = camera_id;
  m.width = image.cols;
  m.height = image.rows;
  if (jpeg_quality > 0) {
    m.pixel_format = arphys::image_t::PIXEL_FORMAT_JPEG;
    cv::imencode(".jpg", image, m.data, {cv::IMWRITE_JPEG_QUALITY, jpeg_quality});
  } else {
    m.pixel_format = image.channels() == 1 ? arphys::image_t::PIXEL_FORMAT_GRAY8 : arphys::image_t::PIXEL_FORMAT_BGR8;
    m.row_stride = static_cast<int32_t>(image.cols * image.elemSize());
    const cv::Mat packed = image.isContinuous() ? image : image.clone();
    m.data.assign(packed.data, packed.data + packed.total() * packed.elemSize());
  }
  m.size = static_cast<int32_t>(m.data.size());
  return m;
}

}  // namespace arphys::msg

#pragma once
// Camera frames as the synthetic camera sends them, for the process tests. JPEG: a raw
// 640x480 frame (300 KB) can exceed a receiver's socket buffer and LCM drops it whole.
#include <opencv2/imgcodecs.hpp>

#include "arphys/image_t.hpp"

namespace arphys::testing {

inline arphys::image_t jpeg_image(const cv::Mat& image, int64_t utime, int64_t seq) {
  arphys::image_t m{};
  m.utime = utime;
  m.seq = seq;
  m.camera_id = "synthetic";
  m.width = image.cols;
  m.height = image.rows;
  m.pixel_format = arphys::image_t::PIXEL_FORMAT_JPEG;
  cv::imencode(".jpg", image, m.data, {cv::IMWRITE_JPEG_QUALITY, 95});
  m.size = static_cast<int32_t>(m.data.size());
  return m;
}

}  // namespace arphys::testing

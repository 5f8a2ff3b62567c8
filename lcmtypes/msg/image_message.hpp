#pragma once
#include <cstdint>
#include <string>

#include <opencv2/core.hpp>

#include "arphys/image_t.hpp"

namespace arphys::msg {

// The pixels of an image_t: GRAY8 as one channel, BGR8 as is, RGB8 converted to BGR,
// JPEG decoded as stored (grey or BGR). Throws std::invalid_argument saying why when the
// format is unknown, the header does not match the bytes (sizes checked without overflow)
// or the JPEG does not decode. The result owns its pixels.
cv::Mat decode_image_message(const arphys::image_t& message);

// An image_t of 8-bit pixels (grey or BGR): JPEG at jpeg_quality (1..100), or raw
// (GRAY8 / BGR8, rows packed) when jpeg_quality is 0. Throws std::invalid_argument naming
// the value for an empty or non-8-bit image or a quality outside 0..100.
arphys::image_t encode_image_message(const cv::Mat& image, int64_t capture_utime, int64_t seq,
                                     const std::string& camera_id, int jpeg_quality = 90);

}  // namespace arphys::msg

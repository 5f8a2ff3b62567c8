#pragma once
#include <opencv2/core.hpp>

#include "arphys/image_t.hpp"

namespace arphys::msg {

// The pixels of an image_t: GRAY8 as one channel, BGR8 as is, RGB8 converted to BGR,
// JPEG decoded as stored (grey or BGR). Throws std::invalid_argument saying why when the
// format is unknown, the header does not match the bytes (sizes checked without overflow)
// or the JPEG does not decode. The result owns its pixels.
cv::Mat decode_image_message(const arphys::image_t& message);

}  // namespace arphys::msg

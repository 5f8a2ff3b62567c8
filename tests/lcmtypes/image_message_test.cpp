// Images to messages and back: raw grey and BGR exactly, JPEG within its loss, and what
// cannot be encoded or decoded refused with the reason.
#include <gtest/gtest.h>

#include <stdexcept>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "lcmtypes/msg/image_message.hpp"

namespace arphys::msg {
namespace {

cv::Mat test_pattern(int type) {
  cv::Mat image(48, 64, type);
  cv::randu(image, 0, 256);
  cv::GaussianBlur(image, image, cv::Size(9, 9), 3);  // smooth: JPEG keeps it closely
  return image;
}

double max_difference(const cv::Mat& a, const cv::Mat& b) {
  double worst = 0;
  cv::minMaxLoc(cv::abs(a - b), nullptr, &worst);
  return worst;
}

TEST(ImageMessage, RawFramesComeBackExactlyAndJpegWithinItsLoss) {
  for (const int type : {CV_8UC1, CV_8UC3}) {
    const cv::Mat image = test_pattern(type);
    const arphys::image_t raw = encode_image_message(image(cv::Rect(2, 3, 40, 30)), 123, 7, "cam", 0);
    EXPECT_EQ(raw.utime, 123);
    EXPECT_EQ(raw.seq, 7);
    EXPECT_EQ(raw.camera_id, "cam");
    EXPECT_EQ(raw.pixel_format, type == CV_8UC1 ? arphys::image_t::PIXEL_FORMAT_GRAY8 : arphys::image_t::PIXEL_FORMAT_BGR8);
    EXPECT_EQ(raw.size, 40 * 30 * image.channels());
    EXPECT_EQ(max_difference(decode_image_message(raw), image(cv::Rect(2, 3, 40, 30))), 0);
    const arphys::image_t jpeg = encode_image_message(image, 1, 1, "cam", 95);
    EXPECT_EQ(jpeg.pixel_format, arphys::image_t::PIXEL_FORMAT_JPEG);
    EXPECT_LT(jpeg.size, static_cast<int32_t>(image.total() * image.elemSize()));
    EXPECT_LT(max_difference(decode_image_message(jpeg), image), 12);
  }
}

TEST(ImageMessage, WhatCannotBeEncodedIsRefusedByName) {
  EXPECT_THROW(encode_image_message(cv::Mat(), 0, 0, "cam"), std::invalid_argument);
  EXPECT_THROW(encode_image_message(cv::Mat(4, 4, CV_32FC1), 0, 0, "cam"), std::invalid_argument);
  try {
    encode_image_message(cv::Mat(4, 4, CV_8UC1), 0, 0, "cam", 101);
    FAIL() << "quality 101 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("jpeg_quality = 101"), std::string::npos) << e.what();
  }
  arphys::image_t broken = encode_image_message(cv::Mat(4, 4, CV_8UC1, cv::Scalar(9)), 0, 0, "cam", 0);
  broken.data.resize(3);
  broken.size = 3;
  EXPECT_THROW(decode_image_message(broken), std::invalid_argument);
}

}  // namespace
}  // namespace arphys::msg

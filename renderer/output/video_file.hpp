#pragma once
#include <string>

#include <opencv2/videoio.hpp>

namespace arphys::rendering {

// Opens a video file for writing, the codec chosen by the extension: `.mp4` mp4v
// (2.7-4.5 ms per 640x480 frame measured here), anything else MJPG (`.avi`, 5-7 ms).
// Throws std::runtime_error naming the path when OpenCV cannot write it.
cv::VideoWriter open_video_file(const std::string& path, double fps, cv::Size size, bool colour);

}  // namespace arphys::rendering

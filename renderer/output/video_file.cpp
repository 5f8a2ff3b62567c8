#include "renderer/output/video_file.hpp"

#include <stdexcept>

namespace arphys::rendering {

cv::VideoWriter open_video_file(const std::string& path, double fps, cv::Size size, bool colour) {
  const bool mp4 = path.size() > 4 && path.substr(path.size() - 4) == ".mp4";
  const int fourcc = mp4 ? cv::VideoWriter::fourcc('m', 'p', '4', 'v') : cv::VideoWriter::fourcc('M', 'J', 'P', 'G');
  cv::VideoWriter writer(path, fourcc, fps, size, colour);
  if (!writer.isOpened()) throw std::runtime_error("cannot write video file " + path);
  return writer;
}

}  // namespace arphys::rendering

#include <filesystem>
#include <regex>

#include "tracker/sources/frame_source.hpp"
#include "tracker/sources/image_folder_source.hpp"
#include "tracker/sources/video_capture_source.hpp"

namespace arphys::tracking {

std::unique_ptr<FrameSource> open_frame_source(const std::string& spec, double fps_hint, int width, int height,
                                               double camera_fps) {
  std::smatch match;
  static const std::regex kDevice(R"(^(?:/dev/video|cam:)(\d+)$)");
  if (std::regex_match(spec, match, kDevice)) {
    return std::make_unique<VideoCaptureSource>(std::stoi(match[1]), width, height, camera_fps);
  }
  if (spec.rfind("lcm:", 0) == 0) {
    throw SourceError("source " + spec + ": LCM image channels are opened by the tracker executable");
  }
  std::error_code error;
  if (std::filesystem::is_directory(spec, error)) return std::make_unique<ImageFolderSource>(spec, fps_hint);
  if (!std::filesystem::exists(spec, error)) {
    throw SourceError("source " + spec + " does not exist (expected a video file, an image folder, /dev/videoN or lcm:CHANNEL)");
  }
  return std::make_unique<VideoCaptureSource>(spec);
}

}  // namespace arphys::tracking

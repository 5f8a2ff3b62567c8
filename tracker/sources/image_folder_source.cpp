#include "tracker/sources/image_folder_source.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <opencv2/imgcodecs.hpp>

#include "tracker/sources/wall_clock.hpp"

namespace arphys::tracking {

ImageFolderSource::ImageFolderSource(const std::string& folder, double fps) : folder_(folder), fps_(fps) {
  namespace fs = std::filesystem;
  if (!(fps > 0)) throw SourceError("image folder " + folder + ": frame rate " + std::to_string(fps) + " is not positive");
  std::error_code error;
  if (!fs::is_directory(folder, error)) throw SourceError("image folder " + folder + " does not exist");
  static const std::vector<std::string> kExtensions = {".png", ".jpg", ".jpeg", ".bmp", ".pgm", ".ppm", ".tif", ".tiff"};
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (!entry.is_regular_file()) continue;
    std::string ext = entry.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    if (std::find(kExtensions.begin(), kExtensions.end(), ext) != kExtensions.end()) {
      files_.push_back(entry.path().string());
    }
  }
  std::sort(files_.begin(), files_.end());
  if (files_.empty()) throw SourceError("image folder " + folder + " holds no png/jpg/bmp/pgm/ppm/tif images");
  open_utime_ = wall_clock_utime();
}

std::optional<Frame> ImageFolderSource::next(int /*timeout_ms*/) {
  while (index_ < files_.size()) {
    const size_t i = index_++;
    Frame frame;
    frame.image = cv::imread(files_[i], cv::IMREAD_UNCHANGED);
    if (frame.image.empty()) {
      ++skipped_;
      continue;
    }
    frame.seq = static_cast<int64_t>(i);
    frame.capture_utime = open_utime_ + static_cast<int64_t>(std::llround(static_cast<double>(i) * 1e6 / fps_));
    frame.name = std::filesystem::path(files_[i]).filename().string();
    return frame;
  }
  return std::nullopt;
}

}  // namespace arphys::tracking

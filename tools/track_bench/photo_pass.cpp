#include "tools/track_bench/photo_pass.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <stdexcept>

#include "configs/loader/camera_config.hpp"
#include "tools/track_bench/visp_detector.hpp"
#include "tracker/detection/edge_refinement.hpp"
#include "tracker/pose/marker_pose.hpp"

namespace arphys::bench {
namespace {

struct Reference {
  int id = -1;
  std::array<Eigen::Vector2d, 4> corners_px;
};

// NAME.txt: one detection per line, "id, (x y), (x y), (x y), (x y)", in libapriltag's pixel
// convention (a pixel's centre at +0.5), returned in OpenCV's (-0.5 px).
std::vector<Reference> read_references(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::vector<Reference> refs;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    for (char& c : line)
      if (c == ',' || c == '(' || c == ')') c = ' ';
    std::istringstream fields(line);
    Reference r;
    fields >> r.id;
    for (auto& corner : r.corners_px) fields >> corner.x() >> corner.y();
    if (!fields) throw std::runtime_error(path + ": cannot parse '" + line + "'");
    for (auto& corner : r.corners_px) corner -= Eigen::Vector2d(0.5, 0.5);
    refs.push_back(r);
  }
  return refs;
}

double max_corner_distance_px(const tracking::DetectedMarker& m, const Reference& r) {
  double worst = 0;
  for (int k = 0; k < 4; ++k) worst = std::max(worst, (m.corners_px[k] - r.corners_px[k]).norm());
  return worst;
}

}  // namespace

std::vector<PhotoFigures> photo_pass(const std::vector<PhotoConfig>& configs, const std::string& folder,
                                     const std::string& camera_yaml, int repeats) {
  const tracking::CameraModel camera = tracking::CameraModel::from_config(config::load_camera(camera_yaml));
  std::vector<std::pair<cv::Mat, std::vector<Reference>>> photos;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (entry.path().extension() != ".jpg") continue;
    std::filesystem::path txt = entry.path();
    txt.replace_extension(".txt");
    photos.emplace_back(cv::imread(entry.path().string(), cv::IMREAD_GRAYSCALE), read_references(txt.string()));
    if (photos.back().first.empty()) throw std::runtime_error("cannot decode " + entry.path().string());
  }
  std::sort(photos.begin(), photos.end(),
            [](const auto& a, const auto& b) { return a.second.size() < b.second.size(); });
  std::vector<PhotoFigures> out;
  for (const PhotoConfig& config : configs) {
    PhotoFigures f;
    f.config = config.name;
    auto detector = make_bench_detector(config.spec);
    std::vector<double> ms, offsets, reprojection;
    for (const auto& [image, refs] : photos) {
      std::vector<tracking::DetectedMarker> found;
      for (int pass = 0; pass < repeats; ++pass) {
        const auto t0 = std::chrono::steady_clock::now();
        found = detector->detect(image);
        if (config.refine)
          for (auto& m : found) tracking::refine_corners_on_edges(image, m);
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      }
      // Each reference is matched to the detection of its id nearest it (the photos carry
      // several tags of one id).
      std::vector<char> used(found.size(), 0);
      for (const Reference& r : refs) {
        ++f.references;
        int best = -1;
        double best_px = std::numeric_limits<double>::infinity();
        for (std::size_t k = 0; k < found.size(); ++k) {
          if (found[k].id != r.id || used[k]) continue;
          const double px = max_corner_distance_px(found[k], r);
          if (px < best_px) best_px = px, best = static_cast<int>(k);
        }
        if (best < 0 || best_px >= 1.0) continue;
        used[best] = 1;
        ++f.found;
        for (int c = 0; c < 4; ++c) offsets.push_back((found[best].corners_px[c] - r.corners_px[c]).norm());
        const tracking::MarkerPoseSolutions s = tracking::solve_marker_pose(found[best], 0.05, camera);
        if (s.count > 0) reprojection.push_back(s.rms_px[0]);
      }
      f.extra += static_cast<int>(std::count(used.begin(), used.end(), 0));
    }
    f.corner_offset_median_px = percentile(offsets, 0.5);
    f.corner_offset_p90_px = percentile(offsets, 0.9);
    f.reprojection_median_px = percentile(reprojection, 0.5);
    f.reprojection_p90_px = percentile(reprojection, 0.9);
    f.median_ms = percentile(ms, 0.5);
    out.push_back(f);
  }
  return out;
}

}  // namespace arphys::bench

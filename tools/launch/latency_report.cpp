#include "tools/launch/latency_report.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>

namespace arphys::tools {

void LatencyReport::on_image(const arphys::image_t&) { ++images_; }

void LatencyReport::on_detections(const arphys::marker_detections_t& m) {
  capture_to_detection_.samples_ms.push_back(1e-3 * static_cast<double>(m.detect_end_utime - m.utime));
}

void LatencyReport::on_poses(const arphys::object_poses_t& m) {
  ++poses_;
  detection_to_pose_.samples_ms.push_back(1e-3 * static_cast<double>(m.publish_utime - m.detect_end_utime));
  poses_publish_[m.utime] = m.publish_utime;
}

void LatencyReport::on_world_state(const arphys::world_state_t& m) {
  if (m.utime == 0 || world_publish_.count(m.utime)) return;  // the first state computed from a frame
  world_publish_[m.utime] = m.publish_utime;
  const auto p = poses_publish_.find(m.utime);
  if (p != poses_publish_.end()) pose_to_world_.samples_ms.push_back(1e-3 * static_cast<double>(m.publish_utime - p->second));
}

void LatencyReport::on_render_status(const arphys::render_status_t& m) {
  ++renders_;
  end_to_end_.samples_ms.push_back(1e-3 * static_cast<double>(m.render_end_utime - m.utime));
  if (m.world_state_match != arphys::render_status_t::MATCH_EXACT) return;
  ++renders_exact_;
  const auto w = world_publish_.find(m.utime);
  if (w != world_publish_.end()) world_to_overlay_.samples_ms.push_back(1e-3 * static_cast<double>(m.render_end_utime - w->second));
}

nlohmann::json LatencyReport::to_json() const {
  nlohmann::json report;
  for (const Stage* s : stages()) {
    nlohmann::json j;
    j["count"] = s->samples_ms.size();
    if (!s->samples_ms.empty()) {
      std::vector<double> v = s->samples_ms;
      std::sort(v.begin(), v.end());
      auto q = [&](double p) { return v[std::min(v.size() - 1, static_cast<size_t>(p * (v.size() - 1) + 0.5))]; };
      j["p50_ms"] = q(0.5);
      j["p95_ms"] = q(0.95);
      j["p99_ms"] = q(0.99);
      j["max_ms"] = v.back();
    }
    report["stages"][s->name] = j;
  }
  report["frames"] = {{"captured", images_},
                      {"tracked", poses_},
                      {"rendered", renders_},
                      {"rendered_with_own_world_state", renders_exact_},
                      {"dropped_before_overlay", std::max<int64_t>(0, images_ - renders_)}};
  return report;
}

void LatencyReport::print() const {
  const nlohmann::json report = to_json();
  std::printf("%-26s %7s %8s %8s %8s %8s\n", "stage", "count", "p50_ms", "p95_ms", "p99_ms", "max_ms");
  for (const Stage* s : stages()) {
    const auto& j = report["stages"][s->name];
    if (j["count"] == 0) {
      std::printf("%-26s %7d\n", s->name.c_str(), 0);
      continue;
    }
    std::printf("%-26s %7d %8.2f %8.2f %8.2f %8.2f\n", s->name.c_str(), j["count"].get<int>(), j["p50_ms"].get<double>(),
                j["p95_ms"].get<double>(), j["p99_ms"].get<double>(), j["max_ms"].get<double>());
  }
  std::printf("frames: %lld captured, %lld tracked, %lld rendered (%lld with their own world state)\n",
              static_cast<long long>(images_), static_cast<long long>(poses_), static_cast<long long>(renders_),
              static_cast<long long>(renders_exact_));
}

void LatencyReport::write_samples_csv(const std::string& path) const {
  std::ofstream out(path);
  out << "stage,ms\n";
  for (const Stage* s : stages()) {
    for (double ms : s->samples_ms) out << s->name << "," << ms << "\n";
  }
}

}  // namespace arphys::tools

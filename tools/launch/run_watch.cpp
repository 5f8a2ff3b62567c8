#include "tools/launch/run_watch.hpp"

#include <cstdio>
#include <sstream>

#include "arphys/ground_truth_t.hpp"
#include "arphys/image_t.hpp"
#include "arphys/marker_detections_t.hpp"
#include "arphys/object_poses_t.hpp"
#include "arphys/render_status_t.hpp"
#include "arphys/world_state_t.hpp"
#include "configs/loader/camera_config.hpp"
#include "lcmtypes/msg/heartbeat.hpp"
#include "simulator/geometry/triangle_mesh.hpp"

namespace arphys::launch {

void MemoryWatch::on_heartbeat(const arphys::process_status_t& status) {
  const std::optional<double> rss = msg::figure(status, "rss_mb");
  if (!rss || *rss < 0) return;
  Process& p = processes_[status.name];
  if (p.pid != status.pid) p = Process{status.pid};
  if (p.baseline_mb < 0 && status.uptime_s >= kWarmUpS) {
    p.baseline_mb = *rss;
    p.baseline_uptime_s = status.uptime_s;
  }
  p.last_mb = *rss;
  p.last_uptime_s = status.uptime_s;
  p.max_mb = std::max(p.max_mb, *rss);
}

nlohmann::json MemoryWatch::to_json() const {
  nlohmann::json out = nlohmann::json::object();
  for (const auto& [name, p] : processes_) {
    nlohmann::json entry{{"pid", p.pid}, {"rss_mb_end", p.last_mb}, {"rss_mb_max", p.max_mb}};
    if (p.baseline_mb >= 0) {
      entry["rss_mb_after_warm_up"] = p.baseline_mb;
      entry["growth_mb"] = p.last_mb - p.baseline_mb;
      entry["over_s"] = p.last_uptime_s - p.baseline_uptime_s;
    }
    out[name] = entry;
  }
  return out;
}

void MemoryWatch::print() const {
  for (const auto& [name, p] : processes_) {
    if (p.baseline_mb < 0) continue;
    std::fprintf(stderr, "memory %-10s %.1f MB after warm-up, %+.2f MB over %.0f s\n", name.c_str(), p.baseline_mb,
                 p.last_mb - p.baseline_mb, p.last_uptime_s - p.baseline_uptime_s);
  }
}

namespace {

// The tracked real object whose overlay registration is measured (the first kinematic
// real object) and the corners of its bounding box, object frame.
std::unique_ptr<tools::RegistrationReport> registration_for(const config::SceneConfig& scene) {
  if (scene.camera_file.empty()) return nullptr;
  for (const auto& o : scene.objects) {
    if (o.role != config::Role::kReal || o.motion != config::Motion::kKinematic) continue;
    Eigen::AlignedBox3d box;
    switch (o.collision.type) {
      case config::ShapeType::kBox: box = Eigen::AlignedBox3d(-0.5 * o.collision.size_m, 0.5 * o.collision.size_m); break;
      case config::ShapeType::kSphere:
        box = Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-o.collision.radius_m), Eigen::Vector3d::Constant(o.collision.radius_m));
        break;
      case config::ShapeType::kMesh: box = geometry::load_mesh(o.collision.mesh_path, o.collision.scale).bounds(); break;
      case config::ShapeType::kConvexSet: box = geometry::load_mesh(o.collision.pieces_path, o.collision.scale).bounds(); break;
      case config::ShapeType::kPlane: continue;
    }
    std::vector<Eigen::Vector3d> corners;
    for (int i = 0; i < 8; ++i) corners.push_back(box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(i)));
    return std::make_unique<tools::RegistrationReport>(config::load_camera(scene.camera_file), o.id, corners);
  }
  return nullptr;
}

}  // namespace

RunWatch::RunWatch(msg::Bus& bus, const config::SceneConfig& scene, bool synthetic) {
  try {
    if (synthetic) registration_ = registration_for(scene);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "arphys-launch: no registration error measured: %s\n", e.what());
  }
  const auto& ch = scene.channels;
  using lcm::ReceiveBuffer;
  if (registration_) {
    bus.subscribe<arphys::ground_truth_t>(ch.ground_truth, [this](const arphys::ground_truth_t& m, const ReceiveBuffer&,
                                                                  const std::string&) { registration_->on_ground_truth(m); });
  }
  bus.subscribe<arphys::image_t>(ch.camera_image, [this](const arphys::image_t& m, const ReceiveBuffer&,
                                                         const std::string&) { latency_.on_image(m); });
  bus.subscribe<arphys::marker_detections_t>(ch.marker_detections, [this](const arphys::marker_detections_t& m,
                                                                          const ReceiveBuffer&, const std::string&) {
    latency_.on_detections(m);
  });
  bus.subscribe<arphys::object_poses_t>(ch.object_poses, [this](const arphys::object_poses_t& m, const ReceiveBuffer&,
                                                                const std::string&) { latency_.on_poses(m); });
  bus.subscribe<arphys::world_state_t>(ch.world_state, [this](const arphys::world_state_t& m, const ReceiveBuffer&,
                                                              const std::string&) {
    latency_.on_world_state(m);
    if (registration_) registration_->on_world_state(m);
  });
  bus.subscribe<arphys::render_status_t>(ch.render_status, [this](const arphys::render_status_t& m, const ReceiveBuffer&,
                                                                  const std::string&) {
    latency_.on_render_status(m);
    if (registration_) registration_->on_render_status(m);
  });
  bus.subscribe<arphys::process_status_t>(ch.process_status, [this](const arphys::process_status_t& m,
                                                                    const ReceiveBuffer&, const std::string&) {
    heartbeats_[m.name] = m;
    memory_.on_heartbeat(m);
  });
}

std::string RunWatch::status_line(double elapsed_s) const {
  std::ostringstream line;
  line.setf(std::ios::fixed);
  line.precision(1);
  line << "t " << elapsed_s << " s";
  for (const auto& [name, s] : heartbeats_) {
    line << " | " << name << " " << s.rate_hz << " Hz " << s.stage_duration_ms << " ms";
    if (name == "simulator" && s.dropped) {
      line << " gave up " << s.dropped << " steps";  // steps of simulation given up (--max-lag-s)
    } else if (s.dropped) {
      line << " drop " << s.dropped;
    }
    if (s.rejected) line << " rej " << s.rejected;
  }
  return line.str();
}

std::optional<double> RunWatch::simulator_dropped_time_s() const {
  const auto it = heartbeats_.find("simulator");
  if (it == heartbeats_.end()) return std::nullopt;
  return msg::figure(it->second, "dropped_time_s");
}

nlohmann::json RunWatch::report(const LaunchOptions& o, const config::SceneConfig& scene,
                                const std::map<std::string, int>& restarts, const std::string& drain_ended_by,
                                double drain_s) const {
  nlohmann::json report = latency_.to_json();
  report["scene"] = scene.name;
  report["tracker"] = o.tracker_impl;
  report["duration_s"] = o.duration_s;
  report["restarts"] = restarts;
  report["receive_loss"] = o.receive_loss;
  report["tracking_policy"] = o.tracking_policy.empty() ? scene.tracking_policy : o.tracking_policy;
  report["drain"] = {{"ended_by", drain_ended_by.empty() ? nlohmann::json() : nlohmann::json(drain_ended_by)},
                     {"seconds", drain_s}};
  report["memory"] = memory_.to_json();
  // The simulation time the simulator gave up to keep within --sim-max-lag-s of the camera.
  report["simulator"] = {{"max_lag_s", o.sim_max_lag_s}, {"dropped_time_s", nullptr}};
  if (const auto dropped_s = simulator_dropped_time_s()) report["simulator"]["dropped_time_s"] = *dropped_s;
  if (registration_) report["registration"] = registration_->to_json();
  return report;
}

void RunWatch::print(const nlohmann::json& report) const {
  if (report.contains("registration") && report["registration"]["count"].get<int>() > 0) {
    const auto& r = report["registration"];
    std::printf("overlay registration of '%s': p50 %.2f px, p95 %.2f px, max %.2f px over %d frames\n",
                r["object"].get<std::string>().c_str(), r["p50_px"].get<double>(), r["p95_px"].get<double>(),
                r["max_px"].get<double>(), r["count"].get<int>());
  }
  latency_.print();
  const auto& sim = report["simulator"];
  if (sim["dropped_time_s"].is_number() && sim["dropped_time_s"].get<double>() > 0) {
    std::printf("simulator: gave up %.2f s of simulation to stay within %.3g s of the camera (--sim-max-lag-s)\n",
                sim["dropped_time_s"].get<double>(), sim["max_lag_s"].get<double>());
  }
  memory_.print();
}

}  // namespace arphys::launch

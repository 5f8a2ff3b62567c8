// arphys-latency: the pipeline's per-stage latency from an lcm-logger file (the same
// figures arphys-launch measures live), from the stamps inside the messages, so a log
// gives the latency of the run that was recorded, not of its replay.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <fstream>

#include <lcm/lcm-cpp.hpp>

#include "configs/loader/scene_config.hpp"
#include "tools/launch/latency_report.hpp"

namespace {

template <class Message>
bool decode(const lcm::LogEvent& event, Message& message) {
  return message.decode(event.data, 0, event.datalen) >= 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"arphys-latency: per-stage latency (p50/p95/p99/max) of a recorded pipeline run, from its lcm-logger file."};
  std::string log_path, scene_path = arphys::config::default_config_dir() + "/scenes/bunny_box_table.yaml", out;
  app.add_option("log", log_path, "lcm-logger file")->required()->check(CLI::ExistingFile);
  app.add_option("--scene", scene_path, "scene YAML (its channel names)")->capture_default_str();
  app.add_option("--out", out, "write latency.json and latency_samples.csv here");
  CLI11_PARSE(app, argc, argv);

  arphys::config::SceneConfig scene;
  try {
    scene = arphys::config::load_scene(scene_path);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "arphys-latency: %s\n", e.what());
    return 2;
  }
  lcm::LogFile log(log_path, "r");
  if (!log.good()) {
    std::fprintf(stderr, "arphys-latency: cannot read %s as an LCM log\n", log_path.c_str());
    return 2;
  }
  arphys::tools::LatencyReport latency;
  long events = 0, undecodable = 0;
  const auto& c = scene.channels;
  while (const lcm::LogEvent* event = log.readNextEvent()) {
    ++events;
    bool ok = true;
    if (event->channel == c.camera_image) {
      arphys::image_t m;
      if ((ok = decode(*event, m))) latency.on_image(m);
    } else if (event->channel == c.marker_detections) {
      arphys::marker_detections_t m;
      if ((ok = decode(*event, m))) latency.on_detections(m);
    } else if (event->channel == c.object_poses) {
      arphys::object_poses_t m;
      if ((ok = decode(*event, m))) latency.on_poses(m);
    } else if (event->channel == c.world_state) {
      arphys::world_state_t m;
      if ((ok = decode(*event, m))) latency.on_world_state(m);
    } else if (event->channel == c.render_status) {
      arphys::render_status_t m;
      if ((ok = decode(*event, m))) latency.on_render_status(m);
    }
    undecodable += ok ? 0 : 1;
  }
  std::printf("%s: %ld events, %ld undecodable\n", log_path.c_str(), events, undecodable);
  latency.print();
  if (!out.empty()) {
    std::ofstream(out + "/latency.json") << latency.to_json().dump(2) << "\n";
    latency.write_samples_csv(out + "/latency_samples.csv");
  }
  return 0;
}

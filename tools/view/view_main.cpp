// arphys-view: the pipeline's LCM traffic served over the Foxglove WebSocket protocol, for
// Foxglove, Lichtblick or any client of foxglove.websocket.v1 (docs/pipeline.md).
#include <sys/resource.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <csignal>
#include <cstdio>

#include "lcmtypes/msg/clock.hpp"
#include "lcmtypes/msg/heartbeat.hpp"
#include "tools/view/foxglove_server.hpp"
#include "tools/view/view_relay.hpp"

namespace {

volatile std::sig_atomic_t g_stop = 0;

// CPU seconds this process has used (user and system).
double cpu_s() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_utime.tv_sec + usage.ru_stime.tv_sec + 1e-6 * (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

// The view's 1 Hz heartbeat: clients, messages sent a second, what it dropped and refused.
void publish_status(arphys::msg::Bus& bus, const arphys::view::ViewRelay& relay,
                    const arphys::view::FoxgloveServer& server, double uptime_s, double sent_per_s,
                    double cpu_percent) {
  const arphys::view::ServerCounters c = server.counters();
  arphys::process_status_t status = arphys::msg::heartbeat("view", "foxglove.websocket.v1", uptime_s, bus);
  status.state = "serving";
  status.rate_hz = sent_per_s;
  status.published = c.sent;
  status.dropped = c.dropped_backlog + relay.rate_limited();
  status.rejected = c.bad_requests + c.refused_handshakes + relay.refused();
  arphys::msg::add_figure(status, "clients", static_cast<double>(c.clients_now));
  arphys::msg::add_figure(status, "clients_total", static_cast<double>(c.clients_total));
  arphys::msg::add_figure(status, "port", server.port());
  arphys::msg::add_figure(status, "dropped_slow_clients", static_cast<double>(c.dropped_backlog));
  arphys::msg::add_figure(status, "client_commands", static_cast<double>(c.client_messages));
  arphys::msg::add_figure(status, "cpu_percent", cpu_percent);
  bus.publish(relay.status_channel(), status);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace arphys;
  CLI::App app{
      "arphys-view: serves a run's camera frames, overlay, world, transforms, status and latency over\n"
      "the Foxglove WebSocket protocol (foxglove.websocket.v1, JSON) at ws://HOST:PORT/."};
  std::string scene_path = config::default_config_dir() + "/scenes/bunny_box_table.yaml", url;
  view::ServerOptions server_options;
  view::RelayOptions relay_options;
  std::string web_dir = ARPHYS_VIEW_WEB_DIR;
  app.add_option("scene", scene_path, "scene YAML file (its channels and body shapes)")->capture_default_str();
  app.add_option("--port", server_options.port, "TCP port (0: any free one)")->capture_default_str();
  app.add_option("--host", server_options.host, "address to listen on")->capture_default_str();
  app.add_option("--lcm-url", url, "LCM URL (default: the scene's)");
  app.add_option("--image-rate-hz", relay_options.image_rate_hz, "most camera and overlay frames a second sent")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option_function<double>(
         "--max-backlog-mb",
         [&](const double& mb) { server_options.max_backlog_bytes = static_cast<std::size_t>(mb * 1e6); },
         "a client with more than this queued is sent nothing until it drains (counted)")
      ->check(CLI::PositiveNumber)
      ->default_str("8");
  bool allow_spawn = false, allow_replay_control = false;
  int nice_increment = 10;
  std::string replay_control_channel = "ARPHYS_REPLAY_CONTROL";
  app.add_flag(
      "--allow-spawn", allow_spawn,
      "let clients publish spawn commands on /spawn (a dynamic virtual model of the scene, within its limits)");
  app.add_flag("--allow-replay-control", allow_replay_control,
               "let clients pause, step, seek and change the rate of arphys-replay on /replay_control");
  app.add_option("--replay-control-channel", replay_control_channel, "arphys-replay's --control-channel")
      ->capture_default_str();
  app.add_option("--nice", nice_increment,
                 "lower this process's scheduling priority by this much: a monitor yields to the pipeline it watches")
      ->check(CLI::Range(0, 19))
      ->capture_default_str();
  app.add_option("--web-dir", web_dir, "the page's files (index.html, its script, node_modules/three)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  std::unique_ptr<view::ViewRelay> relay;
  std::unique_ptr<view::FoxgloveServer> server;
  std::unique_ptr<msg::Bus> bus;
  try {
    const config::SceneConfig scene = config::load_scene(scene_path);
    bus = std::make_unique<msg::Bus>(url.empty() ? scene.lcm_url : url);
    relay = std::make_unique<view::ViewRelay>(scene, relay_options);
    server_options.files = relay->files("/models/");
    server_options.index_html = view::page(web_dir, scene.name, server_options.files);
    if (allow_spawn) {
      server_options.client_topics.push_back("/spawn");
      server_options.metadata["spawn_models"] = relay->spawnable_models();
    }
    if (allow_replay_control) {
      server_options.client_topics.push_back("/replay_control");
      server_options.metadata["replay_control"] = replay_control_channel;
    }
    server_options.on_client_message = [&](const std::string& topic, const std::string& payload) {
      return topic == "/spawn" ? relay->spawn(*bus, payload)
                               : relay->replay_control(*bus, replay_control_channel, payload);
    };
    server = std::make_unique<view::FoxgloveServer>(server_options, view::topics());
    relay->set_model_url_prefix("http://" + server_options.host + ":" + std::to_string(server->port()) + "/models/");
    relay->subscribe(*bus, *server);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "arphys-view: %s\n", e.what());
    return 2;
  }
  if (nice_increment > 0 && setpriority(PRIO_PROCESS, 0, getpriority(PRIO_PROCESS, 0) + nice_increment) != 0)
    std::fprintf(stderr, "arphys-view: cannot lower its priority (--nice %d); going on\n", nice_increment);
  std::signal(SIGINT, [](int) { g_stop = 1; });
  std::signal(SIGTERM, [](int) { g_stop = 1; });
  std::printf("arphys-view: http://%s:%d/ (the page; ws:// for Foxglove and Lichtblick, foxglove.websocket.v1)\n",
              server_options.host.c_str(), server->port());
  std::fflush(stdout);
  const double started = msg::steady_s();
  double last_status = started;
  int64_t sent_at_status = 0;
  double cpu_at_status = cpu_s();
  while (!g_stop) {
    bus->handle_timeout_ms(100);
    if (const double t = msg::steady_s(); t - last_status >= 1.0) {
      publish_status(*bus, *relay, *server, t - started, (server->counters().sent - sent_at_status) / (t - last_status),
                     100 * (cpu_s() - cpu_at_status) / (t - last_status));
      sent_at_status = server->counters().sent;
      cpu_at_status = cpu_s();
      last_status = t;
    }
  }
  const view::ServerCounters c = server->counters();
  std::fprintf(stderr,
               "arphys-view: %lld clients, %lld messages sent, %lld dropped for slow clients, %lld bad requests, "
               "%lld inputs refused; cpu %.3f s over %.3f s\n",
               static_cast<long long>(c.clients_total), static_cast<long long>(c.sent),
               static_cast<long long>(c.dropped_backlog), static_cast<long long>(c.bad_requests),
               static_cast<long long>(relay->refused()), cpu_s(), msg::steady_s() - started);
  return 0;
}

// arphys-replay: plays an lcm-logger file onto the bus as lcm-logplayer does, and pauses,
// resumes, steps one frame, seeks and changes rate, from the keyboard (in a terminal) or by
// replay_control_t messages; its 1 Hz status says the log's duration and the position.
#include <termios.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>

#include "arphys/replay_control_t.hpp"
#include "configs/loader/scene_config.hpp"
#include "lcmtypes/msg/clock.hpp"
#include "lcmtypes/msg/frame_order.hpp"
#include "lcmtypes/msg/heartbeat.hpp"
#include "tools/replay/log_player.hpp"

namespace {

using namespace arphys;

volatile std::sig_atomic_t g_stop = 0;

// The terminal in single-key mode while it lives (when stdin is one).
struct Keys {
  bool on = false;
  termios saved{};
  Keys() {
    if (!isatty(STDIN_FILENO) || tcgetattr(STDIN_FILENO, &saved) != 0) return;
    termios raw = saved;
    raw.c_lflag &= ~static_cast<tcflag_t>(ICANON | ECHO);
    raw.c_cc[VMIN] = 0;
    raw.c_cc[VTIME] = 0;
    on = tcsetattr(STDIN_FILENO, TCSANOW, &raw) == 0;
  }
  ~Keys() {
    if (on) tcsetattr(STDIN_FILENO, TCSANOW, &saved);
  }
  int read_key() const {
    char c = 0;
    return on && ::read(STDIN_FILENO, &c, 1) == 1 ? c : -1;
  }
};

// Applies one command ("pause", "resume", "toggle", "step", "seek", "rate"); false for an
// unknown one or a bad value (the caller counts it).
bool apply(replay::LogPlayer& player, const std::string& command, double value, const std::string& frame_channel,
           const replay::LogPlayer::Publish& publish) {
  const double t = msg::steady_s();
  if (command == "pause")
    player.pause(t);
  else if (command == "resume")
    player.resume(t);
  else if (command == "toggle")
    player.paused() ? player.resume(t) : player.pause(t);
  else if (command == "step")
    player.step(frame_channel, publish);
  else if (command == "seek" && std::isfinite(value))
    player.seek(value, t);
  else if (command == "rate" && value > 0 && value <= 1000)
    player.set_rate(value, t);
  else
    return false;
  return true;
}

void report(const replay::LogPlayer& player) {
  std::fprintf(stderr, "arphys-replay: %s %.2f / %.2f s at %gx, %lld of %lld events\n",
               player.finished() ? "finished"
               : player.paused() ? "paused"
                                 : "playing",
               player.position_s(), player.duration_s(), player.rate(), static_cast<long long>(player.published()),
               static_cast<long long>(player.events()));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "arphys-replay: an lcm-logger file played onto the bus (as lcm-logplayer), with pause, resume,\n"
      "one-frame steps, seeks and rate changes from the keyboard or by replay_control_t messages.\n"
      "Keys: space pause/resume, n next frame, [ ] seek -/+ 5 s, - + rate /2 x2, q quit."};
  std::string log, url = config::SceneConfig().lcm_url, channels, frame_channel = "ARPHYS_CAMERA_IMAGE";
  std::string control_channel = "ARPHYS_REPLAY_CONTROL", status_channel = config::SceneConfig().channels.process_status;
  replay::PlayerOptions options;
  bool start_paused = false, hold = false;
  app.add_option("log", log, "lcm-logger file")->required();
  app.add_option("--lcm-url", url, "LCM URL to play onto")->capture_default_str();
  app.add_option("--rate", options.rate, "times real time")->capture_default_str();
  app.add_option("--start-s", options.start_s, "seconds into the log to start from")->capture_default_str();
  app.add_option("--channels", channels, "regular expression of the channels to play (default: all)");
  app.add_option("--frame-channel", frame_channel, "what one step plays to")->capture_default_str();
  app.add_option("--control-channel", control_channel, "replay_control_t commands")->capture_default_str();
  app.add_option("--status-channel", status_channel, "1 Hz process_status_t")->capture_default_str();
  app.add_flag("--paused", start_paused, "start paused (resume with space or a control message)");
  app.add_flag("--hold", hold, "stay at the end of the log (for seeks) instead of exiting");
  CLI11_PARSE(app, argc, argv);
  options.channels = channels;
  std::unique_ptr<replay::LogPlayer> player;
  std::unique_ptr<msg::Bus> bus;
  try {
    player = std::make_unique<replay::LogPlayer>(log, options);
    bus = std::make_unique<msg::Bus>(url);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "arphys-replay: %s\n", e.what());
    return 2;
  }
  std::signal(SIGINT, [](int) { g_stop = 1; });
  std::signal(SIGTERM, [](int) { g_stop = 1; });
  const replay::LogPlayer::Publish publish = [&](const replay::LogEvent& e) {
    bus->publish_raw(e.channel, e.data.data(), static_cast<unsigned>(e.data.size()));
  };
  msg::FrameOrder order;
  int64_t commands = 0, refused = 0;
  bus->subscribe<arphys::replay_control_t>(
      control_channel, [&](const arphys::replay_control_t& m, const lcm::ReceiveBuffer&, const std::string&) {
        const bool fresh = order.check(m.sender, m.seq, m.utime) == msg::FrameOrder::Verdict::kNew;
        fresh&& apply(*player, m.command, m.value, frame_channel, publish) ? ++commands : ++refused;
      });
  Keys keys;
  std::fprintf(stderr, "arphys-replay: %s, %lld events over %.2f s onto %s%s\n", log.c_str(),
               static_cast<long long>(player->events()), player->duration_s(), url.c_str(),
               keys.on ? " (keys: space n [ ] - + q)" : "");
  const double started = msg::steady_s();
  int64_t published_at_status = 0;
  double status_at = started;
  const auto publish_status = [&](double t) {
    arphys::process_status_t status = msg::heartbeat("replay", log, t - started, *bus);
    status.rate_hz = t > status_at ? (player->published() - published_at_status) / (t - status_at) : 0;
    published_at_status = player->published();
    status_at = t;
    status.state = player->finished() ? "finished" : player->paused() ? "paused" : "playing";
    status.published = player->published();
    status.rejected = refused;
    msg::add_figure(status, "duration_s", player->duration_s());
    msg::add_figure(status, "position_s", player->position_s());
    msg::add_figure(status, "rate", player->rate());
    msg::add_figure(status, "paused", player->paused() ? 1 : 0);
    msg::add_figure(status, "commands", static_cast<double>(commands));
    bus->publish(status_channel, status);
  };
  if (!start_paused) player->resume(started);
  double last_status = -1, last_report = started;
  while (!g_stop && (hold || !player->finished())) {
    const double wait_s = player->play(msg::steady_s(), publish);
    for (int key; (key = keys.read_key()) >= 0;) {
      if (key == 'q') g_stop = 1;
      const bool applied =
          (key == ' ' && apply(*player, "toggle", 0, frame_channel, publish)) ||
          (key == 'n' && apply(*player, "step", 0, frame_channel, publish)) ||
          ((key == '[' || key == ']') &&
           apply(*player, "seek", player->position_s() + (key == '[' ? -5 : 5), frame_channel, publish)) ||
          ((key == '-' || key == '+') &&
           apply(*player, "rate", std::clamp(player->rate() * (key == '-' ? 0.5 : 2), 1e-3, 1e3), frame_channel,
                 publish));
      if (applied) report(*player);
    }
    const double t = msg::steady_s();
    if (t - last_status >= 1.0) {
      publish_status(t);
      last_status = t;
    }
    if (t - last_report >= 2.0) {
      report(*player);
      last_report = t;
    }
    bus->handle_timeout_ms(static_cast<int>(std::clamp(wait_s * 1000, 0.0, 20.0)));
  }
  publish_status(msg::steady_s());  // the last word: finished (or stopped) and where
  report(*player);
  return 0;
}

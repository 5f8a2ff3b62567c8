#pragma once
// Plays an lcm-logger file as lcm-logplayer does (each event when its log time comes, at a
// rate), and also pauses, resumes, steps one frame and seeks. Transport-free: the caller
// gives the clock and publishes what play() hands it.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

struct _lcm_eventlog_t;

namespace arphys::replay {

struct LogEvent {
  int64_t timestamp_us = 0;  // when lcm-logger received it
  std::string channel;
  std::vector<uint8_t> data;
};

struct PlayerOptions {
  double rate = 1.0;     // times real time, > 0
  double start_s = 0;    // from the log's first event
  std::string channels;  // regular expression of the channels to play (empty: all)
};

class LogPlayer {
 public:
  // Indexes the log (throws std::runtime_error naming the file when it cannot be read, and
  // std::invalid_argument naming a bad option); starts paused at options.start_s.
  LogPlayer(const std::string& path, const PlayerOptions& options);
  ~LogPlayer();
  LogPlayer(const LogPlayer&) = delete;
  LogPlayer& operator=(const LogPlayer&) = delete;

  using Publish = std::function<void(const LogEvent&)>;
  // Publishes every event due by now_s (a monotonic clock, seconds); none while paused.
  // Returns the seconds until the next one is due (infinity: paused or finished).
  double play(double now_s, const Publish& publish);
  // Publishes the events up to and including the next one on frame_channel, then pauses
  // (a frame channel of no event: to the end).
  void step(const std::string& frame_channel, const Publish& publish);
  void pause(double now_s);
  void resume(double now_s);
  // To t_s from the log's first event (clamped to it), paused or playing as before.
  void seek(double t_s, double now_s);
  void set_rate(double rate, double now_s);

  // Times are seconds from the log's first event, whatever channels are played.
  double duration_s() const;
  double position_s() const;  // of the next event to play
  bool paused() const { return paused_; }
  bool finished() const { return next_ >= index_.size(); }
  double rate() const { return rate_; }
  int64_t published() const { return published_; }
  int64_t events() const { return static_cast<int64_t>(index_.size()); }

 private:
  struct Entry {
    int64_t timestamp_us;
    long offset;
  };
  LogEvent read(std::size_t k);
  double log_time_at(double now_s) const;  // seconds from the first event, at wall time now_s
  void anchor(double now_s);

  std::string path_;
  _lcm_eventlog_t* log_ = nullptr;
  std::vector<Entry> index_;            // the played channels' events, in log order
  int64_t first_us_ = 0, last_us_ = 0;  // the log's first and last events, any channel
  std::size_t next_ = 0;
  double rate_ = 1.0;
  bool paused_ = true;
  double anchor_wall_s_ = 0, anchor_log_s_ = 0;
  int64_t published_ = 0;
};

}  // namespace arphys::replay

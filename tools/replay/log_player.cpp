#include "tools/replay/log_player.hpp"

#include <lcm/eventlog.h>

#include <cmath>
#include <limits>
#include <regex>
#include <stdexcept>

namespace arphys::replay {

namespace {

// A rate outside (0, 1000] (or not a number) would stall the clock or flood the bus.
double checked_rate(double rate) {
  if (!(rate > 0 && rate <= 1000))
    throw std::invalid_argument("rate " + std::to_string(rate) + ": expected 0 < rate <= 1000");
  return rate;
}

}  // namespace

LogPlayer::LogPlayer(const std::string& path, const PlayerOptions& options)
    : path_(path), rate_(checked_rate(options.rate)) {
  if (!(options.start_s >= 0) || !std::isfinite(options.start_s))
    throw std::invalid_argument("start " + std::to_string(options.start_s) + " s: expected a time >= 0");
  std::regex channels;
  try {
    channels = std::regex(options.channels.empty() ? ".*" : options.channels);
  } catch (const std::regex_error& e) {
    throw std::invalid_argument("channels '" + options.channels + "': not a regular expression (" + e.what() + ")");
  }
  log_ = lcm_eventlog_create(path.c_str(), "r");
  if (!log_) throw std::runtime_error(path + ": cannot open the log");
  // One pass: where each event of the played channels starts (its data is read again when
  // it is played, so a log of camera frames is not held in memory).
  for (;;) {
    const long offset = std::ftell(log_->f);
    lcm_eventlog_event_t* e = lcm_eventlog_read_next_event(log_);
    if (!e) break;
    if (first_us_ == 0) first_us_ = e->timestamp;
    last_us_ = e->timestamp;
    if (std::regex_match(std::string(e->channel, e->channellen), channels)) index_.push_back({e->timestamp, offset});
    lcm_eventlog_free_event(e);
  }
  if (index_.empty())
    throw std::runtime_error(path + ": no events" + (options.channels.empty() ? "" : " on " + options.channels));
  seek(options.start_s, 0);
}

LogPlayer::~LogPlayer() {
  if (log_) lcm_eventlog_destroy(log_);
}

LogEvent LogPlayer::read(std::size_t k) {
  if (std::fseek(log_->f, index_[k].offset, SEEK_SET) != 0) throw std::runtime_error(path_ + ": cannot seek");
  lcm_eventlog_event_t* e = lcm_eventlog_read_next_event(log_);
  if (!e) throw std::runtime_error(path_ + ": an indexed event cannot be read again");
  LogEvent out{e->timestamp, std::string(e->channel, e->channellen),
               std::vector<uint8_t>(static_cast<uint8_t*>(e->data), static_cast<uint8_t*>(e->data) + e->datalen)};
  lcm_eventlog_free_event(e);
  return out;
}

double LogPlayer::duration_s() const { return (last_us_ - first_us_) * 1e-6; }

double LogPlayer::position_s() const {
  return finished() ? duration_s() : (index_[next_].timestamp_us - first_us_) * 1e-6;
}

double LogPlayer::log_time_at(double now_s) const {
  return paused_ ? anchor_log_s_ : anchor_log_s_ + (now_s - anchor_wall_s_) * rate_;
}

void LogPlayer::anchor(double now_s) {
  anchor_log_s_ = log_time_at(now_s);
  anchor_wall_s_ = now_s;
}

double LogPlayer::play(double now_s, const Publish& publish) {
  if (paused_) return std::numeric_limits<double>::infinity();
  const double log_s = log_time_at(now_s);
  const int64_t first_us = first_us_;
  while (!finished() && (index_[next_].timestamp_us - first_us) * 1e-6 <= log_s) {
    publish(read(next_++));
    ++published_;
  }
  if (finished()) return std::numeric_limits<double>::infinity();
  return std::max(0.0, ((index_[next_].timestamp_us - first_us) * 1e-6 - log_s) / rate_);
}

void LogPlayer::step(const std::string& frame_channel, const Publish& publish) {
  paused_ = true;
  while (!finished()) {
    LogEvent e = read(next_++);
    const bool frame = e.channel == frame_channel;
    publish(e);
    ++published_;
    if (frame) break;
  }
  anchor_log_s_ = position_s();
}

void LogPlayer::pause(double now_s) {
  if (paused_) return;
  anchor(now_s);
  paused_ = true;
}

void LogPlayer::resume(double now_s) {
  if (!paused_) return;
  anchor_wall_s_ = now_s;
  paused_ = false;
}

void LogPlayer::seek(double t_s, double now_s) {
  const int64_t target_us = first_us_ + static_cast<int64_t>(std::llround(std::max(0.0, t_s) * 1e6));
  next_ = 0;
  while (next_ < index_.size() && index_[next_].timestamp_us < target_us) ++next_;
  anchor_log_s_ = position_s();
  anchor_wall_s_ = now_s;
}

void LogPlayer::set_rate(double rate, double now_s) {
  anchor(now_s);
  rate_ = checked_rate(rate);
}

}  // namespace arphys::replay

#pragma once
// An lcm-logger file written by a test: `count` events 50 ms apart, event k on
// channel_of(k), its one data byte k.
#include <lcm/eventlog.h>

#include <cstdint>
#include <functional>
#include <string>

namespace arphys::replay::testing {

inline void write_test_log(const std::string& path, int count, const std::function<std::string(int)>& channel_of) {
  lcm_eventlog_t* log = lcm_eventlog_create(path.c_str(), "w");
  if (!log) return;
  for (int k = 0; k < count; ++k) {
    std::string channel = channel_of(k);
    uint8_t data = static_cast<uint8_t>(k);
    lcm_eventlog_event_t e{};
    e.timestamp = 1'700'000'000'000'000 + k * 50'000;
    e.channellen = static_cast<int32_t>(channel.size());
    e.channel = channel.data();
    e.datalen = 1;
    e.data = &data;
    lcm_eventlog_write_event(log, &e);
  }
  lcm_eventlog_destroy(log);
}

}  // namespace arphys::replay::testing

#include "lcmtypes/msg/bus.hpp"


#include <exception>
#include <stdexcept>

namespace arphys::msg {

Bus::Bus(const std::string& url) : url_(url), lcm_(std::make_unique<lcm::LCM>(url)) {
  if (!lcm_->good()) {
    throw std::runtime_error(
        "LCM could not start on URL '" + (url.empty() ? std::string("(default)") : url) +
        "'. For udpm:// LCM needs a multicast route: `ip route add 224.0.0.0/4 dev lo` (one host) or "
        "`... dev <interface>` (several machines), or a default route.");
  }
}

Bus::~Bus() = default;

void Bus::publish_raw(const std::string& channel, const void* data, unsigned int size) {
  lcm_->publish(channel, data, size);
}

bool Bus::handle_timeout_ms(int timeout_ms) { return lcm_->handleTimeout(timeout_ms) > 0; }

int Bus::handle_pending() {
  int handled = 0;
  while (lcm_->handleTimeout(0) > 0) ++handled;
  return handled;
}

int Bus::file_descriptor() { return lcm_->getFileno(); }

void Bus::count_decode_error(const std::string& channel, uint32_t size) {
  ++counters_.decode_errors;
  counters_.last_error = "channel " + channel + ": " + std::to_string(size) + "-byte message did not decode";
}

void Bus::DispatcherBase::on_message(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
  ++bus->counters_.received;
  // Exceptions must not cross LCM's C dispatch loop: count and drop here.
  try {
    decode_and_call(*rbuf, channel);
  } catch (const std::bad_alloc&) {
    bus->count_decode_error(channel, rbuf->data_size);
  } catch (const std::length_error&) {
    bus->count_decode_error(channel, rbuf->data_size);
  } catch (const std::exception& e) {
    ++bus->counters_.rejected;
    bus->counters_.last_error = "channel " + channel + ": " + e.what();
  }
}

}  // namespace arphys::msg

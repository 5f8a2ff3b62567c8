#include "lcmtypes/msg/bus.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <stdexcept>

namespace arphys::msg {

namespace {

// Camera images are larger than Linux's default socket receive buffer (212 KB): a
// multicast URL without an explicit recv_buf_size gets 4 MiB, so a burst of frames is
// not dropped by the kernel. The kernel caps it at net.core.rmem_max (see warn below).
constexpr int kReceiveBufferBytes = 4 << 20;

std::string with_receive_buffer(const std::string& url) {
  if (url.rfind("udpm://", 0) != 0 || url.find("recv_buf_size") != std::string::npos) return url;
  return url + (url.find('?') == std::string::npos ? "?" : "&") + "recv_buf_size=" + std::to_string(kReceiveBufferBytes);
}

void warn_if_kernel_caps_the_buffer(const std::string& url) {
  if (url.rfind("udpm://", 0) != 0) return;
  std::ifstream in("/proc/sys/net/core/rmem_max");
  long rmem_max = 0;
  if (!(in >> rmem_max) || rmem_max >= 1 << 20) return;
  static bool warned = false;
  if (!warned) {
    std::fprintf(stderr, "arphys: net.core.rmem_max is %ld bytes, smaller than one raw camera frame: images may be "
                 "dropped. Raise it (sysctl -w net.core.rmem_max=4194304) or send JPEG images.\n", rmem_max);
    warned = true;
  }
}

double number_from_environment(const char* name, double fallback, double min, double max) {
  const char* text = std::getenv(name);
  if (!text || !*text) return fallback;
  char* end = nullptr;
  const double value = std::strtod(text, &end);
  if (*end != '\0' || !(value >= min && value <= max)) {
    throw std::invalid_argument(std::string(name) + "='" + text + "': expected a number in [" + std::to_string(min) +
                                ", " + std::to_string(max) + "]");
  }
  return value;
}

}  // namespace

Bus::Bus(const std::string& url) : url_(with_receive_buffer(url)), lcm_(std::make_unique<lcm::LCM>(url_)) {
  receive_loss_ = std::bernoulli_distribution(number_from_environment("ARPHYS_FAULT_RECEIVE_LOSS", 0.0, 0.0, 0.99));
  loss_rng_.seed(static_cast<std::uint64_t>(number_from_environment("ARPHYS_FAULT_SEED", getpid(), 0, 1e15)));
  warn_if_kernel_caps_the_buffer(url_);
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

void Bus::count_decode_error(const std::string& channel, uint32_t size) {
  ++counters_.decode_errors;
  counters_.last_error = "channel " + channel + ": " + std::to_string(size) + "-byte message did not decode";
}

void Bus::DispatcherBase::on_message(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
  if (bus->receive_loss_.p() > 0 && bus->receive_loss_(bus->loss_rng_)) {
    ++bus->counters_.injected_losses;
    return;
  }
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

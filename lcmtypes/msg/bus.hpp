#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

namespace arphys::msg {

// A message in its LCM encoding (what goes on the wire, or into a state file).
template <class Message>
std::vector<uint8_t> encode(const Message& message) {
  std::vector<uint8_t> bytes(static_cast<std::size_t>(message.getEncodedSize()));
  message.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

// What a process received, per bus: exported in its status heartbeat.
struct MessageCounters {
  int64_t received = 0;       // messages that reached a subscription
  int64_t decode_errors = 0;  // dropped: bytes did not decode as the channel's type
  int64_t rejected = 0;       // dropped: decoded, but the handler refused the content
  int64_t injected_losses = 0;  // dropped on purpose by ARPHYS_FAULT_RECEIVE_LOSS (fault injection)
  std::string last_error;     // the most recent decode error or rejection, for the log
};

// A thin wrapper over lcm::LCM that never lets a malformed message crash the
// process: each subscription decodes with the generated (hardened) decoder, counts
// failures and drops them. A handler signals a bad *content* (NaN pose, wrong size)
// by throwing std::exception; the message is counted as rejected and dropped.
class Bus {
 public:
  // url: an LCM provider URL ("" = LCM_DEFAULT_URL or udpm://239.255.76.67:7667?ttl=0,
  // "memq://" = in-process, "file:///path?mode=r" = a log). Throws std::runtime_error
  // when LCM cannot start (typically: no multicast route), saying how to fix it.
  //
  // Fault injection: the environment variable ARPHYS_FAULT_RECEIVE_LOSS=F (0 <= F < 1)
  // makes this bus drop a fraction F of the messages it receives, at random (seed:
  // ARPHYS_FAULT_SEED, default the pid), before they are counted or decoded: packet loss
  // on the receiving side, which is where multicast loses datagrams. Counted in
  // injected_losses. A malformed value throws std::invalid_argument naming the variable.
  explicit Bus(const std::string& url = "");
  ~Bus();
  Bus(const Bus&) = delete;
  Bus& operator=(const Bus&) = delete;

  template <class Message>
  void publish(const std::string& channel, const Message& message) {
    lcm_->publish(channel, &message);
  }

  // Publishes raw bytes (used by fault-injection tools and tests).
  void publish_raw(const std::string& channel, const void* data, unsigned int size);

  // channel is an LCM channel regex. The handler gets the decoded message and the
  // receive buffer (recv_utime = kernel receive time, microseconds).
  template <class Message>
  void subscribe(const std::string& channel,
                 std::function<void(const Message&, const lcm::ReceiveBuffer&, const std::string& channel)> handler) {
    auto dispatcher = std::make_unique<TypedDispatcher<Message>>(this, std::move(handler));
    lcm_->subscribe(channel, &DispatcherBase::on_message, static_cast<DispatcherBase*>(dispatcher.get()));
    dispatchers_.push_back(std::move(dispatcher));
  }

  // Handles at most one message, waiting up to timeout_ms. Returns true if one was handled.
  bool handle_timeout_ms(int timeout_ms);
  // Handles every message already waiting, returns how many.
  int handle_pending();

  const MessageCounters& counters() const { return counters_; }
  const std::string& url() const { return url_; }

 private:
  struct DispatcherBase {
    virtual ~DispatcherBase() = default;
    void on_message(const lcm::ReceiveBuffer* rbuf, const std::string& channel);
    virtual void decode_and_call(const lcm::ReceiveBuffer& rbuf, const std::string& channel) = 0;
    Bus* bus = nullptr;
  };
  template <class Message>
  struct TypedDispatcher : DispatcherBase {
    TypedDispatcher(Bus* owner, std::function<void(const Message&, const lcm::ReceiveBuffer&, const std::string&)> h)
        : handler(std::move(h)) {
      bus = owner;
    }
    void decode_and_call(const lcm::ReceiveBuffer& rbuf, const std::string& channel) override {
      Message message;
      if (message.decode(rbuf.data, 0, static_cast<int>(rbuf.data_size)) < 0) {
        bus->count_decode_error(channel, rbuf.data_size);
        return;
      }
      handler(message, rbuf, channel);
    }
    std::function<void(const Message&, const lcm::ReceiveBuffer&, const std::string&)> handler;
  };

  void count_decode_error(const std::string& channel, uint32_t size);

  std::string url_;
  std::unique_ptr<lcm::LCM> lcm_;
  MessageCounters counters_;
  std::vector<std::unique_ptr<DispatcherBase>> dispatchers_;
  std::bernoulli_distribution receive_loss_{0.0};  // drops a received message with this probability
  std::mt19937_64 loss_rng_;
};

}  // namespace arphys::msg

#pragma once
// A Foxglove WebSocket protocol server (subprotocol foxglove.websocket.v1, JSON messages)
// on websocketpp, with plain HTTP on the same port for files (the models its scene
// updates reference). Read-only: clients subscribe and unsubscribe, nothing else. A
// client that does not keep up is skipped while its send backlog is over the limit (it
// gets the newest messages once it drains), counted, and never slows the publisher.
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "tools/view/foxglove_messages.hpp"

namespace arphys::view {

struct ServerOptions {
  std::string host = "127.0.0.1";
  uint16_t port = 8765;  // 0: any free port (see FoxgloveServer::port)
  std::string name = "arphys-view";
  std::size_t max_backlog_bytes = 8u << 20;  // per client
  // HTTP paths served: path ("/models/x.obj") -> absolute file; "/" -> page text.
  std::map<std::string, std::string> files;
  std::string index_html;
  // Topics clients may publish on (JSON), and what takes their messages: it returns "" when
  // it accepts one, or why it refuses it (sent back as a status message, counted). Called on
  // the server's thread. No topics: read-only.
  std::vector<std::string> client_topics;
  std::function<std::string(const std::string& topic, const std::string& payload)> on_client_message;
  nlohmann::json metadata = nlohmann::json::object();  // the serverInfo's
};

struct ServerCounters {
  int64_t clients_now = 0, clients_total = 0;
  int64_t sent = 0;             // message frames queued to clients
  int64_t dropped_backlog = 0;  // frames skipped for a client over its backlog limit
  int64_t bad_requests = 0;     // client messages that were not JSON, not an op we take, or refused
  int64_t http_requests = 0;
  int64_t refused_handshakes = 0;  // connections without the foxglove subprotocol
  int64_t client_messages = 0;     // accepted by on_client_message
};

class FoxgloveServer {
 public:
  // Binds and starts serving on its own thread; throws std::runtime_error naming the
  // host and port when it cannot listen.
  FoxgloveServer(ServerOptions options, std::vector<Topic> topics);
  ~FoxgloveServer();
  FoxgloveServer(const FoxgloveServer&) = delete;
  FoxgloveServer& operator=(const FoxgloveServer&) = delete;

  // Sends payload (the topic's JSON) to every subscriber of topic `channel` (its index in
  // the topics given). Thread-safe, returns at once.
  void publish(int channel, uint64_t time_ns, std::string payload);
  // Whether any client subscribes to the channel (a publisher may skip building it).
  bool subscribed(int channel) const;
  ServerCounters counters() const;
  uint16_t port() const { return port_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  uint16_t port_ = 0;
};

}  // namespace arphys::view

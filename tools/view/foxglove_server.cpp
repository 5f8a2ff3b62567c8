#include "tools/view/foxglove_server.hpp"

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <websocketpp/config/asio_no_tls.hpp>
#include <websocketpp/server.hpp>

namespace arphys::view {
namespace {

using Server = websocketpp::server<websocketpp::config::asio>;
using Handle = websocketpp::connection_hdl;
constexpr const char* kSubprotocol = "foxglove.websocket.v1";

std::string file_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

std::string content_type(const std::string& path) {
  const auto ends = [&](const std::string& s) {
    return path.size() >= s.size() && path.compare(path.size() - s.size(), s.size(), s) == 0;
  };
  if (ends(".html") || path == "/") return "text/html; charset=utf-8";
  if (ends(".js") || ends(".mjs")) return "text/javascript";
  if (ends(".obj")) return "model/obj";
  return "application/octet-stream";
}

}  // namespace

struct FoxgloveServer::Impl {
  ServerOptions options;
  std::vector<Topic> topics;
  Server server;
  std::thread thread;
  // Per client (io thread only): subscription id by channel, and its advertised topics by channel id.
  struct Client {
    std::map<int, uint32_t> subs;
    std::map<uint32_t, std::string> published;
  };
  std::map<Handle, Client, std::owner_less<Handle>> clients;
  std::vector<std::atomic<int>> subscribers;  // per channel, read by any thread
  std::atomic<int64_t> clients_now{0}, clients_total{0}, sent{0}, dropped{0}, bad{0}, http{0}, refused{0}, accepted{0};

  Impl(ServerOptions o, std::vector<Topic> t)
      : options(std::move(o)), topics(std::move(t)), subscribers(topics.size()) {}

  void send_text(Handle h, const nlohmann::json& message) {
    websocketpp::lib::error_code ec;
    server.send(h, message.dump(), websocketpp::frame::opcode::text, ec);
  }
  void warn(Handle h, const std::string& why) {
    ++bad;
    send_text(h, {{"op", "status"}, {"level", 1}, {"message", why}});
  }

  void on_open(Handle h) {
    clients[h];
    ++clients_now;
    ++clients_total;
    send_text(h, {{"op", "serverInfo"},
                  {"name", options.name},
                  {"capabilities",
                   options.client_topics.empty() ? nlohmann::json::array() : nlohmann::json::array({"clientPublish"})},
                  {"supportedEncodings", nlohmann::json::array({"json"})},
                  {"metadata", options.metadata}});
    nlohmann::json channels = nlohmann::json::array();
    for (std::size_t k = 0; k < topics.size(); ++k)
      channels.push_back({{"id", k},
                          {"topic", topics[k].topic},
                          {"encoding", "json"},
                          {"schemaName", topics[k].schema_name},
                          {"schema", topics[k].schema},
                          {"schemaEncoding", "jsonschema"}});
    send_text(h, {{"op", "advertise"}, {"channels", channels}});
  }

  void on_close(Handle h) {
    const auto it = clients.find(h);
    if (it == clients.end()) return;
    for (const auto& [channel, id] : it->second.subs) --subscribers[channel];
    clients.erase(it);
    --clients_now;
  }

  void subscribe(Handle h, std::map<int, uint32_t>& subs, const nlohmann::json& list) {
    for (const nlohmann::json& s : list) {
      const int channel = s.at("channelId").get<int>();
      const uint32_t id = s.at("id").get<uint32_t>();
      bool reused = false;
      for (const auto& [c, existing] : subs) reused = reused || existing == id;
      if (channel < 0 || channel >= static_cast<int>(topics.size()) || subs.count(channel) || reused) {
        warn(h, "subscription " + std::to_string(id) + " to channel " + std::to_string(channel) + " refused");
        continue;
      }
      subs[channel] = id;
      ++subscribers[channel];
    }
  }

  // A client's channels: only the topics clients may publish on, JSON-encoded.
  void advertise(Handle h, Client& client, const nlohmann::json& channels) {
    for (const nlohmann::json& c : channels) {
      const std::string topic = c.at("topic").get<std::string>();
      const bool allowed =
          std::find(options.client_topics.begin(), options.client_topics.end(), topic) != options.client_topics.end();
      if (!allowed || c.at("encoding").get<std::string>() != "json") {
        warn(h, "publishing on '" + topic + "' is not allowed" + (options.client_topics.empty() ? " (read-only)" : ""));
        continue;
      }
      client.published[c.at("id").get<uint32_t>()] = topic;
    }
  }

  // Client Message Data: opcode 1, the client's channel id (uint32, little-endian), the payload.
  void client_data(Handle h, const Client& client, const std::string& bytes) {
    if (bytes.size() < 5 || bytes[0] != 0x01) return warn(h, "binary message of an unknown kind");
    uint32_t channel = 0;
    for (int k = 0; k < 4; ++k) channel |= static_cast<uint32_t>(static_cast<unsigned char>(bytes[1 + k])) << (8 * k);
    const auto it = client.published.find(channel);
    if (it == client.published.end())
      return warn(h, "message on channel " + std::to_string(channel) + " not advertised");
    const std::string refusal = options.on_client_message(it->second, bytes.substr(5));
    if (!refusal.empty()) return warn(h, it->second + ": " + refusal);
    ++accepted;
  }

  void on_message(Handle h, const Server::message_ptr& message) {
    Client& client = clients[h];
    auto& subs = client.subs;
    if (message->get_opcode() != websocketpp::frame::opcode::text)
      return client_data(h, client, message->get_payload());
    try {
      const nlohmann::json request = nlohmann::json::parse(message->get_payload());
      const std::string op = request.at("op").get<std::string>();
      if (op == "subscribe") return subscribe(h, subs, request.at("subscriptions"));
      if (op == "advertise") return advertise(h, client, request.at("channels"));
      if (op == "unadvertise") {
        for (const nlohmann::json& id : request.at("channelIds")) client.published.erase(id.get<uint32_t>());
        return;
      }
      if (op != "unsubscribe") return warn(h, "op '" + op + "' is not supported");
      for (const nlohmann::json& id : request.at("subscriptionIds"))
        for (auto it = subs.begin(); it != subs.end(); ++it)
          if (it->second == id.get<uint32_t>()) {
            --subscribers[it->first];
            subs.erase(it);
            break;
          }
    } catch (const std::exception& e) {
      warn(h, std::string("malformed request: ") + e.what());
    }
  }

  void on_http(Handle h) {
    ++http;
    const Server::connection_ptr con = server.get_con_from_hdl(h);
    const std::string path = con->get_resource().substr(0, con->get_resource().find('?'));
    const auto file = options.files.find(path);
    if (path == "/" || file != options.files.end()) {
      con->set_body(path == "/" ? options.index_html : file_text(file->second));
      con->replace_header("Content-Type", content_type(path == "/" ? "/" : file->second));
      con->replace_header("Access-Control-Allow-Origin", "*");  // Foxglove's web app fetches models cross-origin
      con->set_status(websocketpp::http::status_code::ok);
    } else {
      con->set_body("not found: " + path + "\n");
      con->set_status(websocketpp::http::status_code::not_found);
    }
  }

  bool on_validate(Handle h) {
    const Server::connection_ptr con = server.get_con_from_hdl(h);
    for (const std::string& p : con->get_requested_subprotocols())
      if (p == kSubprotocol) {
        con->select_subprotocol(p);
        return true;
      }
    ++refused;
    return false;
  }

  void deliver(int channel, uint64_t time_ns, const std::string& payload) {
    for (auto& [h, client] : clients) {
      const auto sub = client.subs.find(channel);
      if (sub == client.subs.end()) continue;
      websocketpp::lib::error_code ec;
      const Server::connection_ptr con = server.get_con_from_hdl(h, ec);
      if (ec || con->get_buffered_amount() > options.max_backlog_bytes) {
        ++dropped;
        continue;
      }
      server.send(h, message_data(sub->second, time_ns, payload), websocketpp::frame::opcode::binary, ec);
      ec ? ++dropped : ++sent;
    }
  }
};

FoxgloveServer::FoxgloveServer(ServerOptions options, std::vector<Topic> topics)
    : impl_(std::make_unique<Impl>(std::move(options), std::move(topics))) {
  Impl& m = *impl_;
  m.server.clear_access_channels(websocketpp::log::alevel::all);
  m.server.clear_error_channels(websocketpp::log::elevel::all);
  m.server.init_asio();
  m.server.set_reuse_addr(true);
  m.server.set_max_message_size(1 << 20);  // a client's requests are small: a huge one is refused, not buffered
  m.server.set_max_http_body_size(1 << 16);
  using std::placeholders::_1;
  using std::placeholders::_2;
  m.server.set_validate_handler(std::bind(&Impl::on_validate, &m, _1));
  m.server.set_open_handler(std::bind(&Impl::on_open, &m, _1));
  m.server.set_close_handler(std::bind(&Impl::on_close, &m, _1));
  m.server.set_fail_handler(std::bind(&Impl::on_close, &m, _1));
  m.server.set_message_handler(std::bind(&Impl::on_message, &m, _1, _2));
  m.server.set_http_handler(std::bind(&Impl::on_http, &m, _1));
  websocketpp::lib::error_code ec;
  m.server.listen(m.options.host, std::to_string(m.options.port), ec);
  if (!ec) m.server.start_accept(ec);
  if (ec)
    throw std::runtime_error("arphys-view: cannot listen on " + m.options.host + ":" + std::to_string(m.options.port) +
                             ": " + ec.message() + " (another view running? choose --port)");
  websocketpp::lib::asio::error_code asio_ec;
  port_ = m.server.get_local_endpoint(asio_ec).port();
  m.thread = std::thread([&m] { m.server.run(); });
}

FoxgloveServer::~FoxgloveServer() {
  Impl& m = *impl_;
  m.server.get_io_service().post([&m] {
    websocketpp::lib::error_code ec;
    m.server.stop_listening(ec);
    for (auto& [h, client] : m.clients)
      m.server.close(h, websocketpp::close::status::going_away, "server stopping", ec);
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  m.server.stop();
  if (m.thread.joinable()) m.thread.join();
}

void FoxgloveServer::publish(int channel, uint64_t time_ns, std::string payload) {
  if (channel < 0 || channel >= static_cast<int>(impl_->topics.size()) || impl_->subscribers[channel] == 0) return;
  Impl* m = impl_.get();
  m->server.get_io_service().post(
      [m, channel, time_ns, payload = std::move(payload)] { m->deliver(channel, time_ns, payload); });
}

bool FoxgloveServer::subscribed(int channel) const {
  return channel >= 0 && channel < static_cast<int>(impl_->topics.size()) && impl_->subscribers[channel] > 0;
}

ServerCounters FoxgloveServer::counters() const {
  const Impl& m = *impl_;
  return {m.clients_now, m.clients_total, m.sent, m.dropped, m.bad, m.http, m.refused, m.accepted};
}

}  // namespace arphys::view

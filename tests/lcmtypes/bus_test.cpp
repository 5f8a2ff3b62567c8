#include "lcmtypes/msg/bus.hpp"

#include <gtest/gtest.h>

#include <climits>
#include <cstdlib>

#include "arphys/image_t.hpp"
#include "arphys/tracker_control_t.hpp"
#include "arphys/world_state_t.hpp"

namespace arphys::msg {
namespace {

void put_int32_be(std::vector<uint8_t>& bytes, std::size_t at, int32_t value) {
  for (int i = 0; i < 4; ++i) bytes[at + i] = static_cast<uint8_t>((uint32_t(value) >> (24 - 8 * i)) & 0xff);
}

TEST(Bus, DeliversTypedMessagesInProcess) {
  Bus bus("memq://");
  int handled = 0;
  bus.subscribe<arphys::world_state_t>("WS", [&](const arphys::world_state_t& m, const lcm::ReceiveBuffer&,
                                                 const std::string& channel) {
    EXPECT_EQ(channel, "WS");
    EXPECT_EQ(m.scene_name, "s");
    EXPECT_EQ(m.num_bodies, 1);
    ++handled;
  });
  arphys::world_state_t ws{};
  ws.scene_name = "s";
  ws.bodies.resize(1);
  ws.num_bodies = 1;
  bus.publish("WS", ws);
  EXPECT_EQ(bus.handle_pending(), 1);
  EXPECT_EQ(handled, 1);
  EXPECT_EQ(bus.counters().received, 1);
  EXPECT_EQ(bus.counters().decode_errors, 0);
}

TEST(Bus, MalformedMessagesAreCountedAndDropped) {
  Bus bus("memq://");
  int handled = 0;
  bus.subscribe<arphys::world_state_t>("WS", [&](const auto&, const auto&, const auto&) { ++handled; });
  const uint8_t garbage[] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
  bus.publish_raw("WS", garbage, sizeof garbage);
  bus.publish_raw("WS", garbage, 0);
  arphys::world_state_t ws{};
  ws.scene_name = "s";
  std::vector<uint8_t> truncated = encode(ws);
  truncated.resize(truncated.size() - 3);
  bus.publish_raw("WS", truncated.data(), static_cast<unsigned>(truncated.size()));
  // A valid message of another type on the channel: wrong fingerprint.
  arphys::image_t image{};
  image.camera_id = "c";
  const auto other = encode(image);
  bus.publish_raw("WS", other.data(), static_cast<unsigned>(other.size()));
  bus.publish("WS", ws);  // and one good one still gets through
  bus.handle_pending();
  EXPECT_EQ(bus.counters().received, 5);
  EXPECT_EQ(bus.counters().decode_errors, 4);
  EXPECT_EQ(handled, 1);
  EXPECT_NE(bus.counters().last_error.find("channel WS"), std::string::npos);
}

TEST(Bus, HandlerRejectionIsCountedNotPropagated) {
  Bus bus("memq://");
  bus.subscribe<arphys::world_state_t>("WS", [&](const auto&, const auto&, const auto&) {
    throw std::invalid_argument("pose of body 'x' is NaN");
  });
  bus.publish("WS", arphys::world_state_t{});
  EXPECT_NO_THROW(bus.handle_pending());
  EXPECT_EQ(bus.counters().rejected, 1);
  EXPECT_NE(bus.counters().last_error.find("NaN"), std::string::npos);
}

// lcm-gen 1.3.1 would allocate for a wire count before checking the buffer, and
// throw from std::string::assign on a zero string length; our build hardens both.
TEST(HardenedDecode, HugeArrayCountIsRejectedBeforeAllocating) {
  arphys::tracker_control_t control{};
  control.target = "t";
  control.implementation = "apriltag";
  std::vector<uint8_t> bytes = encode(control);
  // Layout: hash(8) utime(8) target(4+2) implementation(4+9) num_params(4)
  put_int32_be(bytes, 8 + 8 + 6 + 13, INT_MAX);
  arphys::tracker_control_t decoded;
  int status = 0;
  EXPECT_NO_THROW(status = decoded.decode(bytes.data(), 0, static_cast<int>(bytes.size())));
  EXPECT_LT(status, 0);

  arphys::image_t image{};
  image.camera_id = "cam";
  std::vector<uint8_t> image_bytes = encode(image);
  put_int32_be(image_bytes, image_bytes.size() - 4, INT_MAX);  // the data size field
  arphys::image_t decoded_image;
  EXPECT_LT(decoded_image.decode(image_bytes.data(), 0, static_cast<int>(image_bytes.size())), 0);
  put_int32_be(image_bytes, image_bytes.size() - 4, -5);
  EXPECT_LT(decoded_image.decode(image_bytes.data(), 0, static_cast<int>(image_bytes.size())), 0);
}

TEST(HardenedDecode, ZeroStringLengthIsRejectedNotThrown) {
  arphys::image_t image{};
  image.camera_id = "cam";
  std::vector<uint8_t> bytes = encode(image);
  put_int32_be(bytes, 8 + 8 + 8, 0);  // camera_id length
  arphys::image_t decoded;
  int status = 0;
  EXPECT_NO_THROW(status = decoded.decode(bytes.data(), 0, static_cast<int>(bytes.size())));
  EXPECT_LT(status, 0);
}

TEST(Bus, BadUrlSaysWhatToDo) {
  try {
    Bus bus("nonsense://x");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("nonsense://x"), std::string::npos) << e.what();
  }
}

// Injected receive loss drops about the asked fraction, counts it, and the messages
// that pass are delivered whole; the same seed drops the same messages.
TEST(Bus, InjectedReceiveLossDropsTheAskedFraction) {
  ::setenv("ARPHYS_FAULT_RECEIVE_LOSS", "0.2", 1);
  ::setenv("ARPHYS_FAULT_SEED", "11", 1);
  auto run = [] {
    Bus bus("memq://");
    std::vector<int64_t> delivered;
    bus.subscribe<arphys::world_state_t>("WS", [&](const arphys::world_state_t& m, const lcm::ReceiveBuffer&,
                                                   const std::string&) { delivered.push_back(m.seq); });
    for (int i = 0; i < 2000; ++i) {
      arphys::world_state_t ws{};
      ws.seq = i;
      bus.publish("WS", ws);
      bus.handle_pending();
    }
    EXPECT_EQ(bus.counters().injected_losses + bus.counters().received, 2000);
    EXPECT_EQ(bus.counters().received, static_cast<int64_t>(delivered.size()));
    return delivered;
  };
  const auto first = run();
  const auto second = run();
  ::unsetenv("ARPHYS_FAULT_RECEIVE_LOSS");
  ::unsetenv("ARPHYS_FAULT_SEED");
  EXPECT_NEAR(static_cast<double>(first.size()), 1600.0, 60.0);  // 20 % lost; 3 sigma is about 54
  EXPECT_EQ(first, second);
}

TEST(Bus, MalformedLossSettingNamesTheVariable) {
  ::setenv("ARPHYS_FAULT_RECEIVE_LOSS", "lots", 1);
  try {
    Bus bus("memq://");
    ADD_FAILURE() << "accepted a malformed loss";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("ARPHYS_FAULT_RECEIVE_LOSS='lots'"), std::string::npos) << e.what();
  }
  ::unsetenv("ARPHYS_FAULT_RECEIVE_LOSS");
}

}  // namespace
}  // namespace arphys::msg

// The viewer's wire protocol: every message type parses with its defaults and ranges; malformed
// JSON, non-objects, unknown types, unknown or mistyped fields, out-of-range values and oversized
// messages become errors with stable codes; frame headers round-trip and bad ones are refused.
#include "viewer/protocol.h"

#include <gtest/gtest.h>

namespace {

using namespace lorgnette::viewer;

template <class T>
T parse_as(const std::string& text) {
  ParseResult r = parse_client_message(text);
  EXPECT_TRUE(r.message.has_value()) << text << " -> " << r.error.code << ": " << r.error.message;
  if (!r.message) return T{};
  EXPECT_TRUE(std::holds_alternative<T>(*r.message)) << text;
  return std::holds_alternative<T>(*r.message) ? std::get<T>(*r.message) : T{};
}

std::string error_code(const std::string& text) {
  ParseResult r = parse_client_message(text);
  EXPECT_FALSE(r.message.has_value()) << text << " should be refused";
  EXPECT_FALSE(r.error.message.empty()) << text;
  return r.error.code;
}

TEST(ViewerProtocol, CameraWithEveryFieldAndWithDefaults) {
  auto c = parse_as<CameraMsg>(
      R"({"type":"camera","yaw":12.5,"pitch":-4,"distance":1.5,"pan_x":0.1,"pan_y":-0.2,"interacting":true,"seq":77})");
  EXPECT_DOUBLE_EQ(c.yaw_deg, 12.5);
  EXPECT_DOUBLE_EQ(c.pitch_deg, -4);
  EXPECT_DOUBLE_EQ(c.distance, 1.5);
  EXPECT_DOUBLE_EQ(c.pan_x, 0.1);
  EXPECT_DOUBLE_EQ(c.pan_y, -0.2);
  EXPECT_TRUE(c.interacting);
  EXPECT_EQ(c.seq, 77u);
  auto d = parse_as<CameraMsg>(R"({"type":"camera","yaw":0,"pitch":0})");
  EXPECT_DOUBLE_EQ(d.distance, 1.0);
  EXPECT_FALSE(d.interacting);
  EXPECT_EQ(d.seq, 0u);
}

TEST(ViewerProtocol, EveryOtherMessageType) {
  auto s = parse_as<SizeMsg>(R"({"type":"size","width":640,"height":360})");
  EXPECT_EQ(s.width, 640u);
  EXPECT_EQ(s.height, 360u);
  EXPECT_FALSE(parse_as<GlassesMsg>(R"({"type":"glasses","on":false})").on);
  EXPECT_EQ(parse_as<SelectMsg>(R"({"type":"select","index":3})").index, 3u);
  auto n = parse_as<NudgeMsg>(R"({"type":"nudge","up_mm":0.5,"tilt_deg":-1})");
  EXPECT_DOUBLE_EQ(n.up_mm, 0.5);
  EXPECT_DOUBLE_EQ(n.forward_mm, 0.0);
  EXPECT_DOUBLE_EQ(n.tilt_deg, -1.0);
  EXPECT_TRUE(parse_as<NudgeMsg>(R"({"type":"nudge","reset":true})").reset);
  EXPECT_FALSE(parse_as<SaveMsg>(R"({"type":"save"})").overwrite);
  EXPECT_TRUE(parse_as<SaveMsg>(R"({"type":"save","overwrite":true})").overwrite);
  parse_as<SnapshotMsg>(R"({"type":"snapshot"})");
  EXPECT_EQ(parse_as<PingMsg>(R"({"type":"ping","seq":9})").seq, 9u);
  // A whole number written as a float is an integer.
  EXPECT_EQ(parse_as<SelectMsg>(R"({"type":"select","index":2.0})").index, 2u);
}

TEST(ViewerProtocol, MalformedAndUnknownMessagesAreRefusedWithTheirCode) {
  EXPECT_EQ(error_code("{not json"), "malformed");
  EXPECT_EQ(error_code(""), "malformed");
  EXPECT_EQ(error_code(R"({"type":"camera","yaw":1,)"), "malformed");
  EXPECT_EQ(error_code("[1,2,3]"), "not_object");
  EXPECT_EQ(error_code("42"), "not_object");
  EXPECT_EQ(error_code(R"({"yaw":1})"), "invalid");
  EXPECT_EQ(error_code(R"({"type":7})"), "invalid");
  EXPECT_EQ(error_code(R"({"type":"teleport"})"), "unknown_type");
  ParseResult r = parse_client_message(R"({"type":"teleport"})");
  EXPECT_EQ(r.type, "teleport");
  EXPECT_NE(r.error.message.find("camera"), std::string::npos)
      << "lists the known types: " << r.error.message;
}

TEST(ViewerProtocol, FieldsAreCheckedForPresenceTypeRangeAndName) {
  EXPECT_EQ(error_code(R"({"type":"camera","yaw":1})"), "invalid");               // pitch missing
  EXPECT_EQ(error_code(R"({"type":"camera","yaw":"1","pitch":0})"), "invalid");   // string
  EXPECT_EQ(error_code(R"({"type":"camera","yaw":1000,"pitch":0})"), "invalid");  // range
  EXPECT_EQ(error_code(R"({"type":"camera","yaw":0,"pitch":0,"distance":0})"), "invalid");
  EXPECT_EQ(error_code(R"({"type":"camera","yaw":0,"pitch":0,"zoom":2})"), "invalid");  // unknown field
  EXPECT_EQ(error_code(R"({"type":"camera","yaw":0,"pitch":0,"seq":-1})"), "invalid");
  EXPECT_EQ(error_code(R"({"type":"camera","yaw":0,"pitch":0,"interacting":1})"), "invalid");
  EXPECT_EQ(error_code(R"({"type":"size","width":10,"height":480})"), "invalid");
  EXPECT_EQ(error_code(R"({"type":"size","width":99999,"height":480})"), "invalid");
  EXPECT_EQ(error_code(R"({"type":"select","index":-1})"), "invalid");
  EXPECT_EQ(error_code(R"({"type":"select","index":1.5})"), "invalid");
  EXPECT_EQ(error_code(R"({"type":"select","path":"/etc/passwd","index":0})"), "invalid");  // no paths, ever
  EXPECT_EQ(error_code(R"({"type":"nudge"})"), "invalid");                                  // nothing to do
  EXPECT_EQ(error_code(R"({"type":"nudge","up_mm":50})"), "invalid");
  EXPECT_EQ(error_code(R"({"type":"save","overwrite":"yes"})"), "invalid");
  EXPECT_EQ(error_code(R"({"type":"save","path":"/tmp/x.json"})"), "invalid");
  EXPECT_EQ(error_code(R"({"type":"glasses"})"), "invalid");
  ParseResult r = parse_client_message(R"({"type":"camera","yaw":1000,"pitch":0})");
  EXPECT_NE(r.error.message.find("camera.yaw"), std::string::npos) << r.error.message;
}

TEST(ViewerProtocol, OversizedMessagesAreRefusedBeforeParsing) {
  std::string big = R"({"type":"ping","seq":1,"pad":")" + std::string(kMaxMessageBytes, 'x') + "\"}";
  EXPECT_EQ(error_code(big), "too_large");
  // Deep nesting within the size limit is only malformed/invalid, never a crash.
  std::string deep = std::string(2000, '[') + std::string(2000, ']');
  EXPECT_EQ(error_code(deep), "not_object");
}

TEST(ViewerProtocol, ErrorRepliesAreJsonWithCodeAndRequest) {
  auto j = nlohmann::json::parse(error_reply({"invalid", "bad \xff byte"}, "camera"));
  EXPECT_EQ(j["type"], "error");
  EXPECT_EQ(j["code"], "invalid");
  EXPECT_EQ(j["request"], "camera");
}

TEST(ViewerProtocol, FrameHeaderRoundTripsAndBadFramesAreRefused) {
  FrameHeader h;
  h.kind = FrameKind::kFullJpeg;
  h.seq = 0xdeadbeef;
  h.width = 854;
  h.height = 480;
  h.render_us = 123456;
  std::vector<uint8_t> payload = {1, 2, 3, 4, 5};
  std::vector<uint8_t> bytes = encode_frame(h, payload);
  ASSERT_EQ(bytes.size(), FrameHeader::kSize + payload.size());
  FrameHeader back = decode_frame_header(bytes.data(), bytes.size());
  EXPECT_EQ(back.kind, FrameKind::kFullJpeg);
  EXPECT_EQ(back.seq, 0xdeadbeefu);
  EXPECT_EQ(back.width, 854);
  EXPECT_EQ(back.height, 480);
  EXPECT_EQ(back.render_us, 123456u);
  EXPECT_EQ(back.payload_bytes, 5u);
  EXPECT_THROW(decode_frame_header(bytes.data(), 10), std::invalid_argument);
  EXPECT_THROW(decode_frame_header(bytes.data(), bytes.size() - 1), std::invalid_argument);
  bytes[0] = 'X';
  EXPECT_THROW(decode_frame_header(bytes.data(), bytes.size()), std::invalid_argument);
}

}  // namespace

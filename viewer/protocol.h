// The viewer's wire protocol over one WebSocket. Clients send small JSON text messages (camera orbit,
// viewport size, glasses on/off, catalogue pick, nudge, save, snapshot, ping); the server answers with
// JSON text (info, state, fit progress, saved, errors) and binary frames: a fixed 24-byte header
// (FrameHeader) followed by a JPEG (coarse or refined view) or a PNG (snapshot). Parsing is strict:
// every field is checked for type and range, unknown fields and types are refused, and every failure
// becomes a ProtocolError with a stable code and a message that says what was expected, which the
// server sends back instead of acting. Clients never name files: a frame is a catalogue index.
#pragma once
#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace lorgnette::viewer {

// Text messages longer than this get a "too_large" error reply; the WebSocket layer closes the
// connection (code 1009) beyond kHardMessageBytes, so a client can never make the server buffer more.
constexpr size_t kMaxMessageBytes = 4096;
constexpr size_t kHardMessageBytes = 65536;

// Absolute orbit (degrees; distance as a factor of the framing distance; pan in scene units along
// the orbit's right/up axes). The server clamps it to the capture's limits and echoes `seq` in the
// frames that show it. `interacting`: the user is still dragging (refinement waits).
struct CameraMsg {
  double yaw_deg = 0, pitch_deg = 0, distance = 1, pan_x = 0, pan_y = 0;
  bool interacting = false;
  uint32_t seq = 0;
};
struct SizeMsg {
  uint32_t width = 854, height = 480;
};
struct GlassesMsg {
  bool on = true;
};
struct SelectMsg {
  uint32_t index = 0;
};
// Deltas in the frame's canonical axes: up (+y) and forward (+z) in millimetres, tilt about the
// frame's x axis through the bridge in degrees (positive: the lenses' bottoms move towards the face).
// `reset` drops every nudge of the current frame.
struct NudgeMsg {
  double up_mm = 0, forward_mm = 0, tilt_deg = 0;
  bool reset = false;
};
// Writes <frame>.placement.json; an existing file is replaced only with overwrite = true (a backup
// is kept), otherwise the reply is an "exists" error.
struct SaveMsg {
  bool overwrite = false;
};
struct SnapshotMsg {};
struct PingMsg {
  uint32_t seq = 0;
};

using ClientMessage =
    std::variant<CameraMsg, SizeMsg, GlassesMsg, SelectMsg, NudgeMsg, SaveMsg, SnapshotMsg, PingMsg>;

// Stable codes: too_large, binary, malformed (not JSON), not_object, unknown_type, invalid (a field
// missing, of the wrong type, out of range or unknown), and from the server: exists, io, busy.
struct ProtocolError {
  std::string code, message;
};

struct ParseResult {
  std::optional<ClientMessage> message;
  ProtocolError error;  // set when !message
  std::string type;     // the message's "type" when it could be read (for the error reply)
};

// Limits the parser enforces (ranges beyond what any orbit or viewport needs).
struct ProtocolLimits {
  uint32_t min_side = 32, max_width = 3840, max_height = 2160;
  double max_nudge_mm = 10.0, max_nudge_tilt_deg = 10.0;  // per message
};

ParseResult parse_client_message(std::string_view text, const ProtocolLimits& limits = {});

// {"type":"error","code":...,"message":...[,"request":type]} as a string.
std::string error_reply(const ProtocolError& e, const std::string& request_type = "");

// Binary frames. Little-endian 24-byte header: magic "LGNF", version, kind, header size, camera seq,
// width, height, render time (microseconds), payload size; then the payload.
enum class FrameKind : uint8_t { kCoarseJpeg = 1, kFullJpeg = 2, kSnapshotPng = 3 };

struct FrameHeader {
  static constexpr uint8_t kVersion = 1;
  static constexpr uint16_t kSize = 24;
  FrameKind kind = FrameKind::kCoarseJpeg;
  uint32_t seq = 0;
  uint16_t width = 0, height = 0;
  uint32_t render_us = 0;
  uint32_t payload_bytes = 0;
};

std::vector<uint8_t> encode_frame(const FrameHeader& header, const std::vector<uint8_t>& payload);
// Throws std::invalid_argument when the bytes are no frame (bad magic, version, sizes).
FrameHeader decode_frame_header(const uint8_t* data, size_t size);

}  // namespace lorgnette::viewer

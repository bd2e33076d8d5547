// Strict parsing of the viewer's client messages and the binary frame header (protocol.h).
#include "viewer/protocol.h"

#include <fmt/format.h>

#include <cmath>
#include <cstring>
#include <set>
#include <stdexcept>

namespace lorgnette::viewer {
namespace {

using nlohmann::json;

// Thrown inside the parser and turned into a ProtocolError with code "invalid".
struct Invalid : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Reads the fields of one message, remembering which were read so that unknown ones are refused.
class Fields {
 public:
  Fields(const json& j, std::string type) : j_(j), type_(std::move(type)) { seen_.insert("type"); }

  double number(const char* key, double lo, double hi, std::optional<double> fallback = std::nullopt) {
    const json* v = find(key, fallback.has_value());
    if (!v) return *fallback;
    if (!v->is_number())
      throw Invalid(fmt::format("'{}.{}' must be a number, found {}", type_, key, brief(*v)));
    double x = v->get<double>();
    if (!std::isfinite(x) || x < lo || x > hi)
      throw Invalid(fmt::format("'{}.{}' must be within [{}, {}], found {}", type_, key, lo, hi, brief(*v)));
    return x;
  }
  uint32_t integer(const char* key, uint32_t lo, uint32_t hi,
                   std::optional<uint32_t> fallback = std::nullopt) {
    const json* v = find(key, fallback.has_value());
    if (!v) return *fallback;
    if (!v->is_number_integer() &&
        !(v->is_number_float() && std::floor(v->get<double>()) == v->get<double>()))
      throw Invalid(fmt::format("'{}.{}' must be an integer, found {}", type_, key, brief(*v)));
    double x = v->get<double>();
    if (x < lo || x > hi)
      throw Invalid(fmt::format("'{}.{}' must be within [{}, {}], found {}", type_, key, lo, hi, brief(*v)));
    return uint32_t(x);
  }
  bool boolean(const char* key, std::optional<bool> fallback = std::nullopt) {
    const json* v = find(key, fallback.has_value());
    if (!v) return *fallback;
    if (!v->is_boolean())
      throw Invalid(fmt::format("'{}.{}' must be true or false, found {}", type_, key, brief(*v)));
    return v->get<bool>();
  }
  // Refuses fields the message type does not have (typos would otherwise be silently ignored).
  void finish() const {
    for (auto it = j_.begin(); it != j_.end(); ++it)
      if (!seen_.count(it.key()))
        throw Invalid(fmt::format("'{}' has no field '{}'", type_, it.key().substr(0, 64)));
  }

 private:
  const json* find(const char* key, bool optional) {
    seen_.insert(key);
    auto it = j_.find(key);
    if (it == j_.end()) {
      if (optional) return nullptr;
      throw Invalid(fmt::format("'{}' needs the field '{}'", type_, key));
    }
    return &*it;
  }
  static std::string brief(const json& v) {
    std::string s = v.dump();
    return s.size() > 40 ? s.substr(0, 40) + "..." : s;
  }

  const json& j_;
  std::string type_;
  std::set<std::string> seen_;
};

ClientMessage parse_typed(const std::string& type, const json& j, const ProtocolLimits& limits) {
  Fields f(j, type);
  ClientMessage out;
  if (type == "camera") {
    CameraMsg m;
    m.yaw_deg = f.number("yaw", -360, 360);
    m.pitch_deg = f.number("pitch", -90, 90);
    m.distance = f.number("distance", 0.05, 20, 1.0);
    m.pan_x = f.number("pan_x", -100, 100, 0.0);
    m.pan_y = f.number("pan_y", -100, 100, 0.0);
    m.interacting = f.boolean("interacting", false);
    m.seq = f.integer("seq", 0, 0xffffffffu, 0u);
    out = m;
  } else if (type == "size") {
    SizeMsg m;
    m.width = f.integer("width", limits.min_side, limits.max_width);
    m.height = f.integer("height", limits.min_side, limits.max_height);
    out = m;
  } else if (type == "glasses") {
    out = GlassesMsg{f.boolean("on")};
  } else if (type == "select") {
    out = SelectMsg{f.integer("index", 0, 1u << 20)};
  } else if (type == "nudge") {
    NudgeMsg m;
    m.up_mm = f.number("up_mm", -limits.max_nudge_mm, limits.max_nudge_mm, 0.0);
    m.forward_mm = f.number("forward_mm", -limits.max_nudge_mm, limits.max_nudge_mm, 0.0);
    m.tilt_deg = f.number("tilt_deg", -limits.max_nudge_tilt_deg, limits.max_nudge_tilt_deg, 0.0);
    m.reset = f.boolean("reset", false);
    if (!m.reset && m.up_mm == 0 && m.forward_mm == 0 && m.tilt_deg == 0)
      throw Invalid("'nudge' needs a non-zero 'up_mm', 'forward_mm' or 'tilt_deg', or 'reset': true");
    out = m;
  } else if (type == "save") {
    out = SaveMsg{f.boolean("overwrite", false)};
  } else if (type == "snapshot") {
    out = SnapshotMsg{};
  } else if (type == "ping") {
    out = PingMsg{f.integer("seq", 0, 0xffffffffu, 0u)};
  } else {
    throw std::logic_error("unreachable: type checked by the caller");
  }
  f.finish();
  return out;
}

const std::set<std::string>& known_types() {
  static const std::set<std::string> types = {"camera", "size", "glasses",  "select",
                                              "nudge",  "save", "snapshot", "ping"};
  return types;
}

void put_u16(std::vector<uint8_t>& b, size_t at, uint16_t v) {
  b[at] = uint8_t(v), b[at + 1] = uint8_t(v >> 8);
}
void put_u32(std::vector<uint8_t>& b, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + i] = uint8_t(v >> (8 * i));
}
uint16_t get_u16(const uint8_t* p) { return uint16_t(p[0] | (p[1] << 8)); }
uint32_t get_u32(const uint8_t* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

}  // namespace

ParseResult parse_client_message(std::string_view text, const ProtocolLimits& limits) {
  ParseResult r;
  if (text.size() > kMaxMessageBytes) {
    r.error = {"too_large",
               fmt::format("message of {} bytes; the limit is {} bytes", text.size(), kMaxMessageBytes)};
    return r;
  }
  json j = json::parse(text.begin(), text.end(), nullptr, false);
  if (j.is_discarded()) {
    r.error = {"malformed", "the message is not valid JSON"};
    return r;
  }
  if (!j.is_object()) {
    r.error = {"not_object", "a message must be a JSON object with a \"type\" field"};
    return r;
  }
  auto t = j.find("type");
  if (t == j.end() || !t->is_string()) {
    r.error = {"invalid", "the message needs a string field \"type\""};
    return r;
  }
  r.type = t->get<std::string>().substr(0, 32);
  if (!known_types().count(t->get<std::string>())) {
    r.error = {"unknown_type",
               fmt::format("unknown message type '{}'; known: camera, size, glasses, select, nudge, "
                           "save, snapshot, ping",
                           r.type)};
    return r;
  }
  try {
    r.message = parse_typed(r.type, j, limits);
  } catch (const Invalid& e) {
    r.error = {"invalid", e.what()};
  }
  return r;
}

std::string error_reply(const ProtocolError& e, const std::string& request_type) {
  json j = {{"type", "error"}, {"code", e.code}, {"message", e.message}};
  if (!request_type.empty()) j["request"] = request_type;
  return j.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::vector<uint8_t> encode_frame(const FrameHeader& h, const std::vector<uint8_t>& payload) {
  std::vector<uint8_t> b(FrameHeader::kSize + payload.size());
  std::memcpy(b.data(), "LGNF", 4);
  b[4] = FrameHeader::kVersion;
  b[5] = uint8_t(h.kind);
  put_u16(b, 6, FrameHeader::kSize);
  put_u32(b, 8, h.seq);
  put_u16(b, 12, h.width);
  put_u16(b, 14, h.height);
  put_u32(b, 16, h.render_us);
  put_u32(b, 20, uint32_t(payload.size()));
  if (!payload.empty()) std::memcpy(b.data() + FrameHeader::kSize, payload.data(), payload.size());
  return b;
}

FrameHeader decode_frame_header(const uint8_t* data, size_t size) {
  if (size < FrameHeader::kSize)
    throw std::invalid_argument(fmt::format("frame of {} bytes is shorter than its header", size));
  if (std::memcmp(data, "LGNF", 4) != 0) throw std::invalid_argument("frame without the LGNF magic");
  if (data[4] != FrameHeader::kVersion)
    throw std::invalid_argument(
        fmt::format("frame version {}, expected {}", int(data[4]), int(FrameHeader::kVersion)));
  if (data[5] < 1 || data[5] > 3)
    throw std::invalid_argument(fmt::format("unknown frame kind {}", int(data[5])));
  FrameHeader h;
  h.kind = FrameKind(data[5]);
  if (get_u16(data + 6) != FrameHeader::kSize) throw std::invalid_argument("unexpected frame header size");
  h.seq = get_u32(data + 8);
  h.width = get_u16(data + 12);
  h.height = get_u16(data + 14);
  h.render_us = get_u32(data + 16);
  h.payload_bytes = get_u32(data + 20);
  if (size_t(h.payload_bytes) + FrameHeader::kSize != size)
    throw std::invalid_argument(
        fmt::format("frame payload {} bytes, header says {}", size - FrameHeader::kSize, h.payload_bytes));
  return h;
}

}  // namespace lorgnette::viewer

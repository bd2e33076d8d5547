// Structural checks of PLY and GLB files (see file_checks.h). PLY ASCII data is checked one record per
// line, as every writer puts it and as Assimp reads it, so both agree on which number is a list count.
#include "mesh/file_checks.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

namespace lorgnette::mesh {
namespace {

struct Property {
  int size = 0;        // bytes of the scalar, or of each list item
  int count_size = 0;  // bytes of the list count; 0 for a scalar
  bool count_signed = false;
};

struct Element {
  std::string name;
  uint64_t count = 0;
  std::vector<Property> properties;
};

struct PlyType {
  const char* name;
  const char* alias;
  int size;
  bool is_signed, is_integer;
};

// The spec's names and the sized aliases many writers use; nullptr when unknown.
const PlyType* find_type(std::string_view name) {
  static const PlyType kTypes[] = {
      {"char", "int8", 1, true, true},      {"uchar", "uint8", 1, false, true},
      {"short", "int16", 2, true, true},    {"ushort", "uint16", 2, false, true},
      {"int", "int32", 4, true, true},      {"uint", "uint32", 4, false, true},
      {"float", "float32", 4, true, false}, {"double", "float64", 8, true, false}};
  for (const PlyType& t : kTypes)
    if (name == t.name || name == t.alias) return &t;
  return nullptr;
}

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> words;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
  return words;
}

bool parse_count(std::string_view word, uint64_t* n) {
  if (word.empty() || word.size() > 18) return false;  // 18 digits cannot overflow
  *n = 0;
  for (char c : word) {
    if (c < '0' || c > '9') return false;
    *n = *n * 10 + uint64_t(c - '0');
  }
  return true;
}

class Checker {
 public:
  Checker(std::string_view bytes, const std::string& name) : bytes_(bytes), name_(name) {}

  void run() {
    read_header();
    for (const Element& e : elements_)
      if (e.count > 0 && e.properties.empty()) fail(fmt::format("element '{}' has no properties", e.name));
    if (ascii_)
      walk_ascii();
    else
      walk_binary();
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(fmt::format("cannot load mesh '{}': not a valid PLY file: {}", name_, what));
  }

  // The next line without its line end (LF or CRLF), rejecting control characters; false at the end.
  bool next_line(std::string_view* line, const char* where) {
    if (pos_ >= bytes_.size()) return false;
    size_t end = bytes_.find('\n', pos_);
    if (end == std::string_view::npos) end = bytes_.size();
    *line = bytes_.substr(pos_, end - pos_);
    pos_ = end + 1;
    if (!line->empty() && line->back() == '\r') line->remove_suffix(1);
    for (char c : *line)
      if (static_cast<unsigned char>(c) < 0x20 && c != '\t')
        fail(fmt::format("a control character (code {}) in {} line {}", int(c), where, line_ + 1));
    ++line_;
    return true;
  }

  void read_property(const std::vector<std::string_view>& w) {
    if (elements_.empty()) fail(fmt::format("header line {}: a property before any element", line_));
    Property p;
    const PlyType* item = nullptr;
    if (w.size() == 5 && w[1] == "list") {
      const PlyType* count = find_type(w[2]);
      if (!count || !count->is_integer)
        fail(fmt::format("header line {}: list count type '{}' is not an integer type", line_, w[2]));
      p.count_size = count->size;
      p.count_signed = count->is_signed;
      item = find_type(w[3]);
    } else if (w.size() == 3) {
      item = find_type(w[1]);
    } else {
      fail(fmt::format("header line {}: a property needs a type and a name", line_));
    }
    if (!item) fail(fmt::format("header line {}: unknown property type", line_));
    p.size = item->size;
    elements_.back().properties.push_back(p);
  }

  void read_header() {
    std::string_view line;
    bool format = false;
    if (!next_line(&line, "header") || split(line) != std::vector<std::string_view>{"ply"})
      fail("the first line is not 'ply'");
    while (true) {
      if (!next_line(&line, "header")) fail("the header has no end_header line (truncated?)");
      std::vector<std::string_view> w = split(line);
      if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
      if (w[0] == "end_header") break;
      if (w[0] == "format" && w.size() == 3 && !format) {
        format = true;
        ascii_ = w[1] == "ascii";
        big_endian_ = w[1] == "binary_big_endian";
        if (!ascii_ && !big_endian_ && w[1] != "binary_little_endian")
          fail(fmt::format("header line {}: unknown format '{}'", line_, w[1]));
      } else if (w[0] == "element" && w.size() == 3) {
        Element e{std::string(w[1]), 0, {}};
        if (!parse_count(w[2], &e.count)) fail(fmt::format("header line {}: bad element count", line_));
        elements_.push_back(e);
      } else if (w[0] == "property") {
        read_property(w);
      } else {
        fail(fmt::format("header line {}: unexpected '{}'", line_, line));
      }
    }
    if (!format) fail("the header has no format line");
  }

  // One record per line, exactly the numbers the header describes; list counts are checked
  // against the numbers on the line before anyone allocates for them.
  void walk_ascii() {
    for (const Element& e : elements_)
      for (uint64_t r = 0; r < e.count; ++r) {
        std::string_view line;
        if (!next_line(&line, "data"))
          fail(fmt::format("the data ends at record {} of {} of element '{}'", r, e.count, e.name));
        std::vector<std::string_view> w = split(line);
        size_t used = 0;
        for (const Property& p : e.properties) {
          uint64_t items = 1;
          if (p.count_size) {
            if (used >= w.size() || !parse_count(w[used], &items))
              fail(fmt::format("data line {} ('{}' {}): a list count is missing or not a whole number", line_,
                               e.name, r));
            ++used;
          }
          if (items > w.size() - std::min(used, w.size()))
            fail(fmt::format("data line {} ('{}' {}): fewer numbers than the header describes", line_, e.name,
                             r));
          used += items;
        }
        if (used != w.size())
          fail(fmt::format("data line {} ('{}' {}): {} numbers, the header describes {}", line_, e.name, r,
                           w.size(), used));
      }
  }

  uint64_t read_count(const Property& p) {
    uint64_t v = 0;
    for (int i = 0; i < p.count_size; ++i) {
      int byte = big_endian_ ? i : p.count_size - 1 - i;
      v = (v << 8) | static_cast<unsigned char>(bytes_[pos_ + byte]);
    }
    pos_ += p.count_size;
    if (p.count_signed && (v >> (8 * p.count_size - 1)) != 0) fail("a negative list count");
    return v;
  }

  // Every record's bytes must be there, lists included (each record takes at least one byte).
  void walk_binary() {
    for (const Element& e : elements_)
      for (uint64_t r = 0; r < e.count; ++r)
        for (const Property& p : e.properties) {
          uint64_t left = bytes_.size() - std::min(pos_, bytes_.size()), items = 1;
          if (p.count_size) {
            if (left < uint64_t(p.count_size))
              fail(fmt::format("the data ends at record {} of {} of element '{}'", r, e.count, e.name));
            items = read_count(p);
            left -= p.count_size;
          }
          if (items > left / p.size)
            fail(fmt::format("the data ends at record {} of {} of element '{}'", r, e.count, e.name));
          pos_ += items * p.size;
        }
  }

  std::string_view bytes_;
  const std::string& name_;
  size_t pos_ = 0;
  int line_ = 0;
  bool ascii_ = false, big_endian_ = false;
  std::vector<Element> elements_;
};

}  // namespace

void check_ply(std::string_view bytes, const std::string& name) { Checker(bytes, name).run(); }

namespace {

// The JSON of a GLB (its first chunk) after checking the container; fail() throws.
std::string_view glb_json(std::string_view bytes, const std::function<void(const std::string&)>& fail) {
  auto u32 = [&](size_t at) {  // little-endian, as GLB stores it
    uint32_t v = 0;
    for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(bytes[at + i]);
    return v;
  };
  if (bytes.size() < 12) fail(fmt::format("the 12-byte header is cut off at {} bytes", bytes.size()));
  const uint32_t version = u32(4), length = u32(8);
  if (length > bytes.size() || length < (version == 1 ? 20u : 12u))
    fail(fmt::format("the header says {} bytes, the file has {}", length, bytes.size()));
  if (version == 1) {  // glTF 1.0 binary: one JSON content block after a 20-byte header
    if (u32(12) > length - 20) fail(fmt::format("the JSON content of {} bytes runs past the end", u32(12)));
    return bytes.substr(20, u32(12));
  }
  if (version != 2) fail(fmt::format("version {} (this reads 1 and 2)", version));
  size_t at = 12;
  for (int chunk = 0; at < length; ++chunk) {  // every chunk advances by at least its 8-byte header
    if (length - at < 8) fail(fmt::format("chunk {} is cut off in its header", chunk));
    const uint32_t size = u32(at), type = u32(at + 4);
    if (size > length - at - 8) fail(fmt::format("chunk {} of {} bytes runs past the end", chunk, size));
    if (chunk == 0 && type != 0x4E4F534Au) fail("the first chunk is not JSON");
    at += 8 + size;
  }
  if (at == 12) fail("there is no JSON chunk");
  return bytes.substr(20, u32(12));
}

// Whether `"mode": 2` or `"mode": 6` occurs anywhere in the text.
bool raw_mode_is_loop_or_fan(std::string_view text) {
  for (size_t at = text.find("\"mode\""); at != std::string_view::npos; at = text.find("\"mode\"", at + 1)) {
    size_t i = at + 6;
    auto skip_space = [&] {
      while (i < text.size() && (text[i] == ' ' || text[i] == '\t' || text[i] == '\n' || text[i] == '\r'))
        ++i;
    };
    skip_space();
    if (i >= text.size() || text[i] != ':') continue;
    ++i;
    skip_space();
    if (i < text.size() && (text[i] == '2' || text[i] == '6') &&
        (i + 1 == text.size() || !std::isdigit(static_cast<unsigned char>(text[i + 1]))))
      return true;
  }
  return false;
}

}  // namespace

void check_gltf(std::string_view bytes, const std::string& name) {
  auto fail = [&](const std::string& what) {
    throw std::runtime_error(
        fmt::format("cannot load mesh '{}': not a valid or supported glTF file: {}", name, what));
  };
  std::string_view text = bytes.substr(0, 4) == "glTF" ? glb_json(bytes, fail) : bytes;
  nlohmann::json doc = nlohmann::json::parse(text.begin(), text.end(), nullptr, false);
  if (doc.is_discarded()) {
    // Assimp's JSON reader is more lenient (it takes invalid UTF-8, for one), so the raw text is
    // searched instead (fuzz/regressions/glasses/gltf-bad-utf8-line-loop-segv).
    if (raw_mode_is_loop_or_fan(text))
      fail("a primitive in LINE_LOOP or TRIANGLE_FAN mode (re-export it as triangles)");
    return;
  }
  if (!doc.is_object() || !doc.contains("meshes") || !doc["meshes"].is_array()) return;
  for (const auto& mesh : doc["meshes"]) {
    if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
    for (const auto& prim : mesh["primitives"]) {
      if (!prim.is_object() || !prim.contains("indices") || !prim.contains("mode")) continue;
      const auto& mode = prim["mode"];
      if (mode.is_number_integer() && (mode.get<int64_t>() == 2 || mode.get<int64_t>() == 6))
        fail(fmt::format("a primitive in {} mode with indices (re-export it as triangles)",
                         mode.get<int64_t>() == 2 ? "LINE_LOOP" : "TRIANGLE_FAN"));
    }
  }
}

}  // namespace lorgnette::mesh

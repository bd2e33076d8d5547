// placement.json read/write (see placement_json.h).
#include "fit/placement_json.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <climits>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "host/util/image_io.h"

namespace lorgnette::fit {
namespace fs = std::filesystem;

Eigen::Matrix4d nudge_matrix(const PlacementNudge& n) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  // About +x (the wearer's left) a positive tilt turns canonical +z (forward) down; the bridge
  // (canonical origin) stays on the rotation axis.
  m.block<3, 3>(0, 0) =
      Eigen::AngleAxisd(n.tilt_deg * M_PI / 180.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  m(1, 3) = n.up_mm;
  m(2, 3) = n.forward_mm;
  return m;
}

PlacementNudge combined_nudge(const PlacementNudge& a, const PlacementNudge& b) {
  const double t = a.tilt_deg * M_PI / 180.0, c = std::cos(t), s = std::sin(t);
  return {a.up_mm + c * b.up_mm - s * b.forward_mm, a.forward_mm + s * b.up_mm + c * b.forward_mm,
          a.tilt_deg + b.tilt_deg};
}

// placement.json's optional "temples" object (ARCHITECTURE.md):
// {"hinge_l": [x,y,z], "hinge_r": [x,y,z], "spread_l_deg": a, "spread_r_deg": b, "ramp_mm": r}
// plus whatever else the writer adds (the fit adds penetration figures). Absent = no spread.
nlohmann::json temple_bend_to_json(const mesh::TempleBend& b) {
  auto v = [](const Eigen::Vector3d& p) { return nlohmann::json::array({p.x(), p.y(), p.z()}); };
  return {{"hinge_l", v(b.left.hinge)},
          {"hinge_r", v(b.right.hinge)},
          {"spread_l_deg", b.left.spread_deg},
          {"spread_r_deg", b.right.spread_deg},
          {"ramp_mm", b.ramp_mm}};
}

// Reads the "temples" object of a placement (the whole placement.json object); no "temples" = none.
mesh::TempleBend temple_bend_from_placement(const nlohmann::json& placement) {
  mesh::TempleBend b;
  if (!placement.is_object() || !placement.contains("temples") || placement["temples"].is_null()) return b;
  const nlohmann::json& t = placement["temples"];
  auto vec = [&](const char* key) {
    if (!t.contains(key) || !t[key].is_array() || t[key].size() != 3)
      throw std::runtime_error(std::string("placement.json: temples.") + key +
                               " must be an array of 3 numbers");
    return Eigen::Vector3d(t[key][0].get<double>(), t[key][1].get<double>(), t[key][2].get<double>());
  };
  auto num = [&](const char* key, double fallback) {
    if (!t.contains(key)) return fallback;
    if (!t[key].is_number())
      throw std::runtime_error(std::string("placement.json: temples.") + key + " must be a number");
    return t[key].get<double>();
  };
  b.left.hinge = vec("hinge_l");
  b.right.hinge = vec("hinge_r");
  b.left.spread_deg = num("spread_l_deg", 0.0);
  b.right.spread_deg = num("spread_r_deg", 0.0);
  b.ramp_mm = num("ramp_mm", b.ramp_mm);
  if (!(b.ramp_mm > 0.0) || std::abs(b.left.spread_deg) > 90.0 || std::abs(b.right.spread_deg) > 90.0)
    throw std::runtime_error("placement.json: temples need ramp_mm > 0 and spreads within +-90 degrees");
  return b;
}

std::string file_hash(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(fmt::format("cannot read '{}' to hash it", path));
  uint64_t h = 14695981039346656037ull;  // FNV-1a 64 offset basis
  char buf[65536];
  while (in) {
    in.read(buf, sizeof(buf));
    for (std::streamsize i = 0; i < in.gcount(); ++i) h = (h ^ uint8_t(buf[i])) * 1099511628211ull;
  }
  return fmt::format("fnv1a64:{:016x}", h);
}

namespace {

// A whole number that fits an int. nlohmann's get<int>() casts any number, which is undefined
// behaviour for a double beyond int's range (a corrupt or hand-edited file).
int whole_number(const nlohmann::json& v, const std::string& name) {
  double d = v.is_number() ? v.get<double>() : NAN;
  if (!(d >= INT_MIN && d <= INT_MAX) || d != std::floor(d))
    throw std::runtime_error(
        fmt::format("placement.json: field '{}' must be a whole number, found {}", name, v.dump()));
  return static_cast<int>(d);
}

nlohmann::json temples_json(const TempleFitResult& t) {
  nlohmann::json j = temple_bend_to_json(t.bend);
  for (const auto* side : {&t.left, &t.right})
    j[side == &t.left ? "left" : "right"] = {{"penetration_before_mm", side->penetration_before_mm},
                                             {"penetration_mm", side->penetration_mm},
                                             {"points", side->points},
                                             {"clear", side->clear}};
  return j;
}

TempleFitResult temples_from_json(const nlohmann::json& placement) {
  TempleFitResult t;
  t.fitted = true;
  t.bend = temple_bend_from_placement(placement);
  const nlohmann::json& j = placement["temples"];
  for (auto* side : {&t.left, &t.right}) {
    side->spread_deg = side == &t.left ? t.bend.left.spread_deg : t.bend.right.spread_deg;
    const char* key = side == &t.left ? "left" : "right";
    if (!j.contains(key)) continue;
    const nlohmann::json& s = j[key];
    side->penetration_before_mm = s.value("penetration_before_mm", 0.0);
    side->penetration_mm = s.value("penetration_mm", 0.0);
    if (s.contains("points"))
      side->points = whole_number(s["points"], std::string("temples.") + key + ".points");
    side->clear = s.value("clear", true);
  }
  return t;
}

nlohmann::json advice_json(const FitAdvice& a) {
  nlohmann::json rules = nlohmann::json::array();
  for (const AdviceRule& r : a.rules)
    rules.push_back({{"name", r.name},
                     {"verdict", r.verdict},
                     {"frame_mm", r.frame_mm},
                     {"head_mm", r.head_mm},
                     {"difference_mm", r.difference_mm},
                     {"low_mm", r.low_mm},
                     {"high_mm", r.high_mm},
                     {"off_by_mm", r.off_by_mm},
                     {"text", r.text}});
  return {{"approximate", a.approximate}, {"rules", rules}};
}

}  // namespace

nlohmann::json to_json(const PlacementFile& p) {
  using nlohmann::json;
  json t = json::array();
  for (int i = 0; i < 4; ++i)
    t.push_back({p.transform(i, 0), p.transform(i, 1), p.transform(i, 2), p.transform(i, 3)});
  json lms = json::object(), seconds = json::object();
  for (const auto& [name, l] : p.landmarks)
    lms[name] = {{"position", {l.position.x(), l.position.y(), l.position.z()}},
                 {"sigma_mm", l.sigma_mm},
                 {"views", l.views}};
  double total = 0;
  for (const auto& [name, s] : p.seconds) seconds[name] = s, total += s;
  seconds["total"] = total;
  json out = {{"version", p.version},
              {"glasses", {{"path", p.glasses_path}, {"hash", p.glasses_hash}}},
              {"transform", t},
              {"scale_policy", p.scale_policy},
              {"scale", p.scale},
              {"mm_per_unit", p.mm_per_unit},
              {"pd_mm", p.pd_mm},
              {"landmarks", lms},
              {"residuals_px", p.residuals_px},
              {"views_used", p.views_used},
              {"views_total", p.views_total},
              {"penetration_mm", p.penetration_mm},
              {"contact_shift_mm", p.contact_shift_mm},
              {"contact_rise_mm", p.contact_rise_mm},
              {"front_penetration_mm", p.front_penetration_mm},
              {"tip_penetration_mm", p.tip_penetration_mm},
              {"seconds", seconds},
              {"warnings", p.warnings},
              {"ok", p.ok}};
  if (p.has_temples) out["temples"] = temples_json(p.temples);
  if (p.has_nudge)
    out["nudge"] = {
        {"up_mm", p.nudge.up_mm}, {"forward_mm", p.nudge.forward_mm}, {"tilt_deg", p.nudge.tilt_deg}};
  if (!p.checks.is_null()) out["checks"] = p.checks;
  if (!p.scale_source.empty()) out["scale_source"] = p.scale_source;
  out["mm_per_unit_uncertainty"] = p.mm_per_unit_uncertainty;
  out["pd_uncertainty_mm"] = p.pd_uncertainty_mm;
  if (p.has_advice) out["advice"] = advice_json(p.advice);
  return out;
}

namespace {

template <typename T>
T field(const nlohmann::json& j, const char* name) {
  if (!j.contains(name)) throw std::runtime_error(fmt::format("placement.json: missing field '{}'", name));
  try {
    return j.at(name).get<T>();
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(
        fmt::format("placement.json: field '{}' has the wrong type ({})", name, e.what()));
  }
}

// An optional field: `fallback` when absent, else checked like field().
template <typename T>
T optional_field(const nlohmann::json& j, const char* name, T fallback) {
  return j.contains(name) ? field<T>(j, name) : fallback;
}

template <>
int field<int>(const nlohmann::json& j, const char* name) {
  if (!j.contains(name)) throw std::runtime_error(fmt::format("placement.json: missing field '{}'", name));
  return whole_number(j.at(name), name);
}

// A number that is finite (JSON cannot hold NaN, but 1e999 reads as infinity).
template <>
double field<double>(const nlohmann::json& j, const char* name) {
  if (!j.contains(name)) throw std::runtime_error(fmt::format("placement.json: missing field '{}'", name));
  const nlohmann::json& v = j.at(name);
  if (!v.is_number() || !std::isfinite(v.get<double>()))
    throw std::runtime_error(
        fmt::format("placement.json: field '{}' must be a finite number, found {}", name, v.dump()));
  return v.get<double>();
}

Transform transform_from_json(const nlohmann::json& j) {
  auto t = field<std::vector<std::vector<double>>>(j, "transform");
  if (t.size() != 4) throw std::runtime_error("placement.json: 'transform' must be 4 rows of 4 numbers");
  Transform m;
  for (int i = 0; i < 4; ++i) {
    if (t[i].size() != 4) throw std::runtime_error("placement.json: 'transform' must be 4 rows of 4 numbers");
    for (int k = 0; k < 4; ++k) m(i, k) = t[i][k];
  }
  try {
    check_transform(m, "placement.json: 'transform'");
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(e.what());
  }
  return m;
}

// "nudge", or the "viewer": {"nudge"} object viewers wrote before the field existed.
void nudge_from_json(const nlohmann::json& j, PlacementFile& p) {
  const nlohmann::json* n = nullptr;
  if (j.contains("nudge") && !j["nudge"].is_null())
    n = &j["nudge"];
  else if (j.contains("viewer") && j["viewer"].is_object() && j["viewer"].contains("nudge"))
    n = &j["viewer"]["nudge"];
  if (!n) return;
  if (!n->is_object()) throw std::runtime_error("placement.json: 'nudge' must be an object");
  p.has_nudge = true;
  p.nudge.up_mm = optional_field<double>(*n, "up_mm", 0.0);
  p.nudge.forward_mm = optional_field<double>(*n, "forward_mm", 0.0);
  p.nudge.tilt_deg = optional_field<double>(*n, "tilt_deg", 0.0);
}

// A rule of "advice": name and verdict strings, its numbers finite (absent: 0).
AdviceRule advice_rule_from_json(const nlohmann::json& r) {
  if (!r.is_object()) throw std::runtime_error("placement.json: each of 'advice.rules' must be an object");
  AdviceRule a;
  a.name = field<std::string>(r, "name");
  a.verdict = field<std::string>(r, "verdict");
  a.text = optional_field<std::string>(r, "text", "");
  a.frame_mm = optional_field<double>(r, "frame_mm", 0.0);
  a.head_mm = optional_field<double>(r, "head_mm", 0.0);
  a.difference_mm = optional_field<double>(r, "difference_mm", 0.0);
  a.low_mm = optional_field<double>(r, "low_mm", 0.0);
  a.high_mm = optional_field<double>(r, "high_mm", 0.0);
  a.off_by_mm = optional_field<double>(r, "off_by_mm", 0.0);
  return a;
}

// "scale_source", the uncertainties and "advice" (all optional: files before them read as unknown).
void scale_and_advice_from_json(const nlohmann::json& j, PlacementFile& p) {
  p.scale_source = optional_field<std::string>(j, "scale_source", "");
  if (!p.scale_source.empty() && p.scale_source != "card" && p.scale_source != "iris" &&
      p.scale_source != "mean-face")
    throw std::runtime_error(fmt::format(
        "placement.json: field 'scale_source' must be card, iris or mean-face, found '{}'", p.scale_source));
  p.mm_per_unit_uncertainty = optional_field<double>(j, "mm_per_unit_uncertainty", 0.0);
  p.pd_uncertainty_mm = optional_field<double>(j, "pd_uncertainty_mm", 0.0);
  if (p.mm_per_unit_uncertainty < 0.0 || p.pd_uncertainty_mm < 0.0)
    throw std::runtime_error("placement.json: the uncertainties must not be negative");
  p.has_advice = j.contains("advice") && !j["advice"].is_null();
  if (!p.has_advice) return;
  const nlohmann::json& a = j["advice"];
  if (!a.is_object()) throw std::runtime_error("placement.json: field 'advice' must be an object");
  p.advice.approximate = optional_field<bool>(a, "approximate", false);
  for (const nlohmann::json& r : optional_field<nlohmann::json>(a, "rules", nlohmann::json::array()))
    p.advice.rules.push_back(advice_rule_from_json(r));
}

}  // namespace

PlacementFile placement_from_json(const nlohmann::json& j) {
  if (!j.is_object()) throw std::runtime_error("placement.json: expected a JSON object");
  PlacementFile p;
  p.version = field<int>(j, "version");
  if (p.version > PlacementFile::kVersion || p.version < 1)
    throw std::runtime_error(
        fmt::format("placement.json version {} is not supported (this build reads up to {}): "
                    "re-run `lorgnette fit` or update lorgnette",
                    p.version, PlacementFile::kVersion));
  // Only the version and the transform are required: a hand-written placement (a transform, maybe
  // the glasses and the temples) is as valid as one `lorgnette fit` wrote with all its numbers.
  p.transform = transform_from_json(j);
  auto g = optional_field<nlohmann::json>(j, "glasses", nlohmann::json::object());
  p.glasses_path = optional_field<std::string>(g, "path", "");
  p.glasses_hash = optional_field<std::string>(g, "hash", "");
  p.scale_policy = optional_field<std::string>(j, "scale_policy", p.scale_policy);
  p.scale = optional_field<double>(j, "scale", p.scale);
  p.mm_per_unit = optional_field<double>(j, "mm_per_unit", 0.0);
  p.pd_mm = optional_field<double>(j, "pd_mm", 0.0);
  const nlohmann::json lms = optional_field<nlohmann::json>(j, "landmarks", nlohmann::json::object());
  for (const auto& [name, l] : lms.items()) {
    auto pos = field<std::vector<double>>(l, "position");
    if (pos.size() != 3)
      throw std::runtime_error(fmt::format("placement.json: landmark '{}' needs 3 coordinates", name));
    p.landmarks[name] = {Eigen::Vector3d(pos[0], pos[1], pos[2]), field<double>(l, "sigma_mm"),
                         field<int>(l, "views")};
  }
  p.residuals_px = optional_field<std::map<std::string, double>>(j, "residuals_px", {});
  p.views_used = j.contains("views_used") ? whole_number(j["views_used"], "views_used") : 0;
  p.views_total = j.contains("views_total") ? whole_number(j["views_total"], "views_total") : 0;
  p.penetration_mm = optional_field<double>(j, "penetration_mm", 0.0);
  p.contact_shift_mm = optional_field<double>(j, "contact_shift_mm", 0.0);
  p.contact_rise_mm = optional_field<double>(j, "contact_rise_mm", 0.0);
  p.front_penetration_mm = optional_field<double>(j, "front_penetration_mm", 0.0);
  p.tip_penetration_mm = optional_field<double>(j, "tip_penetration_mm", 0.0);
  const nlohmann::json secs = optional_field<nlohmann::json>(j, "seconds", nlohmann::json::object());
  for (const auto& [name, s] : secs.items()) {
    if (name == "total") continue;
    if (!s.is_number())
      throw std::runtime_error(fmt::format("placement.json: seconds '{}' must be a number", name));
    p.seconds.emplace_back(name, s.get<double>());
  }
  p.warnings = optional_field<std::vector<std::string>>(j, "warnings", {});
  // A fit records its verdict; a hand-written transform is taken as given.
  p.ok = optional_field<bool>(j, "ok", true);
  p.checks = optional_field<nlohmann::json>(j, "checks", nullptr);
  if (!p.checks.is_null() && !p.checks.is_object())
    throw std::runtime_error("placement.json: field 'checks' must be an object");
  p.has_temples = j.contains("temples") && !j["temples"].is_null();
  if (p.has_temples) {
    try {
      p.temples = temples_from_json(j);
    } catch (const nlohmann::json::exception& e) {
      throw std::runtime_error(fmt::format("placement.json: field 'temples' is malformed ({})", e.what()));
    }
  }
  nudge_from_json(j, p);
  scale_and_advice_from_json(j, p);
  return p;
}

void write_placement(const std::string& path, const PlacementFile& p) {
  try {
    check_transform(p.transform, "placement '" + path + "': transform");
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(std::string(e.what()) + ": nothing was written");
  }
  PlacementFile stored = p;
  if (!p.glasses_path.empty() && fs::path(p.glasses_path).is_relative()) {
    // Relative to the file's folder (fs::relative resolves symbolic links on both sides).
    std::error_code ec;
    fs::path rel = fs::relative(fs::absolute(p.glasses_path), fs::absolute(path).parent_path(), ec);
    stored.glasses_path =
        ec || rel.empty() ? fs::absolute(p.glasses_path).lexically_normal().string() : rel.string();
  }
  write_text_file_atomic(path, to_json(stored).dump(2) + "\n");
}

PlacementFile read_placement(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(fmt::format("cannot open placement file '{}'", path));
  nlohmann::json j;
  try {
    in >> j;
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(fmt::format("'{}' is not valid JSON: {}", path, e.what()));
  }
  PlacementFile p;
  try {
    p = placement_from_json(j);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(fmt::format("placement '{}': {}", path, e.what()));
  }
  if (!p.glasses_path.empty() && fs::path(p.glasses_path).is_relative())
    p.glasses_path = (fs::path(path).parent_path() / p.glasses_path).lexically_normal().string();
  return p;
}

std::string glasses_mismatch(const PlacementFile& p, const std::string& glasses_path) {
  if (p.glasses_hash.empty()) return "";
  std::string hash;
  try {
    hash = file_hash(glasses_path);
  } catch (const std::runtime_error&) {
    return "";
  }
  if (hash == p.glasses_hash) return "";
  return fmt::format(
      "the placement was fitted for another glasses file ('{}', {}) than '{}' ({}): the frame sits where "
      "the other one was fitted; run `lorgnette fit` for this frame",
      p.glasses_path, p.glasses_hash, glasses_path, hash);
}

}  // namespace lorgnette::fit

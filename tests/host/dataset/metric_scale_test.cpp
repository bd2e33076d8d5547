// scale.json (host/dataset/metric_scale.h): written and read back exactly, absent = unknown, and a
// malformed file refused with what is wrong and that deleting it makes the scale unknown.
#include "host/dataset/metric_scale.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace lorgnette::dataset {
namespace {

namespace fs = std::filesystem;

std::string fresh_dir(const char* name) {
  fs::path d = fs::temp_directory_path() /
               (std::string("lgn_metric_scale_") + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d.string();
}

std::string read_error(const std::string& dir) {
  try {
    read_scale_json(dir);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

#define EXPECT_HAS(text, part) EXPECT_NE((text).find(part), std::string::npos) << (text)

TEST(MetricScaleFile, RoundTripsAndAbsentIsUnknown) {
  const std::string dir = fresh_dir("roundtrip");
  EXPECT_FALSE(read_scale_json(dir).has_value());
  write_scale_json(dir, {"card", 213.5, 0.75, 11});
  auto back = read_scale_json(dir);
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->source, "card");
  EXPECT_EQ(back->mm_per_unit, 213.5);
  EXPECT_EQ(back->uncertainty, 0.75);
  EXPECT_EQ(back->frames, 11);
  EXPECT_THROW(write_scale_json(dir, {"card", -1.0, 0.0, 3}), std::runtime_error);
  EXPECT_THROW(write_scale_json(dir, {"", 200.0, 0.0, 3}), std::runtime_error);
  fs::remove_all(dir);
}

TEST(MetricScaleFile, MalformedFilesAreRefusedWithWhatToDo) {
  const std::string dir = fresh_dir("malformed");
  auto write = [&](const std::string& text) { std::ofstream(fs::path(dir) / kScaleFile) << text; };
  write("not json");
  EXPECT_HAS(read_error(dir), "is not a JSON object");
  EXPECT_HAS(read_error(dir), "delete it");
  write(R"({"source": "card"})");
  EXPECT_HAS(read_error(dir), "lacks a field");
  write(R"({"source": "card", "mm_per_unit": 0})");
  EXPECT_HAS(read_error(dir), "mm_per_unit must be a positive number");
  write(R"({"source": "card", "mm_per_unit": 200, "mm_per_unit_uncertainty": -2})");
  EXPECT_HAS(read_error(dir), "mm_per_unit_uncertainty must be a number >= 0");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace lorgnette::dataset

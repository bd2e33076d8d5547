// The demo's report page, and its refusals: bad output directories and interruption leave nothing
// passing as complete. The whole quick demo runs once, packaged: standalone_packaged_demo.
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "demo/pipeline.h"
#include "demo/report.h"
#include "host/util/interrupt.h"
#include "host/util/output_folder.h"

using namespace lorgnette;
namespace fs = std::filesystem;

namespace {
std::string tmp(const std::string& name) {
  std::string p = std::string(LORGNETTE_TEST_TMP) + "/" + name;
  fs::remove_all(p);
  return p;
}
nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}
}  // namespace

// The report's size-and-fit section from a placement's fields alone: the scale's source with its
// +-, whether the size is real, and one row per advice rule.
TEST(DemoReport, SizeAndFitSection) {
  demo::DemoReport r;
  r.fit = {
      {"scale_source", "iris"},
      {"scale_policy", "true-size"},
      {"mm_per_unit", 201.5},
      {"mm_per_unit_uncertainty", 8.6},
      {"pd_mm", 63.3},
      {"pd_uncertainty_mm", 2.8},
      {"advice",
       {{"approximate", false},
        {"rules",
         {{{"name", "frame_width"}, {"verdict", "too narrow"}, {"text", "frame width 127.9 mm <x>"}}}}}}};
  std::string page = demo::render_report_html(r);
  EXPECT_NE(page.find("Scale from <b>iris</b>: 201.5 &plusmn; 8.6 mm per unit; PD 63.3 &plusmn; 2.8 mm"),
            std::string::npos);
  EXPECT_NE(page.find("shown at its real size"), std::string::npos);
  EXPECT_NE(page.find("<td>too narrow</td><td>frame width 127.9 mm &lt;x&gt;</td>"), std::string::npos);
  r.fit["scale_policy"] = "stretch";
  EXPECT_NE(demo::render_report_html(r).find("not its real size"), std::string::npos);
  r.fit = nlohmann::json::object();  // a fit that failed: no section
  EXPECT_EQ(demo::render_report_html(r).find("Size and fit"), std::string::npos);
}

// The stages' wall and CPU seconds with their totals, and the machine, in report.json and the page.
TEST(DemoReport, StageWallAndCpuSecondsWithTheirTotals) {
  demo::DemoReport r;
  r.machine = "Test CPU, 2 CPUs, 23.4 GiB, load 0.21";
  r.stages = {{"train", 10.0, 18.5}, {"render", 2.0, 3.3}};
  const nlohmann::json j = r.to_json();
  EXPECT_EQ(j["machine"], r.machine);
  EXPECT_DOUBLE_EQ(j["seconds"]["train"].get<double>(), 10.0);
  EXPECT_DOUBLE_EQ(j["seconds"]["total"].get<double>(), 12.0);
  EXPECT_DOUBLE_EQ(j["cpu_seconds"]["train"].get<double>(), 18.5);
  EXPECT_DOUBLE_EQ(j["cpu_seconds"]["render"].get<double>(), 3.3);
  EXPECT_NEAR(j["cpu_seconds"]["total"].get<double>(), 21.8, 1e-12);
  const std::string page = demo::render_report_html(r);
  EXPECT_NE(page.find("<tr><td>train</td><td>10.0 s</td><td>18.5 s</td></tr>"), std::string::npos);
  EXPECT_NE(page.find("<tr><th>total</th><th>12.0 s</th><th>21.8 s</th></tr>"), std::string::npos);
  EXPECT_NE(page.find("Machine: Test CPU, 2 CPUs, 23.4 GiB, load 0.21"), std::string::npos);
}

TEST(Demo, RefusesANonEmptyOutputDirectoryAndChangesNothing) {
  std::string dir = tmp("demo-occupied");
  fs::create_directories(dir);
  { std::ofstream(dir + "/mine.txt") << "user data"; }
  demo::DemoOptions o;
  o.quick = true;
  o.out_dir = dir;
  try {
    demo::run_demo(o, {});
    FAIL() << "expected a refusal";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("--force"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::exists(dir + "/mine.txt"));
  EXPECT_FALSE(fs::exists(dir + "/report.json"));
  // --force replaces only an earlier demo output, never other files.
  o.force = true;
  EXPECT_THROW(demo::run_demo(o, {}), std::runtime_error);
  EXPECT_TRUE(fs::exists(dir + "/mine.txt"));
}

namespace {
// An earlier demo output (its marker and a report) in a fresh folder.
std::string earlier_demo_output(const std::string& name) {
  std::string dir = tmp(name);
  fs::create_directories(dir);
  mark_output(dir, {"demo", "demo output", ""});
  std::ofstream(dir + "/report.json") << "{\"ok\": true, \"earlier\": true}";
  std::ofstream(dir + "/frame.glb") << "the earlier run's frame";
  return dir;
}
std::vector<std::string> siblings(const std::string& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(fs::path(dir).parent_path()))
    if (e.path().filename().string().find(fs::path(dir).filename().string() + ".") != std::string::npos)
      out.push_back(e.path().filename().string());
  return out;
}
}  // namespace

// --force builds beside the earlier output: an interrupted run leaves it whole (and no staging
// folder behind).
TEST(Demo, InterruptedForceRunLeavesTheEarlierOutputWhole) {
  std::string dir = earlier_demo_output("demo-earlier");
  install_interrupt_handler();
  std::raise(SIGINT);
  demo::DemoOptions o;
  o.quick = true;
  o.force = true;
  o.out_dir = dir;
  try {
    demo::run_demo(o, {});
    FAIL() << "an interrupted run must fail";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("is unchanged"), std::string::npos) << e.what();
  }
  clear_interrupt();
  EXPECT_TRUE(read_json(dir + "/report.json")["earlier"].get<bool>());
  EXPECT_TRUE(fs::exists(dir + "/frame.glb"));
  EXPECT_EQ(siblings(dir), std::vector<std::string>{});
}

// An input inside the output folder would be deleted by the swap: refused before anything starts.
TEST(Demo, GlassesInsideTheOutputFolderAreRefusedUpFront) {
  std::string dir = earlier_demo_output("demo-glasses-inside");
  demo::DemoOptions o;
  o.quick = true;
  o.force = true;
  o.out_dir = dir;
  o.glasses = dir + "/frame.glb";
  try {
    demo::run_demo(o, {});
    FAIL() << "expected a refusal";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("lies inside the output folder"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::exists(dir + "/frame.glb"));
  EXPECT_TRUE(read_json(dir + "/report.json")["earlier"].get<bool>());
}

TEST(Demo, UnwritableOutputIsAClearError) {
  demo::DemoOptions o;
  o.out_dir = "/proc/lorgnette-cannot-write-here";
  try {
    demo::run_demo(o, {});
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("lorgnette-cannot-write-here"), std::string::npos) << e.what();
  }
}

TEST(Demo, InterruptionLeavesAReportMarkedIncomplete) {
  install_interrupt_handler();
  std::raise(SIGINT);  // the first Ctrl-C only sets the flag
  demo::DemoOptions o;
  o.quick = true;
  o.out_dir = tmp("demo-interrupted");
  EXPECT_THROW(demo::run_demo(o, {}), std::runtime_error);
  clear_interrupt();
  nlohmann::json j = read_json(o.out_dir + "/report.json");
  EXPECT_FALSE(j["ok"].get<bool>());
  EXPECT_NE(j["message"].get<std::string>().find("interrupted"), std::string::npos);
  EXPECT_FALSE(fs::exists(o.out_dir + "/orbit/orbit.mp4"));
}

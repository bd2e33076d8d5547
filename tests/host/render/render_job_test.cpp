// The render job's inputs and outputs: sizes,
// placement and pose files, the refusal to overwrite files, and the straight-alpha conversion.
#include "host/render/render_job.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "host/render/analytic_field.h"
#include "host/util/interrupt.h"
#include "tests/common/scoped_tmpfs.h"

using namespace lorgnette;
using namespace lorgnette::render;
namespace fs = std::filesystem;

namespace {
std::string tmp_dir(const std::string& name) {
  fs::path p = fs::path(LORGNETTE_TEST_TMP) / ("render_job_" + name);
  fs::remove_all(p);
  fs::create_directories(p);
  return p.string();
}
void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

// The analytic head marched at `step`: the render function the jobs below run.
struct HeadRender {
  cl::Runtime rt;
  AnalyticField field{rt, analytic_head_min, analytic_head_max, analytic_head_primitives(), 1u << 14};
  VolumeScene scene;
  Marcher marcher{rt};
  explicit HeadRender(float step) {
    scene.aabb_min = analytic_head_min;
    scene.aabb_max = analytic_head_max;
    scene.step = step;
    scene.field = &field;
  }
  RenderResult render(const Camera& c, const lorgnette::SurfaceBuffers* s, const RenderOptions& o) {
    return marcher.render(scene, c, s, o);
  }
};

// Three views of 24 px around the analytic head, without video: the jobs that fail or stop midway.
RenderJob three_view_job() {
  OrbitSpec spec;
  spec.views = 3;
  spec.width = spec.height = 24;
  RenderJob job;
  job.cameras = orbit_cameras(spec);
  job.video = false;
  return job;
}
}  // namespace

TEST(RenderJob, ParsesSizesAndRefusesBadOnes) {
  auto s = parse_size("1280x720");
  EXPECT_EQ(s[0], 1280u);
  EXPECT_EQ(s[1], 720u);
  EXPECT_THROW(parse_size("1280"), std::invalid_argument);
  EXPECT_THROW(parse_size("0x10"), std::invalid_argument);
}

// Placement files are read by the placement module (tests/fit/placement_json_test.cpp).
TEST(RenderJob, ReadsPoseFiles) {
  std::string dir = tmp_dir("files");
  write(dir + "/pose.json",
        R"({"transform_matrix":[[1,0,0,0],[0,1,0,0],[0,0,1,3],[0,0,0,1]],"fl_x":500,"w":1000,"h":500})");
  Camera c = read_pose(dir + "/pose.json", 500, 250, 30.0f);
  EXPECT_FLOAT_EQ(c.fx, 250.0f);
  EXPECT_FLOAT_EQ(c.cx, 250.0f);
  EXPECT_FLOAT_EQ(c.c2w[11], 3.0f);
}

TEST(RenderJob, RefusesToOverwriteUnlessForced) {
  std::string dir = tmp_dir("overwrite");
  write(dir + "/frame_0000.png", "user file");
  try {
    check_outputs_free(dir, {"frame_0000.png", "depth_0000.exr"}, false);
    FAIL() << "expected a refusal";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("--force"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("frame_0000.png"), std::string::npos);
  }
  EXPECT_NO_THROW(check_outputs_free(dir, {"frame_0000.png"}, true));
  EXPECT_NO_THROW(check_outputs_free(dir, {"other.png"}, false));
}

TEST(RenderJob, OutputImagesAreStraightAlphaOrOpaqueRgb) {
  Image rgba(1, 1, 4);
  rgba.pixels = {0.2f, 0.1f, 0.05f, 0.5f};  // premultiplied
  Image a = to_output_image(rgba, true);
  ASSERT_EQ(a.channels, 4);
  EXPECT_FLOAT_EQ(a.pixels[0], 0.4f);
  EXPECT_FLOAT_EQ(a.pixels[3], 0.5f);
  Image b = to_output_image(rgba, false);
  ASSERT_EQ(b.channels, 3);
  EXPECT_FLOAT_EQ(b.pixels[0], 0.2f);
}

// End to end on the analytic head: a 3-view orbit writes every output, and a second run into the
// same directory is refused (then allowed with force).
TEST(RenderJob, OrbitWritesFramesDepthVideoSheetAndSummary) {
  HeadRender head(1.0f / 128.0f);
  OrbitSpec spec;
  spec.center = {0.0f, -0.15f, 0.05f};
  spec.half_extent = {0.6f, 0.75f, 0.65f};
  spec.views = 3;
  spec.width = 48;
  spec.height = 32;
  RenderJob job;
  job.cameras = orbit_cameras(spec);
  job.out_dir = tmp_dir("orbit");
  auto render = [&](const Camera& c, const lorgnette::SurfaceBuffers* s) {
    return head.render(c, s, job.options);
  };
  nlohmann::json out = run_render_job(job, render);
  EXPECT_EQ(out["views"], 3);
  for (const auto& name : render_job_outputs(job))
    EXPECT_TRUE(fs::exists(fs::path(job.out_dir) / name)) << name;
  Image depth = read_image(job.out_dir + "/depth_0001.exr");
  EXPECT_EQ(depth.width, 48);
  Image frame = read_image(job.out_dir + "/frame_0000.png");
  EXPECT_LT(frame.at(24, 12, 2), 0.9f) << "the head is in the middle of the frame";
  EXPECT_GT(frame.at(1, 1, 2), 0.99f) << "white background in the corner";
  EXPECT_THROW(run_render_job(job, render), std::runtime_error);
  job.force = true;
  EXPECT_NO_THROW(run_render_job(job, render));
}

// A full disk: the job stops with the disk's error instead of leaving 0-byte frames.
TEST(RenderJob, FullDiskIsAnErrorAndLeavesNoEmptyFrames) {
  lgn_test::ScopedTmpfs disk(fs::path(LORGNETTE_TEST_TMP) / "render_job_full_disk", 64 * 1024);
  LGN_SKIP_UNLESS_MOUNTED(disk);
  disk.fill();
  HeadRender head(1.0f / 64.0f);
  OrbitSpec spec;
  spec.views = 2;
  spec.width = spec.height = 24;
  RenderJob job;
  job.cameras = orbit_cameras(spec);
  job.out_dir = disk.path().string();
  try {
    run_render_job(job, [&](const Camera& c, const lorgnette::SurfaceBuffers* s) {
      return head.render(c, s, job.options);
    });
    FAIL() << "writing onto a full disk must fail";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("No space left on device"), std::string::npos) << e.what();
  }
  for (const auto& e : fs::directory_iterator(disk.path()))
    EXPECT_EQ(e.path().filename(), "filler") << "left behind: " << e.path();
}

// A disk that fills during the job, after the first view was written: the folders the job created
// (-o renders/today, neither there before) are removed with the view in them, so no empty or
// half-filled folder looks like a result; in a folder the user already had, the job's own files go
// and the user's file stays.
TEST(RenderJob, ADiskThatFillsMidJobLeavesNothingOfTheJob) {
  lgn_test::ScopedTmpfs disk(fs::path(LORGNETTE_TEST_TMP) / "render_job_fills", 1024 * 1024);
  LGN_SKIP_UNLESS_MOUNTED(disk);
  HeadRender head(1.0f / 64.0f);
  RenderJob job = three_view_job();
  int views = 0;
  auto fill_after_first = [&](const Camera& c, const lorgnette::SurfaceBuffers* s) {
    if (++views == 2) disk.fill();  // the first view's files are written by now
    return head.render(c, s, job.options);
  };
  const fs::path user = disk.path() / "mine";
  fs::create_directories(user);
  write(user / "notes.txt", "the user's\n");
  for (const fs::path& out : {disk.path() / "renders" / "today", user}) {
    fs::remove(disk.path() / "filler");
    views = 0;
    job.out_dir = out.string();
    try {
      run_render_job(job, fill_after_first);
      FAIL() << "writing onto a full disk must fail";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("No space left on device"), std::string::npos) << e.what();
    }
    EXPECT_EQ(views, 2) << "the first view was written before the disk filled";
  }
  std::vector<std::string> left;
  for (const auto& e : fs::recursive_directory_iterator(disk.path()))
    left.push_back(fs::relative(e.path(), disk.path()).string());
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{"filler", "mine", "mine/notes.txt"}));
}

// --force over an earlier render: a job that fails after its first view puts every earlier file back
// as it was (none half replaced) and leaves no hidden folder; a job that finishes replaces them all.
TEST(RenderJob, AFailedForcedRenderPutsTheEarlierFilesBack) {
  HeadRender head(1.0f / 64.0f);
  RenderJob job = three_view_job();
  job.force = true;
  job.out_dir = tmp_dir("force_fail");
  const std::vector<std::string> names = render_job_outputs(job);
  for (const auto& n : names) write(job.out_dir + "/" + n, "earlier " + n);
  write(job.out_dir + "/notes.txt", "the user's");
  int views = 0;
  auto fail_second = [&](const Camera& c, const lorgnette::SurfaceBuffers* s) {
    if (++views == 2) throw std::runtime_error("the device was lost");
    return head.render(c, s, job.options);
  };
  EXPECT_THROW(run_render_job(job, fail_second), std::runtime_error);
  auto text = [&](const std::string& n) {
    std::ifstream f(job.out_dir + "/" + n);
    return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
  };
  for (const auto& n : names) EXPECT_EQ(text(n), "earlier " + n);
  EXPECT_EQ(text("notes.txt"), "the user's");
  size_t entries = std::distance(fs::directory_iterator(job.out_dir), fs::directory_iterator());
  EXPECT_EQ(entries, names.size() + 1) << "no hidden folder is left";
  run_render_job(job, [&](const Camera& c, const lorgnette::SurfaceBuffers* s) {
    return head.render(c, s, job.options);
  });
  EXPECT_EQ(read_image(job.out_dir + "/frame_0002.png").width, 24);
  entries = std::distance(fs::directory_iterator(job.out_dir), fs::directory_iterator());
  EXPECT_EQ(entries, names.size() + 1);
}

// A stop asked for (Ctrl-C, SIGTERM) keeps the whole views written before it (docs/input-limits.md);
// a stop before the first view leaves no folder.
TEST(RenderJob, AStopKeepsTheWholeViewsWrittenAndNoEmptyFolder) {
  HeadRender head(1.0f / 64.0f);
  RenderJob job = three_view_job();
  const fs::path root = tmp_dir("stop");
  job.out_dir = (root / "renders").string();
  auto stop_after_first = [&](const Camera& c, const lorgnette::SurfaceBuffers* s) {
    request_interrupt();  // seen before the next view
    return head.render(c, s, job.options);
  };
  EXPECT_THROW(run_render_job(job, stop_after_first), std::runtime_error);
  clear_interrupt();
  EXPECT_TRUE(fs::exists(root / "renders" / "frame_0000.png"));
  EXPECT_TRUE(fs::exists(root / "renders" / "depth_0000.exr"));
  EXPECT_FALSE(fs::exists(root / "renders" / "frame_0001.png"));
  job.out_dir = (root / "none").string();
  request_interrupt();
  EXPECT_THROW(run_render_job(job, stop_after_first), std::runtime_error);
  clear_interrupt();
  EXPECT_FALSE(fs::exists(root / "none"));
}

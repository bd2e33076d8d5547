// The loader on small datasets generated in the test: writer round trip, per-frame intrinsics,
// extension-less paths, ground_truth.json, holdout assignment, and every kind of bad input, each of
// which must give an error that names the problem and the frame or file.
#include <gtest/gtest.h>
#include <spdlog/sinks/ringbuffer_sink.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>

#include "host/dataset/dataset.h"

using namespace lorgnette;
using namespace lorgnette::dataset;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr int kW = 16, kH = 12;

Camera test_camera(int i) {
  Camera c{};
  c.fx = 20.5f;
  c.fy = 21.25f;
  c.cx = 8.1f;
  c.cy = 5.9f;
  c.k1 = 0.01f;
  c.p2 = -0.002f;
  c.width = kW;
  c.height = kH;
  // Cameras on a circle around the origin, looking at it (rotation about y by angle a).
  double a = 0.3 * i, ca = std::cos(a), sa = std::sin(a);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() << ca, 0, sa, 0, 1, 0, -sa, 0, ca;
  m.block<3, 1>(0, 3) << 3 * sa, 0.1 * i, 3 * ca;
  set_camera_pose(c, m);
  return c;
}

// A fresh dataset dir with n frames of kW x kH RGB PNGs; `edit` may change the json before writing.
std::string make_dataset(const std::string& name, int n, const std::function<void(json&)>& edit = {}) {
  fs::path dir = fs::path(LORGNETTE_TEST_TMP) / "dataset" / name;
  fs::remove_all(dir);
  fs::create_directories(dir / "images");
  std::vector<Camera> cams;
  std::vector<std::string> files;
  for (int i = 0; i < n; ++i) {
    Image img(kW, kH, 3, 0.25f);
    img.at(i % kW, 0, 0) = 1.0f;
    std::string file = "images/f_" + std::to_string(100 + i) + ".png";
    write_image((dir / file).string(), img);
    cams.push_back(test_camera(i));
    files.push_back(file);
  }
  write_transforms_json(dir.string(), cams, files, json{{"aabb_scale", 2}});
  if (edit) {
    std::ifstream in(dir / "transforms.json");
    json doc = json::parse(in);
    edit(doc);
    std::ofstream(dir / "transforms.json") << doc.dump(1);
  }
  return dir.string();
}

// Loads and returns the error message ("" when it loaded).
std::string load_error(const std::string& dir, LoadOptions opt = {}) {
  try {
    load_dataset(dir, opt);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

#define EXPECT_HAS(msg, text) EXPECT_NE((msg).find(text), std::string::npos) << "message: " << (msg)

}  // namespace

TEST(DatasetWriter, RoundTripsCamerasBitwiseAndAssignsHoldout) {
  std::string dir = make_dataset("roundtrip", 17);
  Dataset ds = load_dataset(dir);
  ASSERT_EQ(ds.frames.size(), 17u);
  EXPECT_FLOAT_EQ(ds.aabb_scale, 2.0f);
  EXPECT_EQ(ds.split(Split::Holdout).size(), 3u);  // indices 0, 8, 16
  for (int i = 0; i < 17; ++i) {
    const Frame& f = ds.frames[i];
    EXPECT_EQ(f.name, "f_" + std::to_string(100 + i));
    EXPECT_EQ(f.split, i % 8 == 0 ? Split::Holdout : Split::Train);
    Camera want = test_camera(i);
    EXPECT_EQ(std::memcmp(&f.camera, &want, sizeof(Camera)), 0) << "frame " << i << " camera differs";
    EXPECT_EQ(f.image.channels, 4);
    EXPECT_NEAR(f.image.at(i % kW, 0, 0), 1.0f, 1e-6);
    EXPECT_NEAR(f.image.at(i % kW, 1, 0), 0.25f, 0.004f);  // 8-bit sRGB quantisation of 0.25
  }
  EXPECT_THROW(ds.require_split(Split::Test), std::runtime_error);
}

TEST(DatasetWriter, PerFrameIntrinsicsWhenCamerasDiffer) {
  fs::path dir = fs::path(LORGNETTE_TEST_TMP) / "dataset" / "perframe";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::vector<Camera> cams = {test_camera(0), test_camera(1)};
  cams[1].fx = 30.0f;
  for (int i = 0; i < 2; ++i)
    write_image((dir / ("i" + std::to_string(i) + ".png")).string(), Image(kW, kH, 4, 0.5f));
  write_transforms_json(dir.string(), cams, {"i0.png", "i1"});  // second without extension
  std::ifstream in(dir / "transforms.json");
  json doc = json::parse(in);
  EXPECT_FALSE(doc.contains("fl_x"));
  EXPECT_TRUE(doc["frames"][1].contains("fl_x"));
  Dataset ds = load_dataset((dir / "transforms.json").string());
  ASSERT_EQ(ds.frames.size(), 2u);
  EXPECT_FLOAT_EQ(ds.frames[1].camera.fx, 30.0f);
  EXPECT_FLOAT_EQ(ds.frames[0].camera.fx, 20.5f);
  EXPECT_TRUE(ds.has_alpha);
  EXPECT_THROW(write_transforms_json(dir.string(), cams, {"a.png"}), std::runtime_error);
}

TEST(DatasetLoader, GroundTruthMmPerUnitAndDownscaleKeepsOpticalAxis) {
  std::string dir = make_dataset("gt", 3);
  std::ofstream(fs::path(dir) / "ground_truth.json") << R"({"mm_per_unit": 57.5, "mesh": "head.glb"})";
  LoadOptions opt;
  opt.downscale = 2;
  Dataset ds = load_dataset(dir, opt);
  ASSERT_TRUE(ds.mm_per_unit.has_value());
  EXPECT_DOUBLE_EQ(*ds.mm_per_unit, 57.5);
  EXPECT_EQ(ds.ground_truth["mesh"], "head.glb");
  const Camera& c = ds.frames[1].camera;
  EXPECT_EQ(c.width, 8u);
  EXPECT_EQ(c.height, 6u);
  EXPECT_FLOAT_EQ(c.fx, 20.5f / 2);
  EXPECT_FLOAT_EQ(c.cy, 5.9f / 2);
  EXPECT_EQ(ds.frames[1].image.width, 8);
  // A world point projects to the same place relative to the image size at both resolutions.
  Camera full = test_camera(1);
  LgnVec3 p = lgn_vec3(0.1f, 0.2f, -0.3f);
  float u0, v0, u1, v1;
  camera_project(&full, p, &u0, &v0);
  camera_project(&c, p, &u1, &v1);
  EXPECT_NEAR(u1, u0 / 2, 1e-4);
  EXPECT_NEAR(v1, v0 / 2, 1e-4);
}

TEST(DatasetLoader, MaxFramesIsPerSplitAndEvenlySpaced) {
  std::string dir = make_dataset("maxframes", 24);
  LoadOptions opt;
  opt.max_frames = 2;
  Dataset ds = load_dataset(dir, opt);
  EXPECT_EQ(ds.split(Split::Holdout).size(), 2u);  // of 0, 8, 16
  ASSERT_EQ(ds.split(Split::Train).size(), 2u);    // of 21 -> indices 0 and 10 of the train list
  EXPECT_EQ(ds.split(Split::Train)[1]->name, "f_112");
}

TEST(DatasetValidation, MissingDirectoryAndJson) {
  EXPECT_HAS(load_error("/nonexistent/dataset-xyz"), "does not exist");
  fs::path empty = fs::path(LORGNETTE_TEST_TMP) / "dataset" / "nojson";
  fs::create_directories(empty);
  EXPECT_HAS(load_error(empty.string()), "no transforms.json");
}

TEST(DatasetValidation, MalformedJsonAndNonFiniteLiterals) {
  std::string dir = make_dataset("malformed", 2);
  std::ofstream(fs::path(dir) / "transforms.json") << R"({"frames": [ {"file_path": )";
  EXPECT_HAS(load_error(dir), "not valid JSON");
  std::ofstream(fs::path(dir) / "transforms.json")
      << R"({"fl_x": 10, "frames": [{"file_path": "images/f_100.png", "transform_matrix": [[NaN,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}]})";
  EXPECT_HAS(load_error(dir), "NaN");
}

// The warnings the loader logs while `f` runs.
std::vector<std::string> warnings_of(const std::function<void()>& f) {
  auto sink = std::make_shared<spdlog::sinks::ringbuffer_sink_mt>(16);
  sink->set_level(spdlog::level::warn);
  auto previous = spdlog::default_logger();
  spdlog::set_default_logger(std::make_shared<spdlog::logger>("test", sink));
  try {
    f();
  } catch (...) {
    spdlog::set_default_logger(previous);
    throw;
  }
  spdlog::set_default_logger(previous);
  return sink->last_formatted();
}

TEST(DatasetValidation, AFewMissingImagesAreSkippedWithAWarningThatCountsAndNamesThem) {
  // Like capture: the frames whose photo is gone are left out, never silently. Up to half may go.
  std::string dir = make_dataset("fewmissing", 12);
  for (int i : {103, 104, 105, 106, 107, 110})
    fs::remove(fs::path(dir) / ("images/f_" + std::to_string(i) + ".png"));
  Dataset ds;
  std::vector<std::string> logged = warnings_of([&] { ds = load_dataset(dir); });
  ASSERT_EQ(ds.frames.size(), 6u);
  for (const Frame& f : ds.frames) EXPECT_TRUE(fs::exists(f.image_path)) << f.image_path;
  EXPECT_EQ(ds.frames[1].name, "f_101");
  EXPECT_EQ(ds.frames[2].name, "f_102");
  EXPECT_EQ(ds.frames[3].name, "f_108");  // the cameras stay with their images
  EXPECT_FLOAT_EQ(ds.frames[3].camera.c2w[3], test_camera(8).c2w[3]);
  ASSERT_EQ(logged.size(), 1u) << (logged.empty() ? "" : logged[0]);
  EXPECT_HAS(logged[0], "skipping 6 of 12 frames");
  EXPECT_HAS(logged[0],
             "'images/f_103.png', 'images/f_104.png', 'images/f_105.png', 'images/f_106.png', "
             "'images/f_107.png' and 1 more");
  EXPECT_HAS(logged[0], "6 remain");
  // Fewer than three left is too few, even when that is half.
  std::string small = make_dataset("fewleft", 4);
  fs::remove(fs::path(small) / "images/f_101.png");
  EXPECT_EQ(load_dataset(small).frames.size(), 3u);
  fs::remove(fs::path(small) / "images/f_102.png");
  EXPECT_HAS(load_error(small), "only 2 would remain (at least 3");
}

TEST(DatasetValidation, EmptyFrameList) {
  std::string dir = make_dataset("emptyframes", 2, [](json& d) { d["frames"] = json::array(); });
  EXPECT_HAS(load_error(dir), "empty 'frames' list");
}

TEST(DatasetValidation, MostImagesMissingIsAnErrorThatCountsNamesAndSaysWhatToDo) {
  std::string dir = make_dataset("missingimg", 12);
  for (int i : {101, 103, 104, 105, 106, 107, 110})
    fs::remove(fs::path(dir) / ("images/f_" + std::to_string(i) + ".png"));
  std::string msg = load_error(dir);
  EXPECT_HAS(msg, "7 of 12 frames");
  EXPECT_HAS(msg,
             "'images/f_101.png', 'images/f_103.png', 'images/f_104.png', 'images/f_105.png', "
             "'images/f_106.png' and 2 more");
  EXPECT_HAS(msg, "restore those images");
  EXPECT_HAS(msg, "remove their frames from transforms.json");
  EXPECT_HAS(msg, "lorgnette capture");
  // What a user can do, not a C++ option they cannot pass.
  EXPECT_EQ(msg.find("LoadOptions"), std::string::npos) << msg;
  EXPECT_EQ(msg.find("skip_missing_images"), std::string::npos) << msg;
  EXPECT_HAS(msg, "only 5 would remain");
  LoadOptions any;  // the cameras alone (the renderer's capture arc): however many are missing
  any.any_missing_images_ok = true;
  EXPECT_EQ(load_dataset(dir, any).frames.size(), 5u);
  // Training loads the train split only (holdout: sorted indices 0 and 8, f_100 and f_108).
  LoadOptions train;
  train.splits = {Split::Train};
  EXPECT_HAS(load_error(dir, train), "7 of 10 train frames");
}

TEST(DatasetValidation, CorruptImage) {
  std::string dir = make_dataset("corrupt", 3);
  std::ofstream(fs::path(dir) / "images/f_102.png", std::ios::binary) << "this is not a png";
  std::string msg = load_error(dir);
  EXPECT_HAS(msg, "f_102.png");
  EXPECT_HAS(msg, "frame 2");
  LoadOptions cams_only;
  cams_only.load_images = false;  // the header is still read
  EXPECT_HAS(load_error(dir, cams_only), "f_102.png");
}

namespace {

// A dataset of n 192x192 noisy RGB frames (noise so the files do not compress to a few hundred
// bytes, and a cut really removes pixel data); `ext` is ".png" or ".jpg".
std::string make_noisy_dataset(const std::string& name, int n, const std::string& ext) {
  fs::path dir = fs::path(LORGNETTE_TEST_TMP) / "dataset" / name;
  fs::remove_all(dir);
  fs::create_directories(dir / "images");
  std::vector<Camera> cams;
  std::vector<std::string> files;
  uint32_t state = 12345u;
  for (int i = 0; i < n; ++i) {
    Image img(192, 192, 3);
    for (float& v : img.pixels) v = ((state = state * 1664525u + 1013904223u) >> 8) / 16777216.0f;
    std::string file = "images/g_" + std::to_string(i) + ext;
    write_image((dir / file).string(), img);
    Camera c = test_camera(i);
    c.width = c.height = 192;
    c.cx = c.cy = 96.0f;
    cams.push_back(c);
    files.push_back(file);
  }
  write_transforms_json(dir.string(), cams, files);
  return dir.string();
}

// Keeps the first `bytes` bytes of a file.
void truncate_file(const fs::path& path, size_t bytes) {
  ASSERT_GT(fs::file_size(path), bytes);
  fs::resize_file(path, bytes);
}

}  // namespace

TEST(DatasetValidation, TruncatedPngIsAnErrorNamingFileAndFrame) {
  std::string dir = make_noisy_dataset("truncated_png", 3, ".png");
  ASSERT_EQ(load_dataset(dir).frames.size(), 3u);  // intact, it loads
  truncate_file(fs::path(dir) / "images/g_1.png", 300);
  std::string msg = load_error(dir);
  EXPECT_HAS(msg, "g_1.png");
  EXPECT_HAS(msg, "frame 1");
  EXPECT_HAS(msg, "truncated");
  EXPECT_HAS(msg, "remove the frame");
}

TEST(DatasetValidation, TruncatedJpegIsAnErrorNamingFileAndFrame) {
  // libjpeg decodes a JPEG cut inside its scan data without failing (the rest of the image comes
  // back grey) and only records a warning: the loader must look at that error state.
  std::string dir = make_noisy_dataset("truncated_jpg", 3, ".jpg");
  ASSERT_EQ(load_dataset(dir).frames.size(), 3u);
  fs::path jpg = fs::path(dir) / "images/g_2.jpg";
  truncate_file(jpg, fs::file_size(jpg) / 2);
  std::string msg = load_error(dir);
  EXPECT_HAS(msg, "g_2.jpg");
  EXPECT_HAS(msg, "frame 2");
  EXPECT_HAS(msg, "truncated");
}

TEST(DatasetValidation, ImageSizeDiffersFromIntrinsics) {
  std::string dir = make_dataset("size", 2, [](json& d) { d["w"] = 20; });
  std::string msg = load_error(dir);
  EXPECT_HAS(msg, "16x12");
  EXPECT_HAS(msg, "w=20");
  // No w/h declared, but intrinsics made for a larger image: the principal point gives it away.
  std::string big = make_dataset("bigintrinsics", 2, [](json& d) {
    d.erase("w");
    d.erase("h");
    d["cx"] = 320.0;
  });
  EXPECT_HAS(load_error(big), "principal point");
}

TEST(DatasetValidation, NonFiniteAndNonRigidPoses) {
  std::string inf =
      make_dataset("infpose", 2, [](json& d) { d["frames"][1]["transform_matrix"][0][3] = nullptr; });
  EXPECT_HAS(load_error(inf), "frame 1");
  std::ofstream(fs::path(inf) / "transforms.json")
      << R"({"fl_x": 10, "frames": [{"file_path": "images/f_100.png", "transform_matrix": [[1,0,0,1e999],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}]})";
  EXPECT_HAS(load_error(inf), "infinite");
  std::string scaled = make_dataset("scaledpose", 2, [](json& d) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        d["frames"][1]["transform_matrix"][r][c] = d["frames"][1]["transform_matrix"][r][c].get<double>() * 2;
  });
  std::string msg = load_error(scaled);
  EXPECT_HAS(msg, "not a rigid transform");
  EXPECT_HAS(msg, "frame 1");
}

TEST(DatasetValidation, AllCamerasAtOnePosition) {
  std::string dir = make_dataset("degenerate", 4, [](json& d) {
    for (auto& f : d["frames"])
      for (int r = 0; r < 3; ++r) f["transform_matrix"][r][3] = 1.5;
  });
  EXPECT_HAS(load_error(dir), "same position");
}

TEST(DatasetValidation, UnsupportedCameraModel) {
  std::string dir = make_dataset("fisheye", 2, [](json& d) { d["camera_model"] = "OPENCV_FISHEYE"; });
  EXPECT_HAS(load_error(dir), "OPENCV_FISHEYE");
  std::string k3 = make_dataset("k3", 2, [](json& d) { d["k3"] = 0.1; });
  EXPECT_HAS(load_error(k3), "k3");
}

TEST(DatasetValidation, UnknownSplitNameAndBadOptions) {
  EXPECT_EQ(split_from_string("holdout"), Split::Holdout);
  EXPECT_THROW(split_from_string("testing"), std::runtime_error);
  std::string dir = make_dataset("opts", 2);
  LoadOptions bad;
  bad.downscale = 0;
  EXPECT_HAS(load_error(dir, bad), "downscale");
}

// A generated NeRF-synthetic triple: camera_angle_x only, "./train/r_0" paths without extension,
// RGBA images; downscaling averages premultiplied colour so transparent pixels do not bleed.
TEST(DatasetLoader, NerfSyntheticTripleWithAlphaAndHints) {
  fs::path dir = fs::path(LORGNETTE_TEST_TMP) / "dataset" / "synthetic";
  fs::remove_all(dir);
  for (const char* split : {"train", "test"}) {
    fs::create_directories(dir / split);
    json doc{
        {"camera_angle_x", 0.8}, {"scale", 0.33}, {"offset", {0.5, 0.5, 0.5}}, {"frames", json::array()}};
    for (int i = 0; i < 3; ++i) {
      Image img(4, 4, 4, 0.0f);
      for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) img.at(x, y, 1) = 1.0f;  // transparent green everywhere
      img.at(0, 0, 0) = 1.0f;                                // one opaque red pixel
      img.at(0, 0, 1) = 0.0f;
      img.at(0, 0, 3) = 1.0f;
      write_image((dir / split / ("r_" + std::to_string(i) + ".png")).string(), img);
      Camera c = test_camera(i + (split[1] == 'e' ? 3 : 0));
      json m = json::array();
      for (int r = 0; r < 4; ++r)
        m.push_back(r < 3 ? json::array({c.c2w[r * 4], c.c2w[r * 4 + 1], c.c2w[r * 4 + 2], c.c2w[r * 4 + 3]})
                          : json::array({0, 0, 0, 1}));
      doc["frames"].push_back(
          {{"file_path", std::string("./") + split + "/r_" + std::to_string(i)}, {"transform_matrix", m}});
    }
    std::ofstream(dir / (std::string("transforms_") + split + ".json")) << doc.dump();
  }
  LoadOptions opt;
  opt.downscale = 2;
  Dataset ds = load_dataset((dir / "transforms_test.json").string(), opt);  // a file selects its triple
  EXPECT_EQ(ds.format, "nerf-synthetic");
  EXPECT_EQ(ds.split(Split::Train).size(), 3u);
  EXPECT_EQ(ds.split(Split::Test).size(), 3u);
  EXPECT_FALSE(ds.has_split(Split::Val));
  EXPECT_TRUE(ds.has_alpha);
  ASSERT_TRUE(ds.scale && ds.offset);
  EXPECT_FLOAT_EQ(*ds.scale, 0.33f);
  EXPECT_FLOAT_EQ((*ds.offset)[2], 0.5f);
  const Frame& f = ds.frames[0];
  EXPECT_EQ(f.name, "r_0");
  EXPECT_NEAR(f.camera.fx, 0.5 * 4 / std::tan(0.4) / 2, 1e-5);  // fov focal at 4 px, then halved
  EXPECT_FLOAT_EQ(f.camera.cx, 1.0f);
  ASSERT_EQ(f.image.width, 2);
  EXPECT_FLOAT_EQ(f.image.at(0, 0, 3), 0.25f);  // one opaque pixel of four
  EXPECT_FLOAT_EQ(f.image.at(0, 0, 0), 1.0f);   // straight colour: pure red, no green bleed
  EXPECT_FLOAT_EQ(f.image.at(0, 0, 1), 0.0f);
  EXPECT_FLOAT_EQ(f.image.at(1, 1, 3), 0.0f);
  LoadOptions only_test;
  only_test.splits = {Split::Test};
  EXPECT_EQ(load_dataset(dir.string(), only_test).frames.size(), 3u);
  EXPECT_HAS(std::string([&] {
               try {
                 load_dataset(dir.string(), only_test).require_split(Split::Holdout);
               } catch (const std::runtime_error& e) {
                 return std::string(e.what());
               }
               return std::string();
             }()),
             "--split test");
}

TEST(DatasetLoader, SubjectBoxIsReadAndValidated) {
  std::string dir = make_dataset("aabb", 9, [](json& d) {
    d["aabb"] = {{-1.0, -2.0, -0.5}, {1.0, 0.5, 0.75}};
  });
  Dataset ds = load_dataset(dir);
  ASSERT_TRUE(ds.aabb.has_value());
  EXPECT_FLOAT_EQ((*ds.aabb)[0][1], -2.0f);
  EXPECT_FLOAT_EQ((*ds.aabb)[1][2], 0.75f);
  EXPECT_FALSE(load_dataset(make_dataset("no-aabb", 9)).aabb.has_value());
  std::string inverted = make_dataset("bad-aabb", 9, [](json& d) { d["aabb"] = {{1, 0, 0}, {0, 1, 1}}; });
  EXPECT_HAS(load_error(inverted), "'aabb' must be");
}

// Found by fuzzing (fuzz/regressions/transforms/): numbers a double holds but an int or a float
// does not are refused, not converted (undefined behaviour for the int, an infinite box for aabb).
TEST(DatasetValidation, NumbersBeyondIntOrFloatAreRefused) {
  std::string wide = make_dataset("huge-w", 9, [](json& d) { d["w"] = 1e300; });
  EXPECT_HAS(load_error(wide), "'w' must be a positive whole number");
  std::string far = make_dataset("huge-aabb", 9, [](json& d) { d["aabb"] = {{-1, -1, -1}, {1e300, 1, 1}}; });
  EXPECT_HAS(load_error(far), "'aabb' must be");
}

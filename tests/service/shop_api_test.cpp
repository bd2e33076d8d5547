// The shopper's side of the API in-process (no HTTP): the embedded pages are served at their paths
// (the upload page records or picks a video), and a finished job's artifacts are served behind the
// capture's own token only, byte for byte, while every path that is not one the job listed (".."
// escapes, encoded dots, absolute paths, the model, the upload, another capture's file) gets the
// same 404 and none of the file's bytes. The job's JSON names no path on the server.
#include <gtest/gtest.h>

#include <cstring>

#include "service/api.h"
#include "service/client_json.h"
#include "service/job_folder.h"
#include "service/local_executor.h"
#include "service/progress.h"
#include "service/sqlite_store.h"
#include "service_test_util.h"

using namespace lorgnette::service;
using namespace lorgnette::service::test;

namespace {

class StringBody final : public BodySource {
 public:
  explicit StringBody(std::string s = "") : s_(std::move(s)) {}
  std::string read_all(uint64_t) override { return s_; }
  uint64_t read_to_file(const fs::path& p, uint64_t) override {
    write_file(p, s_);
    return s_.size();
  }

 private:
  std::string s_;
};

struct Shop {
  fs::path data;
  std::unique_ptr<JobStore> store;
  std::unique_ptr<LocalExecutor> executor;
  std::unique_ptr<Api> api;

  explicit Shop(const fs::path& d) : data(d) {
    store = open_sqlite_store((data / "jobs.sqlite").string());
    LocalExecutorOptions eo;
    eo.data_dir = data.string();
    eo.worker_exe = "/bin/false";  // never started: nothing is queued
    executor = std::make_unique<LocalExecutor>(*store, eo);
    ApiOptions ao;
    ao.data_dir = data.string();
    api = std::make_unique<Api>(ao, *store, *executor);
  }
  ApiResponse get(const std::string& target, const std::string& token = "") {
    StringBody body;
    return api->handle({"GET", target, token.empty() ? "" : "Bearer " + token, std::nullopt}, body);
  }
  // A capture whose job finished with one frame's views, as the worker leaves it.
  std::pair<std::string, std::string> finished_capture(const std::string& jpeg) {
    StringBody none;
    const auto c = nlohmann::json::parse(api->handle({"POST", "/api/v1/captures", "", 0}, none).body);
    const std::string id = c["id"], token = c["token"];
    auto rec = *store->get(id);
    rec.state = JobState::Finished;
    store->update(rec);
    const JobFolder f{data / "captures" / id};
    write_file(f.fit_dir("round.glb") / "view_00.jpg", jpeg);
    write_file(f.fit_dir("round.glb") / "placement.json", "{\"version\": 1}\n");
    write_file(f.model(), "private model bytes");
    write_file(f.upload() / "video.mp4", "private video bytes");
    Progress p;
    p.state = "finished";
    p.artifacts = {{"model", "model/head.lnerf"},
                   {"fits", {{"round.glb", "fits/round.glb/placement.json"}}},
                   {"views", {{"round.glb", {"fits/round.glb/view_00.jpg"}}}},
                   {"preview", "fits/round.glb/view_00.jpg"}};
    write_progress(f.progress(), p);
    return {id, token};
  }
};

}  // namespace

TEST(ShopPages, ServesTheUploadStatusAndTryOnPages) {
  Shop shop(test_dir("service_shop"));
  const ApiResponse index = shop.get("/");
  ASSERT_EQ(index.status, 200);
  EXPECT_EQ(index.content_type, "text/html; charset=utf-8");
  EXPECT_NE(index.body.find("accept=\"video/*\" capture"), std::string::npos);  // records on a phone
  EXPECT_NE(index.body.find("<progress"), std::string::npos);
  for (const char* page : {"/status.html", "/tryon.html", "/shop.js", "/upload.js", "/shop.css"})
    EXPECT_EQ(shop.get(page).status, 200) << page;
  EXPECT_EQ(shop.get("/?ignored=1").status, 200);
  EXPECT_EQ(shop.get("/missing.html").status, 404);
  EXPECT_EQ(shop.get("/../service/web/index.html").status, 404);
  StringBody none;
  EXPECT_EQ(shop.api->handle({"POST", "/", "", 0}, none).status, 404);
}

TEST(ShopArtifacts, ServesListedFilesBehindTheCapturesTokenOnly) {
  Shop shop(test_dir("service_shop"));
  const std::string jpeg = std::string("\xFF\xD8\xFF\xE0 a try-on view", 18);
  const auto [id, token] = shop.finished_capture(jpeg);
  const auto [other_id, other_token] = shop.finished_capture("another shopper's view");
  const std::string base = "/api/v1/captures/" + id + "/artifacts/";

  ApiResponse view = shop.get(base + "fits/round.glb/view_00.jpg", token);
  ASSERT_EQ(view.status, 200) << view.body;
  EXPECT_EQ(view.content_type, "image/jpeg");
  EXPECT_EQ(view.body, jpeg);
  ApiResponse placement = shop.get(base + "fits/round.glb/placement.json?download=1", token);
  EXPECT_EQ(placement.status, 200);
  EXPECT_EQ(placement.content_type, "application/json");

  EXPECT_EQ(shop.get(base + "fits/round.glb/view_00.jpg").status, 401);               // no token
  EXPECT_EQ(shop.get(base + "fits/round.glb/view_00.jpg", other_token).status, 404);  // another's token
  for (const std::string& escape :
       {std::string("model/head.lnerf"), std::string("upload/video.mp4"), std::string("job.json"),
        std::string("../") + other_id + "/fits/round.glb/view_00.jpg",
        std::string("fits/round.glb/../../job.json"), std::string("%2e%2e/%2e%2e/jobs.sqlite"),
        std::string("/etc/passwd"), std::string("fits/round.glb"),
        std::string("fits/round.glb/view_00.jpg/")}) {
    ApiResponse r = shop.get(base + escape, token);
    EXPECT_EQ(r.status, 404) << escape;
    EXPECT_EQ(r.body.find("private"), std::string::npos) << escape;
    EXPECT_EQ(r.body.find("another shopper"), std::string::npos) << escape;
  }
}

TEST(ShopArtifacts, AJobNotFinishedHasNoFilesYet) {
  Shop shop(test_dir("service_shop"));
  const auto [id, token] = shop.finished_capture("view");
  auto rec = *shop.store->get(id);
  rec.state = JobState::Running;
  shop.store->update(rec);
  ApiResponse r = shop.get("/api/v1/captures/" + id + "/artifacts/fits/round.glb/view_00.jpg", token);
  EXPECT_EQ(r.status, 409);
  EXPECT_NE(r.body.find("not_finished"), std::string::npos);
}

// Absolute paths in a worker's text reach the client as the file's name; capture-relative paths,
// fractions and URLs are left as they are.
TEST(ClientJson, TextLosesItsServerPaths) {
  EXPECT_EQ(without_server_paths("cannot load mesh '/srv/shop/catalogue/a b.glb': not a valid glTF"),
            "cannot load mesh 'a b.glb': not a valid glTF");
  EXPECT_EQ(without_server_paths("catalogue /srv/shop/catalogue/ is not a directory"),
            "catalogue catalogue is not a directory");
  EXPECT_EQ(without_server_paths("/data/captures/x/upload/video.mp4: No space left on device (/tmp/t.png)."),
            "video.mp4: No space left on device (t.png).");
  EXPECT_EQ(without_server_paths("path=\"/var/lib/l/jobs.sqlite\" [/etc/x]"), "path=\"jobs.sqlite\" [x]");
  for (const std::string kept :
       {"fits/round.glb/view_00.jpg", "frame 1/3", "see http://host/api/v1", "a / b", "ends with /", ""})
    EXPECT_EQ(without_server_paths(kept), kept);
}

namespace {
// Every string in `j` (keys and values), recursively.
void strings_of(const nlohmann::json& j, std::vector<std::string>& out) {
  if (j.is_string()) out.push_back(j.get<std::string>());
  if (j.is_object())
    for (const auto& [k, v] : j.items()) out.push_back(k), strings_of(v, out);
  if (j.is_array())
    for (const auto& v : j) strings_of(v, out);
}

// True when some word of `s` starts with '/' (an absolute path).
bool names_an_absolute_path(const std::string& s) {
  for (size_t i = 0; i < s.size(); ++i)
    if (s[i] == '/' && (i == 0 || std::strchr(" '\"([=", s[i - 1]))) return true;
  return false;
}
}  // namespace

// A finished job whose catalogue had a damaged frame and a failed job whose message names its upload,
// both as the worker writes them (absolute server paths in the text): their JSON lists only what the
// client fetches (preview, views, fits) and why a frame is unavailable, with no absolute path, not
// the server's folders, nor the model or dataset it never serves.
TEST(ShopArtifacts, TheJobsJsonNamesNoServerPath) {
  Shop shop(test_dir("service_shop"));
  const auto [id, token] = shop.finished_capture("view");
  const fs::path catalogue = fs::absolute(shop.data / "catalogue");
  const JobFolder f{shop.data / "captures" / id};
  Progress p = *read_progress(f.progress());
  p.artifacts["dataset"] = "dataset/transforms.json";
  p.artifacts["unavailable"] = {
      {"a-broken.glb", "cannot load mesh '" + (catalogue / "a-broken.glb").string() + "': not a valid glTF"}};
  p.artifacts["unavailable_from"] = {{"a-broken.glb", "fnv1a64:0123456789abcdef"}};
  write_progress(f.progress(), p);
  auto rec = *shop.store->get(id);
  rec.message = "fitted 1 frame of " + catalogue.string();
  shop.store->update(rec);
  const auto [failed_id, failed_token] = shop.finished_capture("view");
  auto failed = *shop.store->get(failed_id);
  failed.state = JobState::Failed;
  failed.message = "cannot read '" +
                   fs::absolute(shop.data / "captures" / failed_id / "upload" / "video.mp4").string() +
                   "': not a video";
  shop.store->update(failed);

  const nlohmann::json done = nlohmann::json::parse(shop.get("/api/v1/captures/" + id, token).body);
  const nlohmann::json bad =
      nlohmann::json::parse(shop.get("/api/v1/captures/" + failed_id, failed_token).body);
  EXPECT_EQ(done["artifacts"]["preview"], "fits/round.glb/view_00.jpg");
  EXPECT_EQ(done["artifacts"]["views"]["round.glb"][0], "fits/round.glb/view_00.jpg");
  EXPECT_EQ(done["artifacts"]["unavailable"]["a-broken.glb"],
            "cannot load mesh 'a-broken.glb': not a valid glTF");
  EXPECT_FALSE(done["artifacts"].contains("unavailable_from"));  // the server's own record
  EXPECT_FALSE(done["artifacts"].contains("model"));
  EXPECT_FALSE(done["artifacts"].contains("dataset"));
  EXPECT_EQ(done["message"], "fitted 1 frame of catalogue");
  EXPECT_EQ(bad["message"], "cannot read 'video.mp4': not a video");
  for (const nlohmann::json* j : {&done, &bad}) {
    std::vector<std::string> all;
    strings_of(*j, all);
    for (const std::string& s : all) {
      EXPECT_FALSE(names_an_absolute_path(s)) << s;
      EXPECT_EQ(s.find(fs::absolute(shop.data).string()), std::string::npos) << s;
    }
  }
  // The API's own errors keep the URLs they point the client to.
  EXPECT_NE(shop.get("/api/nope").body.find("under /api/v1"), std::string::npos);
}

// A frame that could not be fitted is not tried again while its file is the one it failed with (each
// read of the job would queue it again), and is tried again once the shop replaces the file; a job
// that recorded no hash for it (made before the hashes were kept) keeps it unavailable.
TEST(ShopArtifacts, AFrameIsTriedAgainWhenTheShopReplacesItsFile) {
  const fs::path catalogue = test_dir("service_frame_replaced") / "catalogue";
  fs::create_directories(catalogue);
  write_file(catalogue / "a-broken.glb", "glTF but not really");
  write_file(catalogue / "round.glb", "a frame that fitted");
  nlohmann::json artifacts = {
      {"fits", {{"round.glb", "fits/round.glb/placement.json"}}},
      {"unavailable", {{"a-broken.glb", "not a valid glTF"}}},
      {"unavailable_from", {{"a-broken.glb", frame_file_hash((catalogue / "a-broken.glb").string())}}}};
  EXPECT_TRUE(frames_not_fitted(catalogue.string(), artifacts).empty());
  write_file(catalogue / "a-broken.glb", "glTF, repaired by the shop");
  EXPECT_EQ(frames_not_fitted(catalogue.string(), artifacts), std::vector<std::string>{"a-broken.glb"});
  artifacts.erase("unavailable_from");
  EXPECT_TRUE(frames_not_fitted(catalogue.string(), artifacts).empty());
  EXPECT_EQ(frame_file_hash((catalogue / "missing.glb").string()), "");
}

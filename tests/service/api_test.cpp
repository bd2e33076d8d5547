// The API in-process (no HTTP): uploads are judged by their bytes (the magic numbers of each
// accepted format, and near misses refused), and the retention sweep deletes exactly the captures
// older than the period, folder and row, leaving younger ones untouched.
#include "service/api.h"

#include <gtest/gtest.h>

#include "service/content_type.h"
#include "service/local_executor.h"
#include "service/sqlite_store.h"
#include "service/tokens.h"
#include "service_test_util.h"

using namespace lorgnette::service;
using namespace lorgnette::service::test;

TEST(ContentType, AcceptsVideosAndPhotosByTheirBytesOnly) {
  auto kind = [](const std::string& bytes) { return sniff_bytes(bytes); };
  EXPECT_EQ(kind(std::string("\0\0\0\x18"
                             "ftypmp42\0\0\0\0",
                             16))
                .extension,
            ".mp4");
  EXPECT_EQ(kind(std::string("\0\0\0\x14"
                             "ftypqt  \0\0\0\0",
                             16))
                .extension,
            ".mov");
  EXPECT_EQ(kind("\x1A\x45\xDF\xA3\x9F\x42\x86\x81\x01\x42\x82\x84webm").extension, ".webm");
  EXPECT_EQ(kind("\x1A\x45\xDF\xA3\x9F\x42\x86\x81\x01\x42\x82\x88matroska").extension, ".mkv");
  EXPECT_EQ(kind(std::string("RIFF\0\0\0\0AVI LIST", 16)).extension, ".avi");
  EXPECT_EQ(kind("\xFF\xD8\xFF\xE0\0\x10JFIF").kind, UploadKind::Image);
  EXPECT_EQ(kind("\x89PNG\r\n\x1A\n\0\0\0\rIHDR").extension, ".png");
  for (const std::string& bad :
       {std::string(""), std::string("ftyp"), std::string("RIFF\0\0\0\0WAVEfmt ", 16), std::string("GIF89a"),
        std::string("<html><body>"), std::string("\x89PNX\r\n")})
    EXPECT_EQ(kind(bad).kind, UploadKind::Unknown) << bad;
}

TEST(ContentType, TokensAreRandomHashedAndComparedWhole) {
  EXPECT_NE(new_capture_token(), new_capture_token());
  EXPECT_TRUE(valid_capture_id(new_capture_id()));
  EXPECT_FALSE(valid_capture_id("../0123456789abcdef0123456789abc"));
  EXPECT_FALSE(valid_capture_id("0123456789ABCDEF0123456789ABCDEF"));  // lower case only
  // SHA-256 of "abc" (FIPS 180-2, appendix B.1).
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  const std::string t = new_capture_token();
  EXPECT_TRUE(token_matches(t, sha256_hex(t)));
  EXPECT_FALSE(token_matches(t.substr(0, 63), sha256_hex(t)));
  EXPECT_FALSE(token_matches(t, sha256_hex(t).substr(0, 63)));
}

TEST(Api, RetentionDeletesOnlyCapturesOlderThanThePeriod) {
  fs::path data = test_dir("service_api");
  auto store = open_sqlite_store((data / "jobs.sqlite").string());
  LocalExecutorOptions eo;
  eo.data_dir = data.string();
  eo.worker_exe = "/bin/false";  // never started: nothing is queued
  LocalExecutor executor(*store, eo);
  ApiOptions ao;
  ao.data_dir = data.string();
  ao.retention_seconds = 1000;
  Api api(ao, *store, executor);
  const int64_t now = 1'000'000;
  for (const auto& [name, age] : {std::pair<std::string, int64_t>{"old", 1001}, {"young", 999}}) {
    CaptureRecord r;
    r.id = name, r.token_hash = "x", r.state = JobState::Finished, r.created_unix = now - age;
    store->insert(r);
    write_file(data / "captures" / name / "model" / "head.lnerf", "model bytes");
  }
  EXPECT_EQ(api.sweep_retention(now), 1);
  EXPECT_FALSE(fs::exists(data / "captures" / "old"));
  EXPECT_FALSE(store->get("old"));
  EXPECT_TRUE(fs::exists(data / "captures" / "young" / "model" / "head.lnerf"));
  EXPECT_TRUE(store->get("young"));
  EXPECT_EQ(api.sweep_retention(now), 0);
}

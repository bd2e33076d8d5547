// Training checkpoints (host/nerf/checkpoint.h, train_resume.h) on the analytic sphere scene:
//  - 40 steps straight and 17 steps, stopped (the interrupt a Python progress hook or Ctrl-C gives),
//    then resumed to 40 from the checkpoint file give bitwise the same parameters, Adam state,
//    occupancy and loss curve (deterministic mode: every reduction has a fixed order and all
//    randomness is counter-based on the step, which the checkpoint restores);
//  - with a room model the state read back from a checkpoint is bitwise the state written (the room
//    model's hash backward uses float atomics, so two room trainings are not bitwise alike even
//    straight; the round trip is what a checkpoint owes them);
//  - a checkpoint of another dataset or other settings is refused naming what differs;
//  - a truncated or altered checkpoint is refused as corrupt; `train --resume` (Required) stops with
//    the message, the service (IfValid) trains from step 0.
#include "host/nerf/checkpoint.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "host/nerf/train_resume.h"
#include "host/nerf/trainer.h"
#include "host/util/interrupt.h"
#include "sphere_model.h"

namespace {

using namespace lorgnette;
using namespace lorgnette::nerf;

// 16 views of 64 px, models of 2^12 samples per batch, seed 7.
struct Scene : nerftest::SphereModelScene {
  Scene() : SphereModelScene(16, 64) {}
};

std::string tmp_path(const std::string& name) {
  const std::string p = std::string(LORGNETTE_TEST_TMP) + "/checkpoint_" + name;
  std::filesystem::remove(p);
  return p;
}

TrainOptions options(const std::string& checkpoint, bool room = false) {
  TrainOptions o;
  o.steps = 40;  // crosses two occupancy updates (every 16 steps)
  o.seed = 7;
  o.progress = false;
  o.snapshot_every_seconds = 0.0;  // checkpoints at the end of run() only: the stop decides the step
  o.checkpoint_path = checkpoint;
  o.checkpoint_key = {"dataset-a", R"({"steps":40,"seed":7})"};
  o.background.enabled = room;
  o.background.log2_table = 12;
  o.background.levels = 6;
  return o;
}

// A fresh model trained for 3 steps of options(); returns the checkpoint it left at tmp_path(name).
std::string checkpoint_after_3_steps(Scene& s, const std::string& name) {
  NerfModel model = s.make_model();
  const std::string ckpt = tmp_path(name);
  TrainOptions o = options(ckpt);
  o.steps = 3;
  Trainer(model, s.train.views, o, s.sizing.occupancy_mask).run();
  return ckpt;
}

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void expect_same_field(const FieldState& a, const FieldState& b) {
  EXPECT_TRUE(a.params == b.params);
  EXPECT_TRUE(a.adam.m == b.adam.m);
  EXPECT_TRUE(a.adam.v == b.adam.v);
  EXPECT_EQ(a.adam.t, b.adam.t);
  EXPECT_EQ(a.occupancy.bits, b.occupancy.bits);
  EXPECT_TRUE(a.occupancy.density == b.occupancy.density);
  EXPECT_EQ(a.occupancy_updates, b.occupancy_updates);
}

}  // namespace

TEST(Checkpoint, StoppedAndResumedTrainingEqualsTheStraightOneBitwise) {
  Scene s;
  NerfModel straight_model = s.make_model();
  Trainer straight(straight_model, s.train.views, options(""), s.sizing.occupancy_mask);
  const TrainResult full = straight.run();

  const std::string ckpt = tmp_path("resume.ckpt");
  std::vector<double> curve;
  {
    NerfModel model = s.make_model();
    TrainOptions o = options(ckpt);
    o.on_step_in_time = true;  // the hook sees each step before the next is issued
    o.on_step = [](uint64_t step, double, double) {
      if (step == 17) request_interrupt();
    };
    Trainer first(model, s.train.views, o, s.sizing.occupancy_mask);
    const TrainResult r = first.run();
    clear_interrupt();
    ASSERT_TRUE(r.interrupted);
    ASSERT_EQ(r.steps, 17u);
    curve = r.loss_curve;
  }
  ASSERT_TRUE(std::filesystem::exists(ckpt));
  NerfModel model = s.make_model();
  const TrainOptions o = options(ckpt);
  Trainer resumed(model, s.train.views, o, s.sizing.occupancy_mask);
  resume_training(resumed, o, TrainJob::Resume::Required);
  EXPECT_EQ(resumed.steps_done(), 17u);
  const TrainResult rest = resumed.run();
  EXPECT_EQ(rest.steps, 40u);
  curve.insert(curve.end(), rest.loss_curve.begin(), rest.loss_curve.end());
  EXPECT_EQ(curve, full.loss_curve);
  EXPECT_EQ(rest.samples, full.samples);
  expect_same_field(resumed.state().subject, straight.state().subject);
}

TEST(Checkpoint, ARoomModelsStateReadsBackAsWritten) {
  Scene s;
  NerfModel model = s.make_model();
  const std::string ckpt = tmp_path("room.ckpt");
  const TrainOptions o = options(ckpt, true);
  TrainOptions shorter = o;
  shorter.steps = 20;
  Trainer trainer(model, s.train.views, shorter, s.sizing.occupancy_mask);
  for (int i = 0; i < 20; ++i) trainer.step();  // past an occupancy update of both models
  const TrainingState written = trainer.state();
  ASSERT_TRUE(written.room.has_value());
  write_checkpoint(ckpt, o.checkpoint_key, written);

  NerfModel again = s.make_model();
  Trainer restored(again, s.train.views, o, s.sizing.occupancy_mask);
  resume_training(restored, o, TrainJob::Resume::Required);
  const TrainingState read = restored.state();
  EXPECT_EQ(read.step, 20u);
  EXPECT_EQ(read.samples, written.samples);
  EXPECT_EQ(read.n_rays, written.n_rays);
  EXPECT_EQ(read.room_samples, written.room_samples);
  expect_same_field(read.subject, written.subject);
  expect_same_field(*read.room, written.room.value());
  // A training without a room model cannot take it.
  NerfModel plain = s.make_model();
  Trainer no_room(plain, s.train.views, options(ckpt), s.sizing.occupancy_mask);
  EXPECT_THROW(no_room.restore(*read_checkpoint(ckpt, o.checkpoint_key)), CheckpointMismatch);
}

TEST(Checkpoint, AnotherDatasetOrOtherSettingsAreRefusedNamingWhatDiffers) {
  Scene s;
  const std::string ckpt = checkpoint_after_3_steps(s, "mismatch.ckpt");
  ASSERT_TRUE(std::filesystem::exists(ckpt));
  try {
    read_checkpoint(ckpt, {"dataset-b", options(ckpt).checkpoint_key.settings});
    FAIL() << "another dataset's checkpoint was taken";
  } catch (const CheckpointMismatch& e) {
    EXPECT_NE(std::string(e.what()).find("another dataset"), std::string::npos) << e.what();
  }
  try {
    read_checkpoint(ckpt, {"dataset-a", R"({"steps":40,"seed":8})"});
    FAIL() << "a checkpoint of other settings was taken";
  } catch (const CheckpointMismatch& e) {
    EXPECT_NE(std::string(e.what()).find("'seed' (7 there, 8 now)"), std::string::npos) << e.what();
  }
  // The service's mode trains from step 0 instead; `train --resume` stops.
  TrainOptions other = options(ckpt);
  other.checkpoint_key.dataset_hash = "dataset-b";
  NerfModel fresh = s.make_model();
  Trainer t(fresh, s.train.views, other, s.sizing.occupancy_mask);
  EXPECT_THROW(resume_training(t, other, TrainJob::Resume::Required), CheckpointMismatch);
  resume_training(t, other, TrainJob::Resume::IfValid);
  EXPECT_EQ(t.steps_done(), 0u);
}

TEST(Checkpoint, ATruncatedOrAlteredCheckpointIsRefusedAsCorrupt) {
  Scene s;
  const std::string ckpt = checkpoint_after_3_steps(s, "corrupt.ckpt");
  const std::string good = read_bytes(ckpt);
  CheckpointKey key;
  EXPECT_EQ(parse_checkpoint(good, ckpt, key).step, 3u);
  EXPECT_EQ(key.dataset_hash, "dataset-a");

  auto refused = [&](const std::string& bytes, const std::string& why) {
    try {
      CheckpointKey k;
      parse_checkpoint(bytes, ckpt, k);
      ADD_FAILURE() << "accepted a checkpoint that should fail with " << why;
    } catch (const CheckpointCorrupt& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(why), std::string::npos) << m;
      EXPECT_NE(m.find("remove it to train from the start"), std::string::npos) << m;
    }
  };
  refused(good.substr(0, good.size() - 1000), "truncated");
  refused(good.substr(0, 12), "truncated");
  std::string blob = good;
  blob[blob.size() - 5] ^= 0x40;  // the last blob (occupancy density)
  refused(blob, "checksum mismatch in blob");
  std::string header = good;
  header[40] ^= 0x01;
  refused(header, "checksum mismatch in the header");
  refused("LGNNERF\n" + good.substr(8), "bad magic bytes");

  std::ofstream(ckpt, std::ios::binary) << good.substr(0, good.size() / 2);
  NerfModel fresh = s.make_model();
  Trainer t(fresh, s.train.views, options(ckpt), s.sizing.occupancy_mask);
  EXPECT_THROW(resume_training(t, options(ckpt), TrainJob::Resume::Required), CheckpointCorrupt);
  resume_training(t, options(ckpt), TrainJob::Resume::IfValid);
  EXPECT_EQ(t.steps_done(), 0u);
}

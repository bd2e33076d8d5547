// Tests of the training box choice (capture/subject_box.h): auto takes the dataset's aabb, else the
// alpha-mask hull, else the head box when faces are found, else the cameras (saying why); forced
// sources that do not apply fail clearly. Datasets are built in memory; the face case renders a
// small procedural-head dataset (a few seconds).
#include "capture/subject_box.h"

#include <gtest/gtest.h>

#include <cmath>

#include "face_dataset.h"
#include "host/nerf/background_field.h"
#include "kernels/train/render.h"
#include "synth/head_params.h"

namespace lorgnette::capture {
namespace {

// Four opaque grey frames with cameras on a small arc: no face anywhere.
dataset::Dataset blank_dataset(float alpha = 1.0f) {
  dataset::Dataset ds;
  ds.root = "memory";
  ds.format = "transforms";
  for (int i = 0; i < 4; ++i) {
    dataset::Frame f;
    f.name = "f" + std::to_string(i);
    f.camera.width = f.camera.height = 64;
    f.camera.fx = f.camera.fy = 64;
    f.camera.cx = f.camera.cy = 32;
    Eigen::Matrix4d c2w = Eigen::Matrix4d::Identity();
    c2w(0, 3) = 0.3 * i;
    c2w(2, 3) = 3.0;
    dataset::set_camera_pose(f.camera, c2w);
    f.image = Image(64, 64, 4, 0.5f);
    for (size_t p = 3; p < f.image.pixels.size(); p += 4) f.image.pixels[p] = alpha;
    ds.frames.push_back(std::move(f));
  }
  ds.has_alpha = alpha < 1.0f;
  return ds;
}

const dataset::Dataset& face_dataset() {
  static const dataset::Dataset ds = [] {
    dataset::LoadOptions lo;
    lo.splits = {dataset::Split::Train};
    return dataset::load_dataset(test::face_dataset_dir(), lo);
  }();
  return ds;
}

TEST(SubjectBox, AutoPrefersTheDatasetsBox) {
  dataset::Dataset ds = blank_dataset(0.0f);  // masks too: the aabb still wins
  ds.aabb = std::array<std::array<float, 3>, 2>{{{-1, -1, -1}, {1, 1, 1}}};
  SubjectBoxChoice c = choose_subject_box(ds, BoxSource::Auto);
  EXPECT_EQ(c.source, BoxSource::Dataset);
  ASSERT_TRUE(c.aabb.has_value());
  EXPECT_EQ((*c.aabb)[1][2], 1.0f);
  EXPECT_FALSE(c.zones.has_value()) << "a dataset's own box is not masked to a head";
}

TEST(SubjectBox, AutoUsesMasksThenFallsBackToCamerasWithoutFaces) {
  dataset::Dataset masked = blank_dataset(0.0f);
  SubjectBoxChoice c = choose_subject_box(masked, BoxSource::Auto);
  EXPECT_EQ(c.source, BoxSource::Masks);
  EXPECT_TRUE(c.use_masks);
  EXPECT_FALSE(c.aabb.has_value());
  // --no-masks: masks ignored; no face in grey frames -> cameras, and the reason is given.
  c = choose_subject_box(masked, BoxSource::Auto, false);
  EXPECT_EQ(c.source, BoxSource::Cameras);
  EXPECT_FALSE(c.use_masks);
  EXPECT_NE(c.why.find("face in 0 of the 4 photos"), std::string::npos) << c.why;
  // No face in a mask-less dataset: the subject cannot be separated, and the user is told what to film.
  EXPECT_NE(c.problem.find("no face was found"), std::string::npos) << c.problem;
  EXPECT_NE(c.problem.find("Film the face"), std::string::npos) << c.problem;
  // The masks separate the subject themselves; a box the user forces is their call.
  EXPECT_EQ(choose_subject_box(masked, BoxSource::Auto).problem, "");
  EXPECT_EQ(choose_subject_box(masked, BoxSource::Cameras, false).problem, "");
}

TEST(SubjectBox, AutoUsesTheHeadBoxWhenFacesAreFound) {
  SubjectBoxChoice c = choose_subject_box(face_dataset(), BoxSource::Auto);
  EXPECT_EQ(c.source, BoxSource::Head) << c.why;
  EXPECT_EQ(c.problem, "") << "the rendered head is framed with room around it";
  ASSERT_TRUE(c.aabb.has_value());
  // The procedural head is ~0.75 units wide (200 mm per unit): the box is a head, not a room.
  for (int a = 0; a < 3; ++a) {
    float extent = (*c.aabb)[1][a] - (*c.aabb)[0][a];
    EXPECT_GT(extent, 0.75f) << a;
    EXPECT_LT(extent, 2.5f) << a;
  }
  // The head's volume comes with it (capture/head_volume.h): inside the box, holding its middle,
  // and leaving out part of the box (its corners).
  ASSERT_TRUE(c.zones.has_value());
  nerf::Aabb box;
  box.min = (*c.aabb)[0], box.max = (*c.aabb)[1];
  EXPECT_TRUE(c.zones->volume.contains(box.center()));
  const uint64_t allowed = nerf::mask_count(nerf::volume_occupancy_mask(c.zones->volume, box, 32));
  EXPECT_GT(allowed, 32u * 32u * 32u / 4u);
  EXPECT_LT(allowed, 32u * 32u * 32u);
}

// The head box brings the skin's colours (capture/skin_colours.h), for the neck's clearing: up to 8
// chromaticities of the cheeks and the chin, each within 0.04 of the procedural skin albedo's (the
// cheeks' painted blush moves them up to ~0.03 towards red), every sample within 0.02 of one, and the grey
// background, neutral, matches none (kernels/train/render.h render_ray_skin_like at the tolerance
// train --neck-clear adds to the spread).
TEST(SubjectBox, TheHeadBoxCarriesTheSkinsColours) {
  SubjectBoxChoice c = choose_subject_box(face_dataset(), BoxSource::Auto);
  ASSERT_EQ(c.source, BoxSource::Head) << c.why;
  ASSERT_TRUE(c.zones.has_value());
  const nerf::SkinChroma& skin = c.zones->skin;
  ASSERT_GE(skin.chroma.size(), 2u);
  ASSERT_LE(skin.chroma.size(), size_t(SKIN_REFS_MAX));
  const Eigen::Vector3f albedo = synth::HeadParams{}.skin;
  const float r = albedo.x() / albedo.sum(), g = albedo.y() / albedo.sum();
  for (const auto& ref : skin.chroma)
    EXPECT_LT(std::hypot(ref[0] - r, ref[1] - g), 0.04f) << ref[0] << "," << ref[1];
  EXPECT_LT(skin.spread, 0.02f);
  EXPECT_GT(skin.lum_floor, 0.0f);
  std::vector<float> pairs;
  for (const auto& ref : skin.chroma) pairs.insert(pairs.end(), {ref[0], ref[1]});
  const float grey[3] = {0.5f, 0.5f, 0.5f};
  const uint32_t n = uint32_t(skin.chroma.size());
  EXPECT_FALSE(render_ray_skin_like(grey, pairs.data(), n, 0.02f + skin.spread, skin.lum_floor));
  const float shaded[3] = {0.3f * albedo.x(), 0.3f * albedo.y(), 0.3f * albedo.z()};
  EXPECT_TRUE(render_ray_skin_like(shaded, pairs.data(), n, 0.02f + skin.spread, skin.lum_floor));
}

// The head box brings the colours beside the neck where it leaves the box (SkinChroma::beside_neck),
// and training narrows the far-wall rule's body to the neck's column (nerf::neck_column)
// only before a wall that may be skin: the grey background matches no skin colour; the same head
// before a wall of its skin's albedo, at 80 % (a wall lit less than the face), is skin-like in every
// patch.
TEST(SubjectBox, TheWallBesideTheNeckDecidesTheNecksColumn) {
  const Eigen::Vector3f skin = synth::HeadParams{}.skin;
  const dataset::Dataset own = [&] {
    dataset::LoadOptions lo;
    lo.splits = {dataset::Split::Train};
    return dataset::load_dataset(synth::test::render_face_dataset("capture", "skin_wall", 6, 4, 0.8f * skin),
                                 lo);
  }();
  for (const dataset::Dataset* ds : {&face_dataset(), &own}) {
    const bool skin_wall = ds == &own;
    SubjectBoxChoice c = choose_subject_box(*ds, BoxSource::Auto);
    ASSERT_EQ(c.source, BoxSource::Head) << c.why;
    ASSERT_TRUE(c.zones.has_value() && c.zones->base.has_value());
    nerf::BackgroundOptions o;
    o.enabled = true;
    o.subject = c.zones;
    const nerf::NeckColumn column = nerf::neck_column(o);
    EXPECT_GE(column.patches, 8u) << "two sides, two heights and two distances, in the frontal views";
    EXPECT_EQ(column.skin_like, skin_wall ? column.patches : 0u) << (skin_wall ? "the skin's wall" : "grey");
    EXPECT_EQ(column.applies, skin_wall);
  }
}

// The head box's extents reach the choice (train --hair): more hair makes a taller and wider box,
// holding the default one.
TEST(SubjectBox, HeadOptionsSizeTheHeadBox) {
  fit::HeadBoxOptions tall;
  tall.extents.hair_mm = 150.0;
  SubjectBoxChoice c = choose_subject_box(face_dataset(), BoxSource::Head);
  SubjectBoxChoice t = choose_subject_box(face_dataset(), BoxSource::Head, true, tall);
  ASSERT_TRUE(c.aabb && t.aabb);
  double volume = 1.0, tall_volume = 1.0;
  for (int a = 0; a < 3; ++a) {
    EXPECT_LE((*t.aabb)[0][a], (*c.aabb)[0][a] + 1e-6f) << a;
    EXPECT_GE((*t.aabb)[1][a], (*c.aabb)[1][a] - 1e-6f) << a;
    volume *= (*c.aabb)[1][a] - (*c.aabb)[0][a];
    tall_volume *= (*t.aabb)[1][a] - (*t.aabb)[0][a];
  }
  // 120 mm more above and behind and 60 mm more on each side of a ~210 x 340 x 284 mm box: ~3x.
  EXPECT_GT(tall_volume, 2.4 * volume) << tall_volume / volume;  // 1.9x without the sides
}

TEST(SubjectBox, ForcedSourcesThatDoNotApplyFailClearly) {
  dataset::Dataset ds = blank_dataset();
  EXPECT_THROW(choose_subject_box(ds, BoxSource::Dataset), std::runtime_error);
  EXPECT_THROW(choose_subject_box(ds, BoxSource::Masks), std::runtime_error);
  try {
    choose_subject_box(ds, BoxSource::Head);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("face in 0 of the 4 photos tried"), std::string::npos) << e.what();
  }
  EXPECT_EQ(choose_subject_box(ds, BoxSource::Cameras).source, BoxSource::Cameras);
  EXPECT_EQ(box_source_from_string("head"), BoxSource::Head);
  EXPECT_THROW(box_source_from_string("room"), std::runtime_error);
}

}  // namespace
}  // namespace lorgnette::capture

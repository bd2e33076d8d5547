// Rebuilds a synthetic subject's mesh in a model's frame (see subject_mesh.h).
#include "subject_mesh.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "mesh/loader.h"
#include "synth/head_params.h"
#include "synth/studio_render.h"
#include "synth/subject.h"

namespace lorgnette::fit {
namespace {

// The same head parameters up to float rounding: the factor recovered from the two head widths
// (0.95 read back as 0.94999...) scales every length by a factor one ulp off the one synth used.
bool same_params(const nlohmann::json& a, const nlohmann::json& b) {
  if (a.size() != b.size()) return false;
  for (auto it = a.begin(); it != a.end(); ++it) {
    if (!b.contains(it.key())) return false;
    const nlohmann::json& v = b.at(it.key());
    if (it->is_number() && v.is_number()) {
      const double x = it->get<double>(), y = v.get<double>();
      if (std::abs(x - y) > 1e-5 * std::max(1.0, std::abs(y))) return false;
    } else if (*it != v) {
      return false;
    }
  }
  return true;
}

Eigen::Matrix4f matrix_from_json(const nlohmann::json& j) {
  Eigen::Matrix4f m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = j.at(r).at(c).get<float>();
  return m;
}

// The mesh lit as in the dataset (synth's studio lighting, fixed in the world frame; the model frame is
// the dataset frame scaled and shifted, so the light directions carry over) over white: the views
// dlib sees look like the NeRF's. MeshViewSource's own shading (a light at the camera) is kept with
// --gt-shading camera.
class StudioMeshSource : public MeshViewSource {
 public:
  using MeshViewSource::MeshViewSource;
  Image render(const Camera& cam) override {
    synth::RenderSettings rs;
    rs.samples_per_axis = 2;
    rs.background = Eigen::Vector3f(1.0f, 1.0f, 1.0f);
    Image rgba = synth::render_view(scene(), cam, synth::StudioLighting{}, rs).rgba;
    Image out(rgba.width, rgba.height, 3);
    for (size_t i = 0; i < size_t(out.width) * out.height; ++i)
      for (int c = 0; c < 3; ++c) out.pixels[i * 3 + c] = rgba.pixels[i * 4 + c];
    return out;
  }
};

// The dataset frame -> the model's (its normalisation: scale, then offset).
Eigen::Matrix4f dataset_to_model(const nerf::NerfModel& model) {
  Eigen::Matrix4f to_model = Eigen::Matrix4f::Identity();
  to_model.topLeftCorner<3, 3>() *= model.normalisation.scale;
  for (int i = 0; i < 3; ++i) to_model(i, 3) = model.normalisation.offset[i];
  return to_model;
}

}  // namespace

Anatomy anatomy_of(const std::string& dataset, const nerf::NerfModel& model) {
  Anatomy a;
  std::ifstream in(dataset + "/ground_truth.json");
  if (!in) return a;
  const nlohmann::json gt = nlohmann::json::parse(in);
  if (!gt.contains("landmarks") || !gt["landmarks"].contains("ear_rest_l") ||
      !gt["landmarks"].contains("ear_rest_r"))
    return a;
  const Eigen::Matrix4f to_model = dataset_to_model(model);
  auto point = [&](const nlohmann::json& p) {
    Eigen::Vector4f v(p.at(0).get<float>(), p.at(1).get<float>(), p.at(2).get<float>(), 1.0f);
    return Eigen::Vector3d((to_model * v).head<3>().cast<double>());
  };
  a.known = true;
  a.ear_l = point(gt["landmarks"]["ear_rest_l"]), a.ear_r = point(gt["landmarks"]["ear_rest_r"]);
  return a;
}

std::unique_ptr<MeshViewSource> subject_source(const std::string& dataset, const nerf::NerfModel& model,
                                               ViewPrior prior, bool studio) {
  std::ifstream in(dataset + "/ground_truth.json");
  if (!in)
    throw std::runtime_error(dataset +
                             "/ground_truth.json is missing: the case must be a `lorgnette synth` dataset");
  nlohmann::json gt = nlohmann::json::parse(in);
  mesh::TriMesh m;
  if (gt.at("source") == "procedural") {
    // `synth --head-scale` scales the seed's lengths; the factor is the two head widths' ratio (the
    // parameters' comparison below checks it).
    const synth::HeadParams seeded = synth::random_head_params(gt.at("seed").get<uint64_t>());
    const float factor = gt.at("params").at("head_width").get<float>() / seeded.head_width;
    synth::Subject s = synth::procedural_subject(
        std::abs(factor - 1.0f) < 1e-6f ? seeded : synth::scale_head(seeded, factor));
    if (!same_params(nlohmann::json(s.params), gt.at("params")))
      throw std::runtime_error("the procedural head of seed " + gt.at("seed").dump() +
                               " differs from the dataset's");
    m = std::move(s.mesh);
  } else {
    m = mesh::load_mesh(gt.at("source").get<std::string>());
  }
  const Eigen::Matrix4f to_scene = dataset_to_model(model) * matrix_from_json(gt.at("mesh_to_dataset"));
  if (studio) return std::make_unique<StudioMeshSource>(std::move(m), to_scene, prior);
  return std::make_unique<MeshViewSource>(std::move(m), to_scene, prior);
}

}  // namespace lorgnette::fit

// Assimp-backed mesh loading into TriMesh; see loader.h. The node hierarchy is walked by hand
// (instead of aiProcess_PreTransformVertices) so that every mesh instance keeps its own named part.
#include "mesh/loader.h"

#include <assimp/BaseImporter.h>
#include <assimp/GltfMaterial.h>
#include <assimp/commonMetaData.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <assimp/IOStream.hpp>
#include <assimp/IOSystem.hpp>
#include <assimp/Importer.hpp>
#include <cctype>
#include <filesystem>
#include <map>
#include <set>
#include <stdexcept>

#include "host/util/file_kind.h"
#include "mesh/file_checks.h"
#include "mesh/texture.h"

namespace lorgnette::mesh {
namespace fs = std::filesystem;
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

struct LoadContext {
  const aiScene* scene = nullptr;
  fs::path dir;
  bool external_files = true;  // false for a mesh loaded from memory: only embedded textures
  LoadOptions options;
  LoadReport* report = nullptr;
  std::map<std::string, int> texture_index;  // texture path -> TriMesh::textures index
  std::map<std::string, int> part_count;     // for unique part names
  TriMesh mesh;

  void warn(const std::string& msg) {
    spdlog::warn("{}", msg);
    if (report) report->warnings.push_back(msg);
  }
};

Image embedded_texture(const aiTexture* t, const std::string& what) {
  if (t->mHeight == 0)
    return decode_image_bytes(reinterpret_cast<const unsigned char*>(t->pcData), t->mWidth, what);
  Image im(static_cast<int>(t->mWidth), static_cast<int>(t->mHeight), 4);
  for (size_t i = 0; i < static_cast<size_t>(t->mWidth) * t->mHeight; ++i) {
    const aiTexel& p = t->pcData[i];
    im.pixels[4 * i + 0] = srgb_to_linear(p.r / 255.0f);
    im.pixels[4 * i + 1] = srgb_to_linear(p.g / 255.0f);
    im.pixels[4 * i + 2] = srgb_to_linear(p.b / 255.0f);
    im.pixels[4 * i + 3] = p.a / 255.0f;
  }
  return im;
}

// Returns the TriMesh texture index for the material's base-colour texture, or -1 (with a warning
// when the file names a texture that cannot be read).
int load_base_texture(LoadContext& ctx, const aiMaterial* m) {
  aiString path;
  if (m->GetTexture(aiTextureType_BASE_COLOR, 0, &path) != AI_SUCCESS &&
      m->GetTexture(aiTextureType_DIFFUSE, 0, &path) != AI_SUCCESS)
    return -1;
  std::string key = path.C_Str();
  if (auto it = ctx.texture_index.find(key); it != ctx.texture_index.end()) return it->second;
  int index = -1;
  try {
    Image im;
    if (const aiTexture* t = ctx.scene->GetEmbeddedTexture(key.c_str())) {
      im = embedded_texture(t, fmt::format("embedded texture '{}'", key));
    } else if (!ctx.external_files) {
      throw std::runtime_error("an external file, not available to a mesh loaded from memory");
    } else {
      fs::path p = ctx.dir / fs::u8path(key);
      im = read_image(p.string());
    }
    ctx.mesh.textures.push_back(downsample_to(im, ctx.options.max_texture_size));
    index = static_cast<int>(ctx.mesh.textures.size()) - 1;
  } catch (const std::exception& e) {
    ctx.warn(fmt::format("texture '{}' skipped ({}); the material uses its base colour only", key, e.what()));
  }
  ctx.texture_index[key] = index;
  return index;
}

Material convert_material(LoadContext& ctx, const aiMaterial* m) {
  Material out;
  aiString name;
  if (m->Get(AI_MATKEY_NAME, name) == AI_SUCCESS) out.name = name.C_Str();
  aiColor4D base(0.8f, 0.8f, 0.8f, 1.0f);
  if (m->Get(AI_MATKEY_BASE_COLOR, base) != AI_SUCCESS) m->Get(AI_MATKEY_COLOR_DIFFUSE, base);
  out.base_color = {base.r, base.g, base.b};
  m->Get(AI_MATKEY_METALLIC_FACTOR, out.metallic);
  m->Get(AI_MATKEY_ROUGHNESS_FACTOR, out.roughness);
  aiString mode;
  std::string alpha_mode = m->Get(AI_MATKEY_GLTF_ALPHAMODE, mode) == AI_SUCCESS ? mode.C_Str() : "";
  float opacity = 1.0f;
  if (m->Get(AI_MATKEY_OPACITY, opacity) != AI_SUCCESS) opacity = base.a;
  out.alpha = alpha_mode == "OPAQUE" ? 1.0f : std::clamp(std::min(opacity, base.a), 0.0f, 1.0f);
  m->Get(AI_MATKEY_TRANSMISSION_FACTOR, out.transmission);
  float ior = 0.0f;
  if (m->Get(AI_MATKEY_REFRACTI, ior) == AI_SUCCESS && ior >= 1.0f) out.ior = ior;
  aiColor3D attenuation(1, 1, 1);
  // glTF: transmitted light is tinted by the base colour (and the volume's attenuation colour).
  if (out.transmission > 0.0f) {
    out.tint = out.base_color;
    if (m->Get(AI_MATKEY_VOLUME_ATTENUATION_COLOR, attenuation) == AI_SUCCESS)
      out.tint = out.tint.cwiseProduct(Eigen::Vector3f(attenuation.r, attenuation.g, attenuation.b));
  }
  out.roughness = std::clamp(out.roughness, 0.0f, 1.0f);
  out.metallic = std::clamp(out.metallic, 0.0f, 1.0f);
  out.transmission = std::clamp(out.transmission, 0.0f, 1.0f);
  if (ctx.options.load_textures) out.base_color_texture = load_base_texture(ctx, m);
  out.is_lens = looks_like_lens(out, alpha_mode);
  if (out.is_lens && out.transmission == 0.0f && out.alpha >= 0.99f) {
    // A lens by name but modelled opaque (common in exports): treat it as clear glass tinted by its
    // base colour, otherwise it would hide the eyes.
    out.transmission = 1.0f;
    out.tint = out.base_color;
    ctx.warn(fmt::format("material '{}' looks like a lens but is opaque: rendered as clear glass", out.name));
  }
  return out;
}

std::string unique_part_name(LoadContext& ctx, std::string name) {
  if (name.empty()) name = "part";
  int n = ctx.part_count[name]++;
  return n == 0 ? name : fmt::format("{}#{}", name, n);
}

void append_mesh(LoadContext& ctx, const aiMesh* am, const aiMatrix4x4& xf, const std::string& node_name) {
  TriMesh& tm = ctx.mesh;
  if (!am->HasFaces() || am->mNumVertices == 0) return;
  int part = static_cast<int>(tm.part_names.size());
  tm.part_names.push_back(unique_part_name(ctx, am->mName.length > 0 ? am->mName.C_Str() : node_name));
  int base = static_cast<int>(tm.positions.size());
  aiMatrix3x3 nxf = aiMatrix3x3(xf);
  nxf.Inverse().Transpose();
  for (unsigned i = 0; i < am->mNumVertices; ++i) {
    aiVector3D p = xf * am->mVertices[i];
    tm.positions.emplace_back(p.x, p.y, p.z);
    aiVector3D n = am->HasNormals() ? (nxf * am->mNormals[i]).NormalizeSafe() : aiVector3D(0, 0, 0);
    tm.normals.emplace_back(n.x, n.y, n.z);
    aiVector3D uv = am->HasTextureCoords(0) ? am->mTextureCoords[0][i] : aiVector3D(0, 0, 0);
    tm.uvs.emplace_back(uv.x, uv.y);
  }
  for (unsigned f = 0; f < am->mNumFaces; ++f) {
    const aiFace& face = am->mFaces[f];
    if (face.mNumIndices != 3) continue;
    Eigen::Vector3i t(base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]);
    Eigen::Vector3f e =
        (tm.positions[t[1]] - tm.positions[t[0]]).cross(tm.positions[t[2]] - tm.positions[t[0]]);
    if (!(e.squaredNorm() > 0.0f)) {  // also rejects NaN
      if (ctx.report) ctx.report->degenerate_triangles++;
      continue;
    }
    tm.triangles.push_back(t);
    tm.triangle_material.push_back(static_cast<int>(am->mMaterialIndex));
    tm.triangle_part.push_back(part);
  }
}

void walk(LoadContext& ctx, const aiNode* node, const aiMatrix4x4& parent) {
  aiMatrix4x4 xf = parent * node->mTransformation;
  for (unsigned i = 0; i < node->mNumMeshes; ++i)
    append_mesh(ctx, ctx.scene->mMeshes[node->mMeshes[i]], xf, node->mName.C_Str());
  for (unsigned c = 0; c < node->mNumChildren; ++c) walk(ctx, node->mChildren[c], xf);
}

// Post-processing shared by both entry points (and the property it reads).
unsigned import_flags(Assimp::Importer& importer, const LoadOptions& options) {
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType |
                   aiProcess_FlipUVs | aiProcess_ValidateDataStructure;
  if (options.generate_normals) flags |= aiProcess_GenSmoothNormals;
  return flags;
}

// Recomputes each mesh's primitive types from its faces, and refuses faces without vertices.
// Assimp 5.2's PLY reader can make such faces and flag polygons a mesh does not have; both pass
// its validation, and its triangulation then aborts the whole process on an assertion
// (fuzz/regressions/glasses/ply-empty-face-abort).
void check_faces(const aiScene* scene, const std::string& path) {
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    aiMesh* mesh = scene->mMeshes[m];
    unsigned types = 0;
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      unsigned n = mesh->mFaces[f].mNumIndices;
      if (n == 0)
        throw std::runtime_error(
            fmt::format("mesh file '{}' is corrupt: face {} of mesh {} has no vertices", path, f, m));
      types |= n == 1   ? aiPrimitiveType_POINT
               : n == 2 ? aiPrimitiveType_LINE
               : n == 3 ? aiPrimitiveType_TRIANGLE
                        : aiPrimitiveType_POLYGON;
    }
    mesh->mPrimitiveTypes = types;
  }
}

// The scene Assimp read (with aiProcess_ValidateDataStructure only: faces are known to be sane),
// post-processed with `flags`; throws naming `path` when reading or post-processing failed.
const aiScene* post_process(Assimp::Importer& importer, const aiScene* scene, unsigned flags,
                            const std::string& path) {
  if (scene != nullptr) {
    check_faces(scene, path);
    scene = importer.ApplyPostProcessing(flags & ~aiProcess_ValidateDataStructure);
  }
  if (scene == nullptr)
    throw std::runtime_error(
        fmt::format("cannot load mesh '{}': {} (is it a valid glTF 2.0 / OBJ / PLY file?)", path,
                    importer.GetErrorString()));
  if (scene->mRootNode == nullptr || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
    throw std::runtime_error(fmt::format("mesh file '{}' is incomplete (no scene graph or geometry)", path));
  return scene;
}

// Leaves Assimp only the importers for extension `ext` (glTF 1 and 2 for gltf and glb). Otherwise a
// file its own importer refuses goes to whichever of Assimp's ~40 importers claims its first bytes:
// a PLY named .gltf reached the PLY reader past check_file and hung it
// (fuzz/regressions/glasses/ply-named-gltf-hang). Other extensions keep every importer.
void keep_importers_for(Assimp::Importer& importer, const std::string& ext) {
  if (ext != "gltf" && ext != "glb" && ext != "obj" && ext != "ply") return;
  std::vector<Assimp::BaseImporter*> others;
  for (size_t i = 0; i < importer.GetImporterCount(); ++i) {
    std::set<std::string> extensions;
    importer.GetImporter(i)->GetExtensionList(extensions);
    if (!extensions.count(ext)) others.push_back(importer.GetImporter(i));
  }
  for (Assimp::BaseImporter* other : others) {
    importer.UnregisterLoader(other);
    delete other;  // unregistering hands it back
  }
}

// What Assimp must not see (file_checks.h): a malformed PLY, a GLB whose lengths do not fit the
// file, glTF primitive modes it crashes on.
void check_file(std::string_view bytes, const std::string& ext, const std::string& name) {
  if (ext == "ply") check_ply(bytes, name);
  if (ext == "glb" || ext == "gltf") check_gltf(bytes, name);
}

const aiScene* read_scene(Assimp::Importer& importer, const std::string& path, const LoadOptions& options) {
  if (!fs::exists(path))
    throw std::runtime_error(fmt::format("mesh file '{}' does not exist (check the path)", path));
  if (fs::is_directory(path))
    throw std::runtime_error(
        fmt::format("'{}' is a directory; give the .gltf/.glb/.obj/.ply file inside it", path));
  if (fs::file_size(path) == 0)
    throw std::runtime_error(fmt::format("mesh file '{}' is empty (0 bytes)", path));
  std::string ext = lower(fs::path(path).extension().string());
  ext = ext.empty() ? ext : ext.substr(1);
  if (ext == "ply" || ext == "glb" || ext == "gltf") {
    check_file(read_regular_file(path, "mesh file"), ext, path);
  }
  keep_importers_for(importer, ext);
  unsigned flags = import_flags(importer, options);
  return post_process(importer, importer.ReadFile(path, aiProcess_ValidateDataStructure), flags, path);
}

// A file system with no files: a mesh read from memory must not open files beside it (an .mtl, a
// .gltf's buffers), which Assimp would otherwise look for relative to the working directory.
class NoFiles : public Assimp::IOSystem {
 public:
  bool Exists(const char*) const override { return false; }
  char getOsSeparator() const override { return '/'; }
  Assimp::IOStream* Open(const char*, const char*) override { return nullptr; }
  void Close(Assimp::IOStream* stream) override { delete stream; }
};

}  // namespace

bool looks_like_lens(const Material& m, const std::string& alpha_mode) {
  std::string n = lower(m.name);
  for (const char* not_lens : {"nose", "pad", "frame", "temple", "hinge", "screw"})
    if (n.find(not_lens) != std::string::npos) return false;
  for (const char* lens : {"lens", "glass", "vidro", "lente", "verre", "tinted", "transparent"})
    if (n.find(lens) != std::string::npos) return true;
  if (m.transmission > 0.05f) return true;
  return alpha_mode == "BLEND" && m.alpha < 0.6f && m.base_color_texture < 0;
}

bool uv_flip_for_generator(const std::string& generator) { return generator == "probe js2glb.py"; }

namespace {

// Applies LoadOptions::flip_v to the loaded UVs (v -> 1 - v), saying so in the report.
void fix_uv_convention(LoadContext& ctx, const std::string& path) {
  bool flip = ctx.options.flip_v == FlipV::kYes;
  aiString generator;
  if (ctx.options.flip_v == FlipV::kAuto && ctx.scene->mMetaData != nullptr &&
      ctx.scene->mMetaData->Get(AI_METADATA_SOURCE_GENERATOR, generator))
    flip = uv_flip_for_generator(generator.C_Str());
  if (!flip || ctx.mesh.uvs.empty()) return;
  for (Eigen::Vector2f& uv : ctx.mesh.uvs) uv.y() = 1.0f - uv.y();
  if (ctx.options.flip_v != FlipV::kAuto) return;
  std::string msg =
      fmt::format("'{}': generator '{}' stores OpenGL-convention UVs; flipped v", path, generator.C_Str());
  spdlog::info("{}", msg);
  if (ctx.report) ctx.report->warnings.push_back(msg);
}

// The TriMesh of an imported scene; `name` (the path) for messages, `ext` for the unit.
TriMesh convert_scene(LoadContext& ctx, const std::string& name, const std::string& ext) {
  for (unsigned i = 0; i < ctx.scene->mNumMaterials; ++i)
    ctx.mesh.materials.push_back(convert_material(ctx, ctx.scene->mMaterials[i]));
  if (ctx.mesh.materials.empty()) ctx.mesh.materials.push_back(Material{"default"});
  walk(ctx, ctx.scene->mRootNode, aiMatrix4x4());
  TriMesh& tm = ctx.mesh;
  if (tm.triangles.empty())
    throw std::runtime_error(
        fmt::format("mesh file '{}' contains no triangles (empty mesh, or only points/lines)", name));
  bool any_normal = std::any_of(tm.normals.begin(), tm.normals.end(),
                                [](const Eigen::Vector3f& n) { return n.squaredNorm() > 0; });
  if (!any_normal) tm.normals.clear();
  bool any_uv = std::any_of(ctx.mesh.materials.begin(), ctx.mesh.materials.end(),
                            [](const Material& m) { return m.base_color_texture >= 0; });
  if (!any_uv) tm.uvs.clear();
  fix_uv_convention(ctx, name);
  tm.units_to_mm = (ext == ".gltf" || ext == ".glb") ? 1000.0 : 1.0;  // glTF is metres by specification
  if (ctx.report && ctx.report->degenerate_triangles > 0)
    ctx.warn(fmt::format("'{}': dropped {} degenerate (zero-area) triangles", name,
                         ctx.report->degenerate_triangles));
  return std::move(ctx.mesh);
}

}  // namespace

TriMesh load_mesh(const std::string& path, const LoadOptions& options, LoadReport* report) {
  Assimp::Importer importer;
  LoadContext ctx;
  ctx.scene = read_scene(importer, path, options);
  ctx.dir = fs::path(path).parent_path();
  ctx.options = options;
  ctx.report = report;
  return convert_scene(ctx, path, lower(fs::path(path).extension().string()));
}

TriMesh load_mesh_from_memory(const void* data, size_t bytes, const std::string& format,
                              const LoadOptions& options, LoadReport* report) {
  std::string ext = lower(format);
  if (ext != "gltf" && ext != "glb" && ext != "obj" && ext != "ply")
    throw std::runtime_error(fmt::format("mesh format '{}' is not one of gltf, glb, obj, ply", format));
  std::string name = fmt::format("<{} bytes of {}>", bytes, ext);
  if (bytes == 0) throw std::runtime_error(fmt::format("mesh '{}' is empty (0 bytes)", name));
  check_file(std::string_view(static_cast<const char*>(data), bytes), ext, name);
  Assimp::Importer importer;
  importer.SetIOHandler(new NoFiles);  // the importer owns it
  keep_importers_for(importer, ext);
  unsigned flags = import_flags(importer, options);
  LoadContext ctx;
  const aiScene* read =
      importer.ReadFileFromMemory(data, bytes, aiProcess_ValidateDataStructure, ext.c_str());
  ctx.scene = post_process(importer, read, flags, name);
  ctx.external_files = false;
  ctx.options = options;
  ctx.report = report;
  return convert_scene(ctx, name, "." + ext);
}

}  // namespace lorgnette::mesh

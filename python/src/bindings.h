// Shared pieces of the `lorgnette` Python module (pybind11): the OpenCL runtime per device (one per
// process and device, shared by the models on it, one piece of device work at a time), the Model
// handle, NumPy <-> image conversion, and the binders each bind_*.cpp defines.
#pragma once
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>

#include "fit/placement_json.h"
#include "host/cl/runtime.h"
#include "host/nerf/model.h"
#include "host/render/renderer.h"
#include "host/util/bounds.h"
#include "host/util/image_io.h"
#include "mesh/glasses.h"
#include "mesh/placed_glasses.h"

namespace lorgnette::py {

namespace pyb = pybind11;

// One OpenCL runtime (context + queue + kernel cache). Device work holds `mutex` (with the GIL
// released), so Python threads may share a model without racing on its buffers.
struct Device {
  explicit Device(const cl::RuntimeOptions& options) : runtime(options) {}
  cl::Runtime runtime;
  std::mutex mutex;
};

// The runtime for a --device spec ("" = the module's current choice, see lorgnette.use_device).
std::shared_ptr<Device> device_for(const std::string& spec);

// A loaded or trained model; keeps its runtime alive (the model's buffers live in its context).
struct Model {
  std::shared_ptr<Device> device;
  std::unique_ptr<nerf::NerfModel> nerf;
  std::string path;                            // the .lnerf it came from or was saved to
  std::unique_ptr<render::Renderer> renderer;  // made on the first render (builds the marcher)
};

// A frame in canonical millimetres, with the surface pass of its last placement kept for the
// next render (building the Embree scene is the costly part of a glasses render).
struct Glasses {
  mesh::Glasses glasses;
  std::mutex mutex;  // guards the cache below
  std::shared_ptr<mesh::PlacedGlasses> placed;
  std::string placed_key;  // transform + temples it was built for
};

// placement.json in memory, as the placement module reads and writes it (fit/placement_json.h):
// its glasses path is one this process opens (Placement.load resolves a relative one against the
// file's folder, save() stores it relative to the new file's folder).
struct Placement {
  fit::PlacementFile file;
};

// A 4x4 NumPy-like object as a placement transform (canonical mm -> scene); ValueError naming `what`
// when it is not 4x4 or not a sane affine transform (fit::check_transform, as every reader checks).
Eigen::Matrix4d placement_matrix(const pyb::handle& obj, const std::string& what);

// Warns (Python's UserWarning) when the placement was fitted for another glasses file.
void warn_glasses_mismatch(const fit::PlacementFile& p, const std::string& glasses_path);

// Glasses.load (releases the GIL while loading).
std::shared_ptr<Glasses> load_glasses(const std::string& path, double mm_per_unit = 0.0);

// JSON -> Python objects (through the json module) and back.
pyb::object to_python(const nlohmann::json& j);
nlohmann::json from_python(const pyb::handle& obj);

// The Error type (a RuntimeError) carrying the library's messages, and LandmarkError (an Error).
pyb::handle error_type();
pyb::handle landmark_error_type();

// Number arguments checked against their Bound (host/util/bounds.h), so Python refuses exactly what
// the CLI refuses, with the CLI's words: a TypeError naming the argument for something that is not a
// real number (a bool, a string, None), lorgnette.RangeError (an Error and a ValueError) outside the
// range, NaN included. count_arg also wants a whole number (an int, or a float without a fraction).
double number_arg(const pyb::handle& obj, const Bound& bound);
uint64_t count_arg(const pyb::handle& obj, const Bound& bound);
uint64_t count_arg_or_zero(const pyb::handle& obj, const Bound& bound);  // 0: automatic

// Raises FileNotFoundError (as the CLI's "File does not exist" check) when `path` is missing.
void require_file(const std::string& path, const char* what);

// Linear float image -> float32 NumPy array (H x W x C, or H x W when C == 1); copies.
pyb::array_t<float> to_numpy(const Image& image);
// A float NumPy array (H x W or H x W x C) -> linear float image; copies.
Image from_numpy(const pyb::array_t<float, pyb::array::c_style | pyb::array::forcecast>& array);

void bind_model(pyb::module_& m);
void bind_glasses(pyb::module_& m);
void bind_fit(pyb::module_& m);
void bind_train(pyb::module_& m);

}  // namespace lorgnette::py

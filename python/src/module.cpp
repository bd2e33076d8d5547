// The `lorgnette._lorgnette` extension module: errors (the library's messages as lorgnette.Error),
// logging, OpenCL devices and the runtime per device, image IO and conversion to what the CLI
// writes, and the binders of models, glasses, the fit and training (bind_*.cpp).
#include <OpenImageIO/imageio.h>
#include <fmt/format.h>
#include <pybind11/stl.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <new>

#include "host/cl/device.h"
#include "host/render/render_job.h"
#include "host/util/version.h"
#include "python/src/bindings.h"

namespace lorgnette::py {
namespace {

pyb::handle g_error, g_landmark_error, g_range_error;  // owned for the process (never freed at exit)
std::mutex g_devices_mutex;
std::map<std::string, std::weak_ptr<Device>> g_devices;  // by resolved device index
std::string g_device_spec;                               // lorgnette.use_device

pyb::dict device_dict(const cl::DeviceInfo& d, int chosen) {
  pyb::dict out;
  out["index"] = d.index, out["name"] = d.name, out["platform"] = d.platform_name;
  out["vendor"] = d.vendor, out["type"] = d.type_name(), out["version"] = d.version;
  out["driver"] = d.driver_version, out["compute_units"] = d.compute_units;
  out["global_mem_bytes"] = d.global_mem_bytes, out["selected"] = d.index == chosen;
  return out;
}

std::string env_or(const char* name, const std::string& fallback) {
  const char* v = std::getenv(name);
  return v && *v ? v : fallback;
}

// The spec `lorgnette` would use: the argument, else use_device(), else $LORGNETTE_DEVICE (as the CLI).
std::string effective_spec(const std::string& spec) {
  if (!spec.empty()) return spec;
  if (!g_device_spec.empty()) return g_device_spec;
  return env_or("LORGNETTE_DEVICE", "");
}

// Reads an image's stored values (8-bit files as uint8, others as float32), without conversion.
pyb::array raw_image(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  if (!in)
    throw std::runtime_error(
        fmt::format("cannot read image '{}': {}", path, decode_error_text(OIIO::geterror())));
  const OIIO::ImageSpec& spec = in->spec();
  const bool u8 = spec.format == OIIO::TypeDesc::UINT8;
  std::vector<pyb::ssize_t> shape{spec.height, spec.width, spec.nchannels};
  pyb::array out =
      u8 ? pyb::array(pyb::dtype::of<uint8_t>(), shape) : pyb::array(pyb::dtype::of<float>(), shape);
  bool ok = in->read_image(0, 0, 0, spec.nchannels, u8 ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT,
                           out.mutable_data());
  if (!ok || in->has_error())
    throw std::runtime_error(
        fmt::format("cannot read image '{}': {}", path, decode_error_text(in->geterror())));
  return out;
}

// The 8-bit sRGB pixels `lorgnette render` writes to frame_NNNN.png for a render's RGBA: the same
// to_output_image and the same encoding and float -> uint8 conversion as write_image.
pyb::array_t<uint8_t> srgb8(const pyb::array_t<float, pyb::array::c_style | pyb::array::forcecast>& rgba,
                            bool alpha) {
  Image in = from_numpy(rgba);
  if (in.channels != 4) throw pyb::value_error("to_srgb8: expected an H x W x 4 RGBA array (Model.render)");
  Image img = render::to_output_image(in, alpha);
  std::vector<float> data(img.pixels.size());
  for (size_t i = 0; i < data.size(); ++i) {
    const bool colour = int(i % size_t(img.channels)) < 3;
    data[i] = colour ? linear_to_srgb(img.pixels[i]) : std::clamp(img.pixels[i], 0.0f, 1.0f);
  }
  pyb::array_t<uint8_t> out({pyb::ssize_t(img.height), pyb::ssize_t(img.width), pyb::ssize_t(img.channels)});
  OIIO::convert_pixel_values(OIIO::TypeDesc::FLOAT, data.data(), OIIO::TypeDesc::UINT8, out.mutable_data(),
                             int(data.size()));
  return out;
}

void save_image(const std::string& path, const pyb::array& image) {
  if (image.dtype().is(pyb::dtype::of<uint8_t>())) {  // already 8-bit sRGB: written as is
    auto a = pyb::array_t<uint8_t, pyb::array::c_style>::ensure(image);
    if (a.ndim() != 3 && a.ndim() != 2) throw pyb::value_error("save_image: expected H x W or H x W x C");
    const int c = a.ndim() == 3 ? int(a.shape(2)) : 1;
    write_srgb8_image(path, int(a.shape(1)), int(a.shape(0)), c, a.data());
    return;
  }
  write_image(path,
              from_numpy(image.cast<pyb::array_t<float, pyb::array::c_style | pyb::array::forcecast>>()));
}

}  // namespace

pyb::handle error_type() { return g_error; }
pyb::handle landmark_error_type() { return g_landmark_error; }

namespace {

// The value of a real-number argument (any range), or a TypeError naming it.
double real_arg(const pyb::handle& obj, const Bound& bound) {
  // bool is an int in Python, but True for a count is a mistake, not a 1.
  const bool number = PyFloat_Check(obj.ptr()) || PyLong_Check(obj.ptr()) ||
                      (!PyUnicode_Check(obj.ptr()) && PyObject_HasAttrString(obj.ptr(), "__float__"));
  if (PyBool_Check(obj.ptr()) || !number)
    throw pyb::type_error(fmt::format("{} must be a number, found {} ({})", bound_name(bound),
                                      std::string(pyb::repr(obj)).substr(0, 40),
                                      Py_TYPE(obj.ptr())->tp_name));
  double v = PyFloat_AsDouble(obj.ptr());
  if (v == -1.0 && PyErr_Occurred()) {
    PyErr_Clear();
    if (!PyLong_Check(obj.ptr()))  // __float__ failed (e.g. an array of several numbers)
      throw pyb::type_error(fmt::format("{} must be a single number, found {}", bound_name(bound),
                                        std::string(pyb::repr(obj)).substr(0, 40)));
    // An int beyond a double's range: infinite, so the range check names it.
    return PyObject_RichCompareBool(obj.ptr(), pyb::int_(0).ptr(), Py_LT) == 1 ? -HUGE_VAL : HUGE_VAL;
  }
  return v;
}

}  // namespace

double number_arg(const pyb::handle& obj, const Bound& bound) {
  return check_bound(bound, real_arg(obj, bound));
}

uint64_t count_arg(const pyb::handle& obj, const Bound& bound) {
  double v = number_arg(obj, bound);
  if (v != std::floor(v))
    throw OutOfRange(fmt::format("{} must be a whole number within {:g}..{:g} ({}), found {:g}",
                                 bound_name(bound), bound.lo, bound.hi, bound.what, v));
  return uint64_t(v);
}

uint64_t count_arg_or_zero(const pyb::handle& obj, const Bound& bound) {
  return real_arg(obj, bound) == 0.0 ? 0 : count_arg(obj, bound);
}

void require_file(const std::string& path, const char* what) {
  if (std::filesystem::is_regular_file(path)) return;
  PyErr_SetString(PyExc_FileNotFoundError, fmt::format("{}: File does not exist: {}", what, path).c_str());
  throw pyb::error_already_set();
}

std::shared_ptr<Device> device_for(const std::string& spec) {
  std::string s = effective_spec(spec);
  cl::DeviceInfo info = cl::select_device(s);  // throws with the CLI's message for a bad spec
  std::lock_guard<std::mutex> lock(g_devices_mutex);
  std::string key = std::to_string(info.index);
  if (auto d = g_devices[key].lock()) return d;
  cl::RuntimeOptions o;
  o.device = key;
  o.cache_dir = env_or("LORGNETTE_KERNEL_CACHE", "");
  auto d = std::make_shared<Device>(o);
  g_devices[key] = d;
  return d;
}

pyb::array_t<float> to_numpy(const Image& image) {
  std::vector<pyb::ssize_t> shape{image.height, image.width};
  if (image.channels != 1) shape.push_back(image.channels);
  pyb::array_t<float> out(shape);
  std::copy(image.pixels.begin(), image.pixels.end(), out.mutable_data());
  return out;
}

Image from_numpy(const pyb::array_t<float, pyb::array::c_style | pyb::array::forcecast>& a) {
  if (a.ndim() != 2 && a.ndim() != 3) throw pyb::value_error("expected an H x W or H x W x C image array");
  Image img(int(a.shape(1)), int(a.shape(0)), a.ndim() == 3 ? int(a.shape(2)) : 1);
  std::copy(a.data(), a.data() + a.size(), img.pixels.begin());
  return img;
}

pyb::object to_python(const nlohmann::json& j) {
  return pyb::module_::import("json").attr("loads")(j.dump());
}

nlohmann::json from_python(const pyb::handle& obj) {
  return nlohmann::json::parse(pyb::module_::import("json").attr("dumps")(obj).cast<std::string>());
}

namespace {

// lorgnette.Error (the library's messages), LandmarkError (an Error) and RangeError (an Error and a
// ValueError, for a number outside its range in host/util/bounds.h, as Python's own checks raise),
// and the translator that maps the library's C++ exceptions onto them.
void register_errors(pyb::module_& m) {
  g_error = pyb::exception<std::exception>(m, "Error", PyExc_RuntimeError).release();
  g_landmark_error = pyb::exception<std::exception>(m, "LandmarkError", g_error.ptr()).release();
  g_range_error = PyErr_NewExceptionWithDoc(
      "lorgnette._lorgnette.RangeError",
      "A number outside its range (the CLI's message); both a lorgnette.Error and a ValueError.",
      pyb::make_tuple(g_error, pyb::handle(PyExc_ValueError)).release().ptr(), nullptr);
  if (!g_range_error) throw pyb::error_already_set();
  m.attr("RangeError") = g_range_error;
  pyb::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const OutOfRange& e) {
      PyErr_SetString(g_range_error.ptr(), e.what());
    } catch (const std::bad_alloc& e) {
      PyErr_SetString(PyExc_MemoryError, e.what());
    } catch (const pyb::builtin_exception& e) {
      e.set_error();
    } catch (const std::exception& e) {  // the messages `lorgnette` prints after "error: "
      PyErr_SetString(g_error.ptr(), e.what());
    }
  });
}

// Messages go to stderr as the CLI's do; warnings and errors only unless asked.
void bind_logging(pyb::module_& m) {
  if (!spdlog::get("lorgnette")) spdlog::set_default_logger(spdlog::stderr_color_mt("lorgnette"));
  spdlog::set_pattern("lorgnette: %^%l%$: %v");
  spdlog::set_level(spdlog::level::warn);
  m.def(
      "set_log_level",
      [](const std::string& level) {
        auto l = spdlog::level::from_str(level);
        if (l == spdlog::level::off && level != "off")
          throw pyb::value_error("log level must be trace, debug, info, warning, error, critical or off");
        spdlog::set_level(l);
      },
      pyb::arg("level"), "Log level of the library's messages on stderr (default 'warning').");
}

void bind_devices(pyb::module_& m) {
  m.def(
      "devices",
      [] {
        auto all = cl::list_devices();
        int chosen = cl::select_device(effective_spec("")).index;
        pyb::list out;
        for (const auto& d : all) out.append(device_dict(d, chosen));
        return out;
      },
      "Every OpenCL device (as `lorgnette devices --json`); 'selected' marks the one in use.");
  m.def(
      "use_device",
      [](const std::string& spec) {
        cl::DeviceInfo d = cl::select_device(spec);  // validates
        g_device_spec = spec;
        return device_dict(d, d.index);
      },
      pyb::arg("spec"),
      "Chooses the device for models loaded or trained from now on: an index or part of a name.");
  m.def(
      "device",
      [] {
        cl::DeviceInfo d = cl::select_device(effective_spec(""));
        return device_dict(d, d.index);
      },
      "The device in use (use_device, else $LORGNETTE_DEVICE, else the CLI's default rule).");
}

void bind_images(pyb::module_& m) {
  m.def(
      "load_image",
      [](const std::string& path, bool raw) -> pyb::object {
        require_file(path, "image");
        if (raw) return raw_image(path);
        return to_numpy(read_image(path));
      },
      pyb::arg("path"), pyb::arg("raw") = false,
      "An image file as a NumPy array: linear float32 (H x W x C, as the library reads it), or with "
      "raw=True the stored values (uint8 for 8-bit files such as the CLI's PNGs).");
  m.def("save_image", &save_image, pyb::arg("path"), pyb::arg("image"),
        "Writes a float32 linear image (PNG/JPG sRGB-encoded, EXR linear) as the CLI does, or a uint8 "
        "image's values as they are.");
  m.def("to_srgb8", &srgb8, pyb::arg("rgba"), pyb::arg("alpha") = false,
        "Model.render's float RGBA as the 8-bit sRGB pixels `lorgnette render` writes to its PNGs "
        "(H x W x 3, or H x W x 4 straight alpha with alpha=True).");
}

void bind_trs(pyb::module_& m) {
  m.def(
      "trs",
      [](std::array<float, 3> t, std::array<float, 3> r, float s) {
        fit::Transform a = fit::trs_transform(t, r, s);
        pyb::array_t<double> out({4, 4});
        for (int i = 0; i < 16; ++i) out.mutable_data()[i] = a(i / 4, i % 4);
        return out;
      },
      pyb::arg("translate") = std::array<float, 3>{0, 0, 0},
      pyb::arg("rotate_deg") = std::array<float, 3>{0, 0, 0}, pyb::arg("scale") = 1.0f,
      "4x4 p' = translate + R(rotate_deg) * scale * p with R = Rz Ry Rx (render "
      "--translate/--rotate/--scale).");
}

}  // namespace
}  // namespace lorgnette::py

PYBIND11_MODULE(_lorgnette, m) {
  using namespace lorgnette::py;
  m.doc() = "Lorgnette: view-consistent virtual try-on of glasses (NeRF head + ray-traced frame)";
  m.attr("__version__") = lorgnette::version_string();
  register_errors(m);
  bind_logging(m);
  bind_devices(m);
  bind_images(m);
  bind_trs(m);
  bind_model(m);
  bind_glasses(m);
  bind_fit(m);
  bind_train(m);
}

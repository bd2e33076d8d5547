// lorgnette.fit and lorgnette.dlib_landmarks: the glasses placement of `lorgnette fit` (the same
// options and library calls), with the 2D landmarks from the built-in dlib detector or from a Python
// callable (fit::DetectFn), and the project's dlib adapter on its own for Python code.
#include <fmt/format.h>
#include <pybind11/stl.h>
#include <spdlog/spdlog.h>

#include <optional>

#include "fit/fit_job.h"
#include "fit/glasses_input.h"
#include "fit/placement_json.h"
#include "python/src/bindings.h"

namespace lorgnette::py {
namespace {

// Thrown through the fit when the Python callable failed; the Python error waits in CallbackState.
struct CallbackFailed : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct CallbackState {
  pyb::object fn;
  bool pass_face_px = false;
  std::optional<pyb::error_already_set> error;  // what the callable raised
  std::string problem;                          // or what was wrong with what it returned
  int calls = 0;
};

std::vector<Eigen::Vector2d> points_from(const pyb::handle& obj) {
  auto a = pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>::ensure(obj);
  if (!a || a.ndim() != 2 || a.shape(0) != 68 || a.shape(1) != 2)
    throw std::runtime_error(fmt::format("expected 68 (x, y) points in iBUG order, got {}",
                                         pyb::repr(obj).cast<std::string>().substr(0, 80)));
  std::vector<Eigen::Vector2d> pts;
  for (int i = 0; i < 68; ++i) {
    pts.emplace_back(a.at(i, 0), a.at(i, 1));
    if (!pts.back().allFinite()) throw std::runtime_error(fmt::format("point {} is not finite", i));
  }
  return pts;
}

// None -> no face; 68 x 2 points; or {"points": 68 x 2, "box": (left, top, right, bottom), "score": s}.
// Without a box, the points' bounding box stands for the face box (the fit frames the face with it).
fit::FaceDetection detection_from(const pyb::handle& obj) {
  fit::FaceDetection d;
  if (obj.is_none()) return d;
  pyb::object pts = pyb::reinterpret_borrow<pyb::object>(obj);
  if (pyb::isinstance<pyb::dict>(obj)) {
    pyb::dict dict = pyb::reinterpret_borrow<pyb::dict>(obj);
    if (!dict.contains("points")) throw std::runtime_error("a dict result needs 'points' (68 x 2)");
    pts = dict["points"];
    try {  // pybind's "Unable to cast" says nothing about which key was wrong
      if (dict.contains("box")) {
        auto b = dict["box"].cast<std::array<double, 4>>();
        d.box = Eigen::Vector4d(b[0], b[1], b[2], b[3]);
      }
      if (dict.contains("score")) d.score = dict["score"].cast<double>();
    } catch (const pyb::cast_error&) {
      throw std::runtime_error(
          "a dict result's 'box' must be four numbers (left, top, right, bottom) and "
          "its 'score' a number");
    }
  }
  d.points = points_from(pts);
  if (d.box.isZero()) {
    Eigen::Vector2d lo = d.points[0], hi = d.points[0];
    for (const auto& p : d.points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    d.box << lo.x(), lo.y(), hi.x(), hi.y();
  }
  d.found = true;
  d.faces = 1;
  return d;
}

fit::DetectFn python_detector(std::shared_ptr<CallbackState> state) {
  return [state](const std::vector<unsigned char>& rgb, int w, int h, double face_px) {
    pyb::gil_scoped_acquire gil;
    ++state->calls;
    try {
      pyb::array_t<uint8_t> img({pyb::ssize_t(h), pyb::ssize_t(w), pyb::ssize_t(3)});
      std::copy(rgb.begin(), rgb.end(), img.mutable_data());
      pyb::object out = state->pass_face_px ? state->fn(img, pyb::arg("face_px") = face_px) : state->fn(img);
      return detection_from(out);
    } catch (pyb::error_already_set& e) {
      state->error = std::move(e);
    } catch (const std::exception& e) {
      state->problem = e.what();
    }
    throw CallbackFailed("the landmarks callable failed");
  };
}

// The callable's failure as LandmarkError (chained to what it raised).
[[noreturn]] void raise_callback_error(CallbackState& s) {
  std::string msg = fmt::format("the landmarks callable failed on call {}", s.calls);
  if (s.error) {
    pyb::raise_from(*s.error, landmark_error_type().ptr(),
                    fmt::format("{}: {}", msg, s.error->what()).c_str());
    throw pyb::error_already_set();
  }
  PyErr_SetString(
      landmark_error_type().ptr(),
      fmt::format("{}: it must return None, 68 x 2 points or a dict with 'points': {}", msg, s.problem)
          .c_str());
  throw pyb::error_already_set();
}

struct FitArgs {
  pyb::object landmarks;
  bool pass_face_px = false;
  int views = 12, resolution = 384, upsample = 0;
  double yaw_range = 20.0, pitch_range = 15.0;
  std::string policy = "stretch", dataset, mean_face, landmark_model, debug_dir;
};

// `lorgnette fit` (tools/lorgnette/cmd_fit.cpp) with the same defaults, in the same order.
std::shared_ptr<Placement> run_fit(Model& model, const std::string& glasses_path, const FitArgs& a) {
  fit::FitSettings settings;
  settings.views = a.views;
  settings.resolution = a.resolution;
  settings.upsample = a.upsample;
  settings.yaw_range_deg = a.yaw_range;
  settings.pitch_range_deg = a.pitch_range;
  settings.policy = a.policy;
  settings.landmark_model = a.landmark_model;
  settings.mean_face = a.mean_face;
  settings.debug_dir = a.debug_dir;
  fit::FitOptions opt = fit::fit_options(settings);  // the CLI's ranges and messages
  auto state = std::make_shared<CallbackState>();
  if (!a.landmarks.is_none()) {
    if (!PyCallable_Check(a.landmarks.ptr()))
      throw pyb::type_error("landmarks must be a callable (image -> points or None)");
    state->fn = a.landmarks;
    state->pass_face_px = a.pass_face_px;
    opt.detection.detect = python_detector(state);
  }
  fit::PlacementFile pf;
  try {
    pyb::gil_scoped_release release;
    fit::GlassesInput glasses = fit::load_glasses_input(glasses_path);
    std::lock_guard<std::mutex> lock(model.device->mutex);
    fit::NerfViewOptions views;
    views.dataset = a.dataset;
    fit::FitJobResult job = fit::run_fit_job(*model.nerf, glasses, opt, views);
    pf = std::move(job.placement);
    for (const auto& w : job.fit.warnings) spdlog::warn("fit: {}", w);
  } catch (const CallbackFailed&) {
    raise_callback_error(*state);
  }
  auto p = std::make_shared<Placement>();
  p->file = std::move(pf);
  return p;
}

// The process's dlib detector for dlib_landmarks (loaded once; one detection at a time).
fit::LandmarkDetector& shared_dlib() {
  static std::mutex mutex;
  static std::unique_ptr<fit::LandmarkDetector> detector;
  std::lock_guard<std::mutex> lock(mutex);
  if (!detector) detector = std::make_unique<fit::LandmarkDetector>(fit::DetectorOptions{});
  return *detector;
}

pyb::object dlib_landmarks(const pyb::array_t<uint8_t, pyb::array::c_style | pyb::array::forcecast>& image,
                           double face_px) {
  if (image.ndim() != 3 || image.shape(2) != 3)
    throw pyb::value_error("dlib_landmarks: expected an H x W x 3 uint8 sRGB image");
  fit::FaceDetection d;
  {
    pyb::gil_scoped_release release;
    static std::mutex one_at_a_time;
    fit::LandmarkDetector& det = shared_dlib();
    std::lock_guard<std::mutex> lock(one_at_a_time);
    d = det.detect_srgb8(image.data(), int(image.shape(1)), int(image.shape(0)), face_px);
  }
  if (!d.found) return pyb::none();
  pyb::array_t<double> pts({pyb::ssize_t(d.points.size()), pyb::ssize_t(2)});
  for (size_t i = 0; i < d.points.size(); ++i)
    pts.mutable_at(i, 0) = d.points[i].x(), pts.mutable_at(i, 1) = d.points[i].y();
  pyb::dict out;
  out["points"] = pts;
  out["box"] = std::array<double, 4>{d.box[0], d.box[1], d.box[2], d.box[3]};
  out["score"] = d.score;
  out["faces"] = d.faces;
  return out;
}

}  // namespace

void bind_fit(pyb::module_& m) {
  m.def(
      "_fit",
      [](Model& model, pyb::object glasses, pyb::object landmarks, bool pass_face_px, int views,
         int resolution, double yaw_range, double pitch_range, int upsample, const std::string& policy,
         const std::string& dataset, const std::string& mean_face, const std::string& landmark_model,
         const std::string& debug_dir) {
        std::string path;
        if (pyb::isinstance<Glasses>(glasses))
          path = glasses.cast<std::shared_ptr<Glasses>>()->glasses.path;
        else if (pyb::isinstance<pyb::str>(glasses) || pyb::hasattr(glasses, "__fspath__"))
          path = pyb::str(pyb::module_::import("os").attr("fspath")(glasses));
        else
          throw pyb::type_error(
              fmt::format("glasses must be a lorgnette.Glasses or a path to a frame file, found {}",
                          Py_TYPE(glasses.ptr())->tp_name));
        require_file(path, "glasses");
        FitArgs a{landmarks,   pass_face_px, views,   resolution, upsample,       yaw_range,
                  pitch_range, policy,       dataset, mean_face,  landmark_model, debug_dir};
        return run_fit(model, path, a);
      },
      pyb::arg("model"), pyb::arg("glasses"), pyb::arg("landmarks"), pyb::arg("pass_face_px"),
      pyb::arg("views"), pyb::arg("resolution"), pyb::arg("yaw_range"), pyb::arg("pitch_range"),
      pyb::arg("upsample"), pyb::arg("scale_policy"), pyb::arg("dataset"), pyb::arg("mean_face"),
      pyb::arg("landmark_model"), pyb::arg("debug_dir"));
  m.def("dlib_landmarks", &dlib_landmarks, pyb::arg("image"), pyb::arg("face_px") = 0.0,
        "The fit's built-in detector (dlib HOG face + 68-point shape predictor, Debian's libdlib-data; "
        "non-commercial licence) on an H x W x 3 uint8 sRGB image: None, or {'points': 68 x 2 (iBUG order, "
        "pixel centres at i + 0.5), 'box': (left, top, right, bottom), 'score', 'faces'}. `face_px` is the "
        "fit's hint of the face's width (0 = unknown), which the fit passes to callables that accept it.");
}

}  // namespace lorgnette::py

// mdbrief.MdBrief: the cv::Feature2D adapter (feature2d.hpp) with every MdBriefOptions field as a
// keyword argument. The keyword table below is the only place that maps Python names to option
// fields; defaults and the docstring come from a default-constructed MdBriefOptions.
#include <algorithm>
#include <cstring>
#include <functional>
#include <sstream>

#include "bindings.hpp"
#include "conversions.hpp"
#include "mdbrief/feature2d.hpp"

namespace mdbrief::python {
namespace {

struct Keyword {
  const char* name;
  const char* field;  // the C++ field, as validate() names it in its messages
  std::function<py::object(const MdBriefOptions&)> get;
  std::function<void(MdBriefOptions&, const py::handle&)> set;
};

template <typename T>
T castExactly(const py::handle& value, const char* name) {
  // bool is a Python int: refuse it for numbers, and numbers for flags.
  const bool isBool = py::isinstance<py::bool_>(value);
  if constexpr (std::is_same_v<T, bool>) {
    if (!isBool) throw py::type_error(std::string(name) + " must be True or False");
  } else if constexpr (std::is_integral_v<T>) {
    if (isBool || !py::isinstance<py::int_>(value)) throw py::type_error(std::string(name) + " must be an int");
  } else if constexpr (std::is_floating_point_v<T>) {
    if (isBool || !(py::isinstance<py::float_>(value) || py::isinstance<py::int_>(value)))
      throw py::type_error(std::string(name) + " must be a number");
  } else {
    if (!py::isinstance<py::str>(value)) throw py::type_error(std::string(name) + " must be a str");
  }
  try {
    return value.cast<T>();
  } catch (const py::cast_error&) {
    throw py::value_error(std::string(name) + " is out of range");
  }
}

template <typename T, typename Access>
Keyword field(const char* name, const char* cppField, Access access) {
  return {name, cppField, [access](const MdBriefOptions& o) { return py::cast(access(o)); },
          [access, name](MdBriefOptions& o, const py::handle& v) { access(o) = castExactly<T>(v, name); }};
}

template <typename Enum, typename Access>
Keyword enumField(const char* name, const char* cppField, Access access, Enum (*parse)(const std::string&)) {
  return {name, cppField, [access](const MdBriefOptions& o) { return py::cast(toString(access(o))); },
          [access, name, parse](MdBriefOptions& o, const py::handle& v) {
            const std::string text = castExactly<std::string>(v, name);
            try {
              access(o) = parse(text);
            } catch (const std::invalid_argument& e) {
              throw py::value_error(std::string(name) + ": " + e.what());
            }
          }};
}

// A registry name or a file: str, bytes or os.PathLike (pathFrom), read back as str.
template <typename Access>
Keyword pathField(const char* name, const char* cppField, Access access) {
  return {name, cppField, [access](const MdBriefOptions& o) { return py::object(pathText(access(o))); },
          [access, name](MdBriefOptions& o, const py::handle& v) { access(o) = pathFrom(v, name); }};
}

// The pyramid of detector and descriptor (MdBriefOptions::detector.pyramid).
template <typename T, typename Access>
Keyword pyramidField(const char* name, const char* cppField, Access access) {
  return {name, cppField, [access](const MdBriefOptions& o) { return py::cast(access(o.detector.pyramid)); },
          [access, name](MdBriefOptions& o, const py::handle& v) {
            access(o.detector.pyramid) = castExactly<T>(v, name);
          }};
}

const std::vector<Keyword>& keywords() {
  static const std::vector<Keyword> table = {
      enumField("detector", "method", [](auto& o) -> auto& { return o.detector.method; }, &parseDetectorMethod),
      field<int>("nfeatures", "nfeatures", [](auto& o) -> auto& { return o.detector.nfeatures; }),
      pyramidField<int>("levels", "levels", [](auto& p) -> auto& { return p.levels; }),
      pyramidField<double>("scale_factor", "scaleFactor", [](auto& p) -> auto& { return p.scaleFactor; }),
      pyramidField<int>("first_level", "firstLevel", [](auto& p) -> auto& { return p.firstLevel; }),
      pyramidField<int>("smoothing_kernel", "smoothingKernel", [](auto& p) -> auto& { return p.smoothingKernel; }),
      pyramidField<double>("smoothing_sigma", "smoothingSigma", [](auto& p) -> auto& { return p.smoothingSigma; }),
      enumField("corners", "corners", [](auto& o) -> auto& { return o.detector.corners; }, &parseCornerDetector),
      field<int>("threshold", "threshold", [](auto& o) -> auto& { return o.detector.threshold; }),
      field<int>("fallback_threshold", "fallbackThreshold", [](auto& o) -> auto& { return o.detector.fallbackThreshold; }),
      field<int>("harris_block_size", "harrisBlockSize", [](auto& o) -> auto& { return o.detector.harrisBlockSize; }),
      field<double>("harris_k", "harrisK", [](auto& o) -> auto& { return o.detector.harrisK; }),
      field<bool>("spread", "spread", [](auto& o) -> auto& { return o.detector.spread; }),
      field<double>("hessian_sigma", "hessianSigma", [](auto& o) -> auto& { return o.detector.hessianSigma; }),
      field<double>("hessian_threshold", "hessianThreshold", [](auto& o) -> auto& { return o.detector.hessianThreshold; }),
      field<int>("detector_orientation_radius", "DetectorOptions::orientationRadius",
                 [](auto& o) -> auto& { return o.detector.orientationRadius; }),
      field<int>("patch_size", "patchSize", [](auto& o) -> auto& { return o.detector.patchSize; }),
      field<int>("border_margin", "borderMargin", [](auto& o) -> auto& { return o.detector.borderMargin; }),
      field<bool>("conformal", "conformal", [](auto& o) -> auto& { return o.detector.conformal; }),
      enumField("descriptor", "kind", [](auto& o) -> auto& { return o.descriptor.kind; }, &parseDescriptorKind),
      field<int>("bits", "bits", [](auto& o) -> auto& { return o.descriptor.bits; }),
      pathField("pattern", "pattern", [](auto& o) -> auto& { return o.descriptor.pattern; }),
      field<bool>("use_orientation", "useOrientation", [](auto& o) -> auto& { return o.descriptor.useOrientation; }),
      enumField("orientation", "orientation", [](auto& o) -> auto& { return o.descriptor.orientation; },
                &parseOrientationSource),
      field<int>("orientation_radius", "descriptor option orientationRadius",
                 [](auto& o) -> auto& { return o.descriptor.orientationRadius; }),
      enumField("form", "form", [](auto& o) -> auto& { return o.descriptor.form; }, &parseDistortionForm),
      enumField("sampling", "sampling", [](auto& o) -> auto& { return o.descriptor.sampling; }, &parseSampling),
      field<double>("mask_rotation_deg", "maskRotationDeg", [](auto& o) -> auto& { return o.descriptor.maskRotationDeg; }),
      field<double>("max_incidence_deg", "maxIncidenceDeg", [](auto& o) -> auto& { return o.descriptor.maxIncidenceDeg; }),
      field<double>("support_scale", "supportScale", [](auto& o) -> auto& { return o.descriptor.supportScale; }),
  };
  return table;
}

// validate() names C++ fields; the user wrote Python keywords. Name the keyword whose field the
// message mentions first: the option at fault leads, and fields named later say why
// ("borderMargin must be >= 15 (orientationRadius and harrisBlockSize / 2 + 1)"). At the same
// place the longest match wins, so "DetectorOptions::orientationRadius" beats "orientationRadius".
[[noreturn]] void raiseNamingKeyword(const std::string& message) {
  const Keyword* best = nullptr;
  size_t bestAt = std::string::npos;
  for (const Keyword& k : keywords()) {
    const size_t at = message.find(k.field);
    if (at == std::string::npos) continue;
    if (!best || at < bestAt || (at == bestAt && std::strlen(k.field) > std::strlen(best->field))) best = &k, bestAt = at;
  }
  throw py::value_error(best ? std::string(best->name) + ": " + message : message);
}

MdBriefOptions optionsFrom(const py::kwargs& kwargs) {
  MdBriefOptions options;
  for (const auto& [key, value] : kwargs) {
    const std::string name = py::str(key);
    const auto& table = keywords();
    const auto k = std::find_if(table.begin(), table.end(), [&](const Keyword& w) { return name == w.name; });
    if (k == table.end()) throw py::type_error("MdBrief() got an unexpected keyword argument '" + name + "'");
    k->set(options, value);
  }
  try {
    validate(options);
  } catch (const std::invalid_argument& e) {
    raiseNamingKeyword(e.what());
  }
  return options;
}

py::dict optionsDict(const MdBriefOptions& options) {
  py::dict d;
  for (const Keyword& k : keywords()) d[k.name] = k.get(options);
  return d;
}

std::string initDoc() {
  std::ostringstream doc;
  doc << "MdBrief(camera, **options)\n\n"
         "Detector + descriptor, as mdbrief::MdBrief in C++. camera: an mdbrief.Camera (None only for\n"
         "descriptor='brief' or 'mbrief'). Every option of MdBriefOptions is a keyword; the defaults are\n"
         "the library's (docs/RESULTS.md says why):\n\n";
  const py::dict defaults = optionsDict(MdBriefOptions{});
  for (const Keyword& k : keywords()) doc << "    " << k.name << "=" << std::string(py::repr(defaults[k.name])) << "\n";
  doc << "\nA bad value raises ValueError naming the keyword; an unknown keyword, TypeError.";
  return doc.str();
}

using FeaturePtr = std::shared_ptr<MdBrief>;

// Keypoints, descriptors and masks of one call; the C++ work runs without the GIL.
py::tuple run(MdBrief& feature, const py::handle& image, const py::handle& mask, std::vector<cv::KeyPoint> keypoints,
              bool provided) {
  py::object keepImage, keepMask;
  const cv::Mat img = imageFromArray(image, "image", keepImage);
  const cv::Mat msk = imageFromArray(mask, "mask", keepMask, true);
  if (!msk.empty() && msk.channels() != 1) throw py::value_error("mask must have shape (H, W)");
  cv::Mat descriptors, masks;
  try {
    py::gil_scoped_release release;
    feature.detectAndComputeWithMasks(img, msk, keypoints, descriptors, masks, provided);
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
  const int bytes = feature.descriptorSize();
  const bool masked = hasMasks(feature.options().descriptor.kind);
  return py::make_tuple(keypointsToPython(keypoints), arrayFromMat(descriptors, bytes),
                        masked ? py::object(arrayFromMat(masks, bytes)) : py::object(py::none()));
}

}  // namespace

void bindFeatures(py::module_& m) {
  py::class_<MdBrief, FeaturePtr>(m, "MdBrief", "Keypoint detection and BRIEF / dBRIEF / mdBRIEF description.")
      .def(py::init([](std::shared_ptr<Camera> camera, const py::kwargs& kwargs) {
             const MdBriefOptions options = optionsFrom(kwargs);
             try {
               return std::make_shared<MdBrief>(camera, options);
             } catch (const std::invalid_argument& e) {
               raiseNamingKeyword(e.what());
             }
           }),
           py::arg("camera").none(true), initDoc().c_str())
      .def(
          "detect",
          [](MdBrief& f, const py::handle& image, const py::handle& mask) {
            py::object keepImage, keepMask;
            const cv::Mat img = imageFromArray(image, "image", keepImage);
            const cv::Mat msk = imageFromArray(mask, "mask", keepMask, true);
            if (!msk.empty() && msk.channels() != 1) throw py::value_error("mask must have shape (H, W)");
            std::vector<cv::KeyPoint> keypoints;
            try {
              py::gil_scoped_release release;
              f.detectAndComputeWithMasks(img, msk, keypoints, cv::noArray(), cv::noArray());
            } catch (const std::invalid_argument& e) {
              throw py::value_error(e.what());
            }
            return keypointsToPython(keypoints);
          },
          py::arg("image"), py::arg("mask") = py::none(),
          "Keypoints (list of cv2.KeyPoint) of a uint8 image, grey (H, W) or BGR (H, W, 3) of the\n"
          "camera's size. mask: None or uint8 (H, W), nonzero = allowed.")
      .def(
          "compute",
          [](MdBrief& f, const py::handle& image, const py::handle& keypoints) {
            return run(f, image, py::none(), keypointsFromPython(keypoints, "keypoints"), true);
          },
          py::arg("image"), py::arg("keypoints"),
          "Describes given cv2.KeyPoint objects (any detector's). Returns (keypoints, descriptors,\n"
          "masks): the keypoints that could be described (with the re-measured angle for\n"
          "dBRIEF/mdBRIEF), (N, bytes) uint8 descriptors, and (N, bytes) uint8 masks for mdBRIEF\n"
          "(None for BRIEF and dBRIEF).")
      .def(
          "detect_and_compute",
          [](MdBrief& f, const py::handle& image, const py::handle& mask) {
            return run(f, image, mask, {}, false);
          },
          py::arg("image"), py::arg("mask") = py::none(),
          "detect() then compute() on one image pyramid: (keypoints, descriptors, masks).")
      .def_property_readonly("options", [](const MdBrief& f) { return optionsDict(f.options()); },
                             "Every option, by keyword name.")
      .def_property_readonly("camera", [](const MdBrief& f) { return std::const_pointer_cast<Camera>(f.camera()); })
      .def_property_readonly("descriptor_size", &MdBrief::descriptorSize, "Bytes per descriptor.")
      .def_property_readonly("default_norm", &MdBrief::defaultNorm, "cv2.NORM_HAMMING.")
      .def("__repr__", [](const MdBrief& f) {
        return "<mdbrief.MdBrief " + toString(f.options().detector.method) + " + " +
               toString(f.options().descriptor.kind) + "-" + std::to_string(f.options().descriptor.bits) + ">";
      });

  m.def(
      "_native_seconds",
      [](MdBrief& f, const py::handle& image, int repeats, const py::handle& given) {
        py::object keep;
        const cv::Mat img = imageFromArray(image, "image", keep);
        const bool provided = !given.is_none();
        const std::vector<cv::KeyPoint> input = provided ? keypointsFromPython(given, "keypoints") : std::vector<cv::KeyPoint>{};
        py::gil_scoped_release release;
        cv::Mat descriptors, masks;
        const int64 start = cv::getTickCount();
        for (int i = 0; i < repeats; ++i) {
          std::vector<cv::KeyPoint> keypoints = input;
          f.detectAndComputeWithMasks(img, cv::noArray(), keypoints, descriptors, masks, provided);
        }
        return static_cast<double>(cv::getTickCount() - start) / cv::getTickFrequency() / repeats;
      },
      py::arg("feature"), py::arg("image"), py::arg("repeats"), py::arg("keypoints") = py::none(),
      "Seconds per detect_and_compute (or compute of the given keypoints) of the same image in\n"
      "C++ alone: the reference of the binding-overhead benchmark (bench/python/binding_overhead.py).");
}

}  // namespace mdbrief::python

// mdbrief.MdBrief: the cv::Feature2D adapter (feature2d.hpp) with every MdBriefOptions field as a
// keyword argument. The keywords, their docs and ranges come from the library's field table
// (mdBriefOptionFields(), with `method` for its `detector`); defaults from a default-constructed MdBriefOptions.
#include <optional>
#include <string>

#include "bindings.hpp"
#include "conversions.hpp"
#include "mdbrief/api/feature2d.hpp"
#include "mdbrief/api/presets.hpp"
#include "option_keywords.hpp"
#include "presets.hpp"

namespace mdbrief::python {
namespace {

using FeaturePtr = std::shared_ptr<MdBrief>;

// `detector=`, the keyword's name before 0.2, still works with a DeprecationWarning; its errors
// name it as given.
const OptionTable<MdBriefOptions>& keywordTable(const py::dict& keywords) {
  if (!keywords.contains("detector")) return mdBriefKeywords();
  if (keywords.contains("method"))
    throw py::type_error("MdBrief() got both method= and detector=, its deprecated name: give method= only");
  if (PyErr_WarnEx(PyExc_DeprecationWarning, "MdBrief: detector= is deprecated, use method=", 1) != 0)
    throw py::error_already_set();
  return mdBriefOptionFields();
}

// pattern may also be a ComparisonSet (one just trained, say): then the options' pattern is
// `patternText` (default: the set's name), and the set itself describes.
FeaturePtr makeFeature(std::shared_ptr<Camera> camera, MdBriefOptions base, const py::dict& keywords,
                       const std::optional<std::string>& patternText = std::nullopt) {
  std::optional<ComparisonSet> tests;
  if (keywords.contains("pattern") && py::isinstance<ComparisonSet>(keywords["pattern"])) {
    tests = keywords["pattern"].cast<ComparisonSet>();
    base.descriptor.pattern = patternText.value_or(tests->name);
  }
  const MdBriefOptions options = optionsFromKeywords(
      keywordTable(keywords), py::kwargs(keywords), "MdBrief", [](const MdBriefOptions& o) { validate(o); },
      tests ? std::vector<std::string>{"pattern"} : std::vector<std::string>{}, base);
  try {
    return tests ? std::make_shared<MdBrief>(camera, options, *tests) : std::make_shared<MdBrief>(camera, options);
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());  // a missing camera or an unusable pattern
  }
}

// The C++ check's message names Camera::resized; Python users call camera.resized.
void requireCameraSize(const MdBrief& feature, const cv::Mat& image) {
  const auto& camera = feature.camera();
  if (!camera || image.empty() || image.size() == camera->imageSize()) return;
  throw py::value_error("MdBrief: image size " + std::to_string(image.cols) + "x" + std::to_string(image.rows) +
                        " differs from the camera's " + std::to_string(camera->imageSize().width) + "x" +
                        std::to_string(camera->imageSize().height) +
                        " (use MdBrief(camera.resized((width, height)), ...))");
}

// Pickled as the camera, every option by keyword and the test set in use, so a set given as a
// ComparisonSet or a file need not exist where it is unpickled.
py::tuple featureState(const MdBrief& f) {
  return py::make_tuple(std::const_pointer_cast<Camera>(f.camera()), keywordDict(mdBriefKeywords(), f.options()),
                        py::cast(f.extractor().comparisonSet()));
}

FeaturePtr featureFromState(const py::tuple& state) {
  if (state.size() != 3 || !(state[0].is_none() || py::isinstance<Camera>(state[0])) ||
      !py::isinstance<py::dict>(state[1]) || !py::isinstance<ComparisonSet>(state[2]))
    throw py::value_error("MdBrief: bad pickled state (MdBrief.__getstate__ gives (camera: Camera or None, "
                          "options: dict, test_set: ComparisonSet))");
  py::dict keywords = state[1].cast<py::dict>();
  const std::string pattern = keywords.contains("pattern") ? pathFrom(keywords["pattern"], "pattern") : "";
  keywords["pattern"] = state[2];
  return makeFeature(state[0].cast<std::shared_ptr<Camera>>(), MdBriefOptions{}, keywords, pattern);
}

std::string initDoc() {
  return "MdBrief(camera, preset='tracking', **options)\n\n"
         "Detector + descriptor, as mdbrief::MdBrief in C++. camera: an mdbrief.Camera (None only for\n"
         "descriptor='brief' or 'mbrief'). preset: the options to start from (mdbrief.presets():\n"
         "tracking, the library's defaults; matching; paper). Every option of MdBriefOptions is a\n"
         "keyword that changes the preset's value; pattern may also be a ComparisonSet (mdbrief.train()'s).\n"
         "MdBrief objects pickle (camera, options and the test set in use). The defaults\n"
         "(docs/guide/README.md, options and presets; docs/RESULTS.md says why):\n\n" +
         keywordDoc(mdBriefKeywords(), MdBriefOptions{}) +
         "\nA bad value raises ValueError naming the keyword, its range and the value; an unknown keyword,\n"
         "TypeError; an unknown preset, ValueError listing the presets.";
}

// Keypoints, descriptors and masks of one call; the C++ work runs without the GIL.
py::tuple run(MdBrief& feature, const py::handle& image, const py::handle& mask, std::vector<cv::KeyPoint> keypoints,
              bool provided) {
  py::object keepImage, keepMask;
  const cv::Mat img = imageFromArray(image, "image", keepImage);
  const cv::Mat msk = imageFromArray(mask, "mask", keepMask, true);
  if (!msk.empty() && msk.channels() != 1) throw py::value_error("mask must have shape (H, W)");
  requireCameraSize(feature, img);
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

const OptionTable<MdBriefOptions>& mdBriefKeywords() {
  static const OptionTable<MdBriefOptions> table = [] {
    OptionTable<MdBriefOptions> t = mdBriefOptionFields();
    for (OptionField<MdBriefOptions>& f : t)
      if (f.member == "detector.method") f.keyword = "method";
    return t;
  }();
  return table;
}

void bindFeatures(py::module_& m) {
  boundClass<MdBrief, FeaturePtr>(m, "MdBrief", "Keypoint detection and BRIEF / dBRIEF / mdBRIEF description.")
      .def(py::init([](std::shared_ptr<Camera> camera, const std::string& preset, const py::kwargs& kwargs) {
             return makeFeature(camera, presetSettings(presetFrom(preset)).features, kwargs);
           }),
           py::arg("camera").none(true), py::kw_only(), py::arg("preset") = toString(Preset::Tracking),
           initDoc().c_str())
      .def(
          "detect",
          [](MdBrief& f, const py::handle& image, const py::handle& mask) {
            py::object keepImage, keepMask;
            const cv::Mat img = imageFromArray(image, "image", keepImage);
            const cv::Mat msk = imageFromArray(mask, "mask", keepMask, true);
            if (!msk.empty() && msk.channels() != 1) throw py::value_error("mask must have shape (H, W)");
            requireCameraSize(f, img);
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
      .def(py::pickle(&featureState, &featureFromState))
      .def_property_readonly("test_set", [](const MdBrief& f) { return f.extractor().comparisonSet(); },
                             "The tests in use (the pattern's first `bits`).")
      .def_property_readonly("options", [](const MdBrief& f) { return keywordDict(mdBriefKeywords(), f.options()); },
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

// mdbrief.MdBrief: the cv::Feature2D adapter (feature2d.hpp) with every MdBriefOptions field as a
// keyword argument. The keywords, their docs and ranges come from the library's field table
// (mdBriefOptionFields()); defaults from a default-constructed MdBriefOptions.
#include <string>

#include "bindings.hpp"
#include "conversions.hpp"
#include "mdbrief/feature2d.hpp"
#include "mdbrief/presets.hpp"
#include "option_keywords.hpp"
#include "presets.hpp"

namespace mdbrief::python {
namespace {

MdBriefOptions optionsFrom(const std::string& preset, const py::kwargs& kwargs) {
  return optionsFromKeywords(mdBriefOptionFields(), kwargs, "MdBrief", [](const MdBriefOptions& o) { validate(o); },
                             {}, presetSettings(presetFrom(preset)).features);
}

std::string initDoc() {
  return "MdBrief(camera, preset='tracking', **options)\n\n"
         "Detector + descriptor, as mdbrief::MdBrief in C++. camera: an mdbrief.Camera (None only for\n"
         "descriptor='brief' or 'mbrief'). preset: the options to start from (mdbrief.presets():\n"
         "tracking, the library's defaults; matching; paper). Every option of MdBriefOptions is a\n"
         "keyword that changes the preset's value; the defaults (docs/RESULTS.md says why):\n\n" +
         keywordDoc(mdBriefOptionFields(), MdBriefOptions{}) +
         "\nA bad value raises ValueError naming the keyword, its range and the value; an unknown keyword,\n"
         "TypeError; an unknown preset, ValueError listing the presets.";
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
      .def(py::init([](std::shared_ptr<Camera> camera, const std::string& preset, const py::kwargs& kwargs) {
             const MdBriefOptions options = optionsFrom(preset, kwargs);
             try {
               return std::make_shared<MdBrief>(camera, options);
             } catch (const std::invalid_argument& e) {
               throw py::value_error(e.what());  // a missing camera or an unusable pattern
             }
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
      .def_property_readonly("options", [](const MdBrief& f) { return keywordDict(mdBriefOptionFields(), f.options()); },
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

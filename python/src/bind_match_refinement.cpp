// mdbrief.refine_matches: sub-pixel refinement of matches (mdbrief/match/match_refinement.hpp) on
// pyramids built here from the images with the detector's pyramid options, so that the
// keypoints' octaves are their levels; its result, mdbrief.RefinedMatches.
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include <pybind11/numpy.h>

#include "bindings.hpp"
#include "conversions.hpp"
#include "mdbrief/api/feature2d.hpp"
#include "mdbrief/match/match_refinement.hpp"
#include "option_keywords.hpp"

namespace mdbrief::python {
namespace {

// A class of its own: pybind11's STL casters would turn a bare vector into a list.
struct RefinedMatches {
  std::vector<RefinedMatch> matches;
};

std::string sizeText(int width, int height) { return std::to_string(width) + "x" + std::to_string(height); }

void requireCameraSize(const cv::Mat& image, const Camera& camera, const char* imageName, const char* cameraName) {
  const cv::Size size = camera.imageSize();
  if (image.size() == size) return;
  throw py::value_error("refine_matches: " + std::string(imageName) + " is " + sizeText(image.cols, image.rows) +
                        " but " + cameraName + "'s image size is " + sizeText(size.width, size.height) +
                        " (the camera the keypoints were detected with, camera.resized((width, height)) for "
                        "another size)");
}

// Each match's indices against the keypoints, named as the Python caller gave them.
void requireIndices(const std::vector<cv::DMatch>& matches, size_t countA, size_t countB) {
  for (size_t m = 0; m < matches.size(); ++m)
    for (const auto& [index, field, count, keypoints] :
         {std::tuple(matches[m].queryIdx, "queryIdx", countA, "keypoints_a"),
          std::tuple(matches[m].trainIdx, "trainIdx", countB, "keypoints_b")})
      if (index < 0 || static_cast<size_t>(index) >= count)
        throw py::value_error("refine_matches: matches[" + std::to_string(m) + "]." + field + " = " +
                              std::to_string(index) + " is no index of " + keypoints + " (" + std::to_string(count) +
                              " keypoints)");
}

// The library's checks name its C++ parameters (refineMatches: keypointsA[3].octave ...).
[[noreturn]] void raiseInPythonNames(const std::invalid_argument& e) {
  std::string message = e.what();
  for (const auto& [from, to] : {std::pair<std::string, std::string>("refineMatches:", "refine_matches:"),
                                 {"keypointsA[", "keypoints_a["},
                                 {"keypointsB[", "keypoints_b["}})
    for (std::size_t at = message.find(from); at != std::string::npos; at = message.find(from, at + to.size()))
      message.replace(at, from.size(), to);
  throw py::value_error(message);
}

RefinedMatches refine(const MdBrief& feature, const py::handle& imageA, const py::handle& keypointsA,
                      const py::handle& imageB, const py::handle& keypointsB, const py::handle& matchList,
                      std::shared_ptr<Camera> cameraA, std::shared_ptr<Camera> cameraB, const py::kwargs& kwargs) {
  const MatchRefinementOptions options = optionsFromKeywords(
      matchRefinementOptionFields(), kwargs, "refine_matches", [](const MatchRefinementOptions& o) { validate(o); });
  py::object keepA, keepB;
  const cv::Mat a = imageFromArray(imageA, "image_a", keepA);
  const cv::Mat b = imageFromArray(imageB, "image_b", keepB);
  const std::vector<cv::KeyPoint> ka = keypointsFromPython(keypointsA, "keypoints_a");
  const std::vector<cv::KeyPoint> kb = keypointsFromPython(keypointsB, "keypoints_b");
  const std::vector<cv::DMatch> matches = matchesFromPython(matchList, "matches");
  if (!cameraA) cameraA = std::const_pointer_cast<Camera>(feature.camera());
  if (!cameraA)
    throw py::value_error("refine_matches: feature has no camera (descriptor '" +
                          toString(feature.options().descriptor.kind) +
                          "' without one): pass camera_a= (and camera_b= for another camera)");
  if (!cameraB) cameraB = cameraA;
  requireCameraSize(a, *cameraA, "image_a", "camera_a");
  requireCameraSize(b, *cameraB, "image_b", "camera_b");
  requireIndices(matches, ka.size(), kb.size());
  RefinedMatches out;
  try {
    py::gil_scoped_release release;
    const PyramidOptions& pyramid = feature.options().detector.pyramid;
    const ImagePyramid pa(a, pyramid), pb(b, pyramid);
    out.matches = refineMatches(pa, *cameraA, ka, pb, *cameraB, kb, matches, options);
  } catch (const std::invalid_argument& e) {
    raiseInPythonNames(e);
  }
  return out;
}

template <typename T, typename Value>
py::array_t<T> column(const RefinedMatches& r, std::vector<py::ssize_t> shape, Value value) {
  py::array_t<T> out(shape);
  T* p = out.mutable_data();
  const py::ssize_t width = shape.size() > 1 ? shape[1] : 1;
  for (size_t k = 0; k < r.matches.size(); ++k) value(r.matches[k], p + k * width);
  return out;
}

std::string refineDoc() {
  return R"doc(
Sub-pixel refinement of matches: for each match, the position in image b whose patch best aligns
with keypoint a's, by Lucas-Kanade on the smoothed pyramid levels, the two patches compared on
the plane tangent to each keypoint's ray (the lens' distortion removed). b's keypoint moves onto
a's surface point, to a tenth of a level pixel and less; coarse-level keypoints gain the most.

feature: the MdBrief that detected the keypoints; both images' pyramids are built with its
pyramid options, so that each keypoint's octave is its level. image_a, image_b: the images the
keypoints came from (uint8, grey or BGR, the cameras' sizes). keypoints_a, keypoints_b: their
cv2.KeyPoint lists. matches: cv2.DMatch list (queryIdx into keypoints_a, trainIdx into
keypoints_b) or mdbrief.match's structured array. camera_a: default feature.camera; camera_b:
default camera_a (give it for a stereo pair's second camera).

Options (keywords; mdbrief.option_fields("refine_matches")):
)doc" + keywordDoc(matchRefinementOptionFields(), MatchRefinementOptions{}) +
         R"doc(
Returns a RefinedMatches, one row per match in the order given: points_b, bearings_b, sigma_px,
levels, ok, reasons. A match that cannot be refined (a patch leaving the image or the lens'
circle, an edge or flat patch, an alignment that diverged) is not ok and keeps b's keypoint.
ValueError for a match index outside its keypoints, a keypoint whose octave is no pyramid level
or whose position is not finite, an image of another size than its camera, or an option out of
range. Runs without the GIL, the matches in parallel.)doc";
}

}  // namespace

void bindMatchRefinement(py::module_& m) {
  boundClass<RefinedMatches>(m, "RefinedMatches", R"doc(
What mdbrief.refine_matches gives: one row per match, in the order of the matches given. A match
that failed keeps b's keypoint as its point, has sigma_px inf and level -1, and its reason says
why.)doc")
      .def("__len__", [](const RefinedMatches& r) { return r.matches.size(); })
      .def_property_readonly(
          "points_b",
          [](const RefinedMatches& r) {
            return column<double>(r, {static_cast<py::ssize_t>(r.matches.size()), 2}, [](const RefinedMatch& x, double* p) {
              p[0] = x.pointB.x, p[1] = x.pointB.y;
            });
          },
          "(N, 2) float64: b's refined position (x, y), input pixels; b's keypoint where not ok.")
      .def_property_readonly(
          "bearings_b",
          [](const RefinedMatches& r) {
            return column<double>(r, {static_cast<py::ssize_t>(r.matches.size()), 3}, [](const RefinedMatch& x, double* p) {
              for (int i = 0; i < 3; ++i) p[i] = x.bearingB[i];
            });
          },
          "(N, 3) float64: the unit ray of points_b through camera_b (zero where it has none).")
      .def_property_readonly(
          "sigma_px",
          [](const RefinedMatches& r) {
            return column<double>(r, {static_cast<py::ssize_t>(r.matches.size())},
                                  [](const RefinedMatch& x, double* p) { *p = x.sigmaPx; });
          },
          "(N,) float64: standard deviation of points_b along its least certain direction, input\n"
          "pixels (the residual through the shift's covariance); inf where not ok.")
      .def_property_readonly(
          "levels",
          [](const RefinedMatches& r) {
            return column<int32_t>(r, {static_cast<py::ssize_t>(r.matches.size())},
                                   [](const RefinedMatch& x, int32_t* p) { *p = x.level; });
          },
          "(N,) int32: the finest pyramid level b's point was refined on; -1 where not ok.")
      .def_property_readonly(
          "ok",
          [](const RefinedMatches& r) {
            return column<bool>(r, {static_cast<py::ssize_t>(r.matches.size())},
                                [](const RefinedMatch& x, bool* p) { *p = x.ok(); });
          },
          "(N,) bool: the match was refined.")
      .def_property_readonly(
          "reasons",
          [](const RefinedMatches& r) {
            std::vector<std::string> out;
            for (const RefinedMatch& x : r.matches) out.emplace_back(toString(x.failure));
            return out;
          },
          "list of str, one per match: '' where ok, else 'patch outside the image', 'aperture: the\n"
          "patch does not fix both directions' or 'diverged'.")
      .def("__repr__", [](const RefinedMatches& r) {
        size_t ok = 0;
        for (const RefinedMatch& x : r.matches) ok += x.ok();
        return "<mdbrief.RefinedMatches " + std::to_string(ok) + " of " + std::to_string(r.matches.size()) +
               " refined>";
      });

  m.def("refine_matches", &refine, py::arg("feature"), py::arg("image_a"), py::arg("keypoints_a"), py::arg("image_b"),
        py::arg("keypoints_b"), py::arg("matches"), py::kw_only(), py::arg("camera_a").none(true) = py::none(),
        py::arg("camera_b").none(true) = py::none(), refineDoc().c_str());
}

}  // namespace mdbrief::python

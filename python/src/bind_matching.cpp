// mdbrief.match: plain or masked brute-force matching (matcher.hpp); mdbrief.match_guided: the
// same within windows around predicted positions (guided_matcher.hpp).
#include "bindings.hpp"
#include "conversions.hpp"
#include "mdbrief/match/guided_matcher.hpp"
#include "mdbrief/match/matcher.hpp"
#include "option_keywords.hpp"
#include "presets.hpp"

namespace mdbrief::python {
namespace {

// The two descriptor arrays of a match call, and their masks (both or neither), as cv::Mat views
// that keep the arrays they read alive.
struct DescriptorArrays {
  DescriptorArrays(const py::handle& d1, const py::handle& d2, const py::handle& masks1, const py::handle& masks2) {
    if (masks1.is_none() != masks2.is_none())
      throw py::value_error("masks1 and masks2 must both be given (masked matching) or both be None");
    query = descriptorsFromArray(d1, "d1", keep[0]);
    train = descriptorsFromArray(d2, "d2", keep[1]);
    if (!masks1.is_none()) {
      queryMasks = descriptorsFromArray(masks1, "masks1", keep[2]);
      trainMasks = descriptorsFromArray(masks2, "masks2", keep[3]);
    }
  }
  py::object keep[4];
  cv::Mat query, train, queryMasks, trainMasks;
};

}  // namespace

void bindMatching(py::module_& m) {
  m.def(
      "match",
      [](const py::handle& d1, const py::handle& d2, const py::handle& masks1, const py::handle& masks2,
         const std::string& preset, bool asArray, const py::kwargs& kwargs) -> py::object {
        const MatchOptions options = optionsFromKeywords(matchOptionFields(), kwargs, "match",
                                                         [](const MatchOptions& o) { validate(o); }, {},
                                                         presetSettings(presetFrom(preset)).matching);
        const DescriptorArrays arrays(d1, d2, masks1, masks2);
        const cv::Mat &query = arrays.query, &train = arrays.train;
        const cv::Mat &queryMasks = arrays.queryMasks, &trainMasks = arrays.trainMasks;
        std::vector<cv::DMatch> matches;
        try {
          py::gil_scoped_release release;
          matches = masks1.is_none() ? matchBruteForce(query, train, options)
                                     : matchBruteForceMasked(query, queryMasks, train, trainMasks, options);
        } catch (const std::invalid_argument& e) {
          throw py::value_error(e.what());
        }
        if (asArray) return matchesToArray(matches);
        return matchesToPython(matches);
      },
      py::arg("d1"), py::arg("d2"), py::arg("masks1") = py::none(), py::arg("masks2") = py::none(), py::kw_only(),
      py::arg("preset") = toString(Preset::Tracking), py::arg("as_array") = false, R"doc(
Brute-force nearest neighbours of the rows of d1 (queries) among the rows of d2, both (N, bytes)
uint8 arrays of the same width. With masks1 and masks2 (mdBRIEF's masks, the shapes of d1 and
d2) the distance is the masked Hamming distance, otherwise the Hamming distance.

preset: the matcher settings to start from (mdbrief.presets(); 'tracking' = the library's
defaults, a ratio test and mutual nearest neighbours, chosen with the default features on real
images). Keywords change them: ratio (Lowe's ratio test, keep if best < ratio * second best, in
(0, 1]; None = off), cross_check (keep only mutual nearest neighbours), max_distance (keep if
distance <= it, bits; None = off), parallel (spread the queries over threads; the result is the
same either way). mdbrief.option_fields("match") lists them.

Returns a list of cv2.DMatch (queryIdx, trainIdx, distance in bits), one per query that passes,
in query order, as cv2.BFMatcher.match does, so cv2.drawMatches takes it unchanged. With
as_array=True, a numpy structured array with fields query_idx, train_idx (int32) and distance
(float32) instead: no Python object per match, for large or repeated matching.)doc");

  m.def(
      "match_guided",
      [](const py::handle& d1, const py::handle& d2, const py::handle& predicted, const py::handle& keypoints2,
         std::pair<int, int> imageSize, const py::handle& masks1, const py::handle& masks2,
         const py::handle& keypoints1, const std::string& preset, bool asArray,
         const py::kwargs& kwargs) -> py::object {
        GuidedMatchOptions defaults;
        defaults.matching = presetSettings(presetFrom(preset)).matching;
        const GuidedMatchOptions options = optionsFromKeywords(
            guidedMatchOptionFields(), kwargs, "match_guided", [](const GuidedMatchOptions& o) { validate(o); }, {},
            defaults);
        const DescriptorArrays arrays(d1, d2, masks1, masks2);
        const cv::Mat &query = arrays.query, &train = arrays.train;
        const cv::Mat &queryMasks = arrays.queryMasks, &trainMasks = arrays.trainMasks;
        bool single = false;
        const auto points = pointsFromArray(predicted, 2, "predicted", single);
        std::vector<cv::Point2f> positions(single ? 1 : points.shape(0));
        for (size_t i = 0; i < positions.size(); ++i)
          positions[i] = {static_cast<float>(points.data()[2 * i]), static_cast<float>(points.data()[2 * i + 1])};
        const std::vector<cv::KeyPoint> trainKeypoints = keypointsFromPython(keypoints2, "keypoints2");
        const std::vector<cv::KeyPoint> queryKeypoints =
            keypoints1.is_none() ? std::vector<cv::KeyPoint>{} : keypointsFromPython(keypoints1, "keypoints1");
        const cv::Size size(imageSize.first, imageSize.second);
        std::vector<cv::DMatch> matches;
        try {
          py::gil_scoped_release release;
          matches = masks1.is_none()
                        ? matchGuided(query, queryKeypoints, positions, train, trainKeypoints, size, options)
                        : matchGuidedMasked(query, queryMasks, queryKeypoints, positions, train, trainMasks,
                                            trainKeypoints, size, options);
        } catch (const std::invalid_argument& e) {
          throw py::value_error(e.what());
        }
        if (asArray) return matchesToArray(matches);
        return matchesToPython(matches);
      },
      py::arg("d1"), py::arg("d2"), py::arg("predicted"), py::arg("keypoints2"), py::arg("image_size"),
      py::arg("masks1") = py::none(), py::arg("masks2") = py::none(), py::kw_only(),
      py::arg("keypoints1") = py::none(), py::arg("preset") = toString(Preset::Tracking),
      py::arg("as_array") = false, R"doc(
Guided matching, as a tracker searches after the first frame: each row of d1 (queries) is compared
only with the rows of d2 whose keypoint lies within `radius` pixels of the query's predicted
position in the second image. d1, d2, masks1, masks2 as for mdbrief.match.

predicted: (N, 2) positions (x, y) in the second image, one per row of d1; a position outside
the image or NaN has no candidates (no match). keypoints2: the cv2.KeyPoint of each row of d2
(positions on the grid; angle and size for the checks). image_size: (width, height) of the
second image. keypoints1: the cv2.KeyPoint of each row of d1, needed only by the checks.

Keywords: radius (pixels, default 15), max_angle_difference (degrees, keep candidates whose
orientations differ by at most this; None = off), max_scale_ratio (keep candidates whose sizes
differ by at most this factor; None = off), and mdbrief.match's ratio, cross_check (the train's
nearest among the queries whose windows hold it), max_distance and parallel, starting from the
preset. mdbrief.option_fields("match_guided") lists them. With few candidates the ratio test
rarely decides: max_distance bounds what a lone candidate may be.

Returns what mdbrief.match returns: cv2.DMatch list in query order, or a structured array with
as_array=True.)doc");

  m.def(
      "_native_match_seconds",
      [](const py::handle& d1, const py::handle& d2, const py::handle& masks1, const py::handle& masks2, int repeats) {
        py::object k1, k2, k3, k4;
        const cv::Mat q = descriptorsFromArray(d1, "d1", k1), t = descriptorsFromArray(d2, "d2", k2);
        const cv::Mat qm = descriptorsFromArray(masks1, "masks1", k3), tm = descriptorsFromArray(masks2, "masks2", k4);
        py::gil_scoped_release release;
        const int64 start = cv::getTickCount();
        for (int i = 0; i < repeats; ++i) matchBruteForceMasked(q, qm, t, tm, {});
        return static_cast<double>(cv::getTickCount() - start) / cv::getTickFrequency() / repeats;
      },
      py::arg("d1"), py::arg("d2"), py::arg("masks1"), py::arg("masks2"), py::arg("repeats"),
      "Seconds per masked match in C++ alone (bench/python/binding_overhead.py).");
}

}  // namespace mdbrief::python

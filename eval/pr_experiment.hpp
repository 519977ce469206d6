#pragma once
// The precision-recall comparison of the paper's "Results on Real Data": every method on the
// same detected keypoints (the project's Detector, `keypoints` strongest; AKAZE on its own),
// mean PR curve per sequence group, summary numbers. Writes eval_<group>_curves.csv and
// eval_summary.csv.
#include <string>
#include <vector>

#include "descriptor_method.hpp"
#include "eval_datasets.hpp"
#include "mdbrief/detect/detector.hpp"
#include "mdbrief/api/presets.hpp"
#include "patchextract/keypoint_detectors.hpp"

namespace mdbrief::eval {

struct EvalGroup {
  std::string name;  // "perspective", "fisheye", "user"
  std::vector<EvalSequence> sequences;
};

// Whose keypoints every method but AKAZE describes: the library's detector methods or an OpenCV
// detector. The names the other tables already give (the library's DetectorMethod, the
// trainer's DetectorKind) are taken from them, so a detector has one spelling everywhere.
enum class KeypointSource { ModOrb, Hessian, Orb, Akaze, Brisk, Sift };
inline constexpr EnumName<KeypointSource> kKeypointSourceNames[] = {
    {KeypointSource::ModOrb, kDetectorMethodNames[0].name},
    {KeypointSource::Hessian, kDetectorMethodNames[1].name},
    {KeypointSource::Orb, train::kDetectorKindNames[0].name},
    {KeypointSource::Akaze, train::kDetectorKindNames[1].name},
    {KeypointSource::Brisk, "brisk"},
    {KeypointSource::Sift, "sift"}};
static_assert(kDetectorMethodNames[0].value == DetectorMethod::ModOrb &&
              kDetectorMethodNames[1].value == DetectorMethod::Hessian &&
              train::kDetectorKindNames[0].value == train::DetectorKind::Orb &&
              train::kDetectorKindNames[1].value == train::DetectorKind::Akaze);
// Throws std::invalid_argument naming the accepted values.
inline KeypointSource parseKeypointSource(const std::string& name) {
  return parseName(name, kKeypointSourceNames, "keypoint source");
}

struct PrOptions {
  std::string outDir;
  int keypoints = 300;
  KeypointSource keypointSource = KeypointSource::ModOrb;
  // Keep only the keypoints the last method can describe, for every method: methods whose
  // footprints differ in size then compare on the same keypoints (a larger footprint drops
  // more keypoints near borders, which changes the ground truth).
  bool commonKeypoints = false;
  double radiusPx = 3.0;
  int curveSteps = 100;
  // The library's detector for modorb / hessian keypoints: the paper's (cv::ORB's pyramid of 8
  // levels of 1.2), whose keypoints every method describes on that pyramid, as in the paper.
  DetectorOptions library = presetSettings(Preset::Paper).features.detector;
};

// The paper's comparison set; with studies also the length study (32, 64 bits) and the
// test-set study (comparisonSetStudyMethods of every name of builtinComparisonSetNames()).
std::vector<MethodSpec> standardPrMethods(bool withStudies = true);

// The test-set study: dBRIEF and mdBRIEF at 128, 256 and 512 bits (those the set is long
// enough for) with each test set (registry name or JSON path), named "dBRIEF-256@<set>" (a
// JSON path by its file stem).
std::vector<MethodSpec> comparisonSetStudyMethods(const std::vector<std::string>& testSets);

// mdBRIEF-256 and dBRIEF-256 (default set) at each DescriptorOptions::supportScale, named
// "mdBRIEF-256-s<scale>": the footprint study for keypoints of other detectors.
std::vector<MethodSpec> supportScaleStudyMethods(const std::vector<double>& scales);

// At most `count` keypoints of the source: the library's Detector (`library` with the
// source's method and `count`; with `camera` when not null, for its valid area), or the strongest of an OpenCV detector inside `mask` (ties cut
// deterministically).
std::vector<cv::KeyPoint> detectKeypoints(KeypointSource source, const cv::Mat& image, const CameraPtr& camera,
                                          const cv::Mat& mask, int count, DetectorOptions library = {});

void runPrecisionRecall(const std::vector<EvalGroup>& groups, const std::vector<MethodSpec>& methods,
                        const PrOptions& options);

}  // namespace mdbrief::eval

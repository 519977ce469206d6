#pragma once
// One descriptor method of the comparison, described on given keypoints or on its own: the
// BRIEF family of this library (BRIEF, dBRIEF, mdBRIEF, and a BOLD-like masked BRIEF) and the
// OpenCV references (ORB, BRISK, AKAZE-MLDB, SIFT). Hides the differences (binary vs float,
// masked vs plain distance, own keypoints) behind one describe / distance / match interface.
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>

#include "mdbrief/camera/camera.hpp"
#include "mdbrief/describe/descriptor.hpp"
#include "mdbrief/detect/image_pyramid.hpp"

namespace mdbrief::eval {

enum class MethodFamily {
  Library,      // this library's BRIEF family; MethodSpec::options.kind says which
  Orb,          // cv::ORB descriptor on the given keypoints (256 bits)
  Brisk,        // cv::BRISK descriptor on the given keypoints (512 bits)
  Akaze,        // cv::AKAZE MLDB on its own keypoints (486 bits)
  Sift,         // cv::SIFT descriptor on the given keypoints (float reference)
};

struct MethodSpec {
  std::string name;                 // label in tables and plots
  MethodFamily family = MethodFamily::Library;
  DescriptorOptions options;        // used by the library's family (kind, bits, pattern...)
};

// Keypoints and their descriptors; class_id of each keypoint is preserved from the input.
struct Features {
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;  // CV_8U (binary, padded to a multiple of 4 bytes) or CV_32F (SIFT)
  cv::Mat masks;        // masked methods only
  int bits = 0;         // descriptor length in bits (binary), 128 for SIFT
};

bool ownsKeypoints(MethodFamily family);  // AKAZE detects its own keypoints
bool isMasked(const MethodSpec& method);      // masked distance (mdBRIEF, masked BRIEF)
bool isDistorted(const MethodSpec& method);   // through the camera model (dBRIEF, mdBRIEF)

// Describes `keypoints` (input pixels) in `image`; the library's family samples them on a
// pyramid with `pyramid`'s options (the detector's, so that keypoints and descriptors share one).
// Keypoints the method cannot describe are dropped. For AKAZE `keypoints` is ignored and the
// `maxKeypoints` strongest AKAZE keypoints (inside validMask if not empty) are used.
// camera may be null except for dBRIEF/mdBRIEF.
Features describe(const MethodSpec& method, const cv::Mat& image, const CameraPtr& camera,
                  std::vector<cv::KeyPoint> keypoints, int maxKeypoints = 300,
                  const cv::Mat& validMask = {}, const PyramidOptions& pyramid = {});

// Describes keypoints that the method's own OpenCV detector found (AKAZE: class_id is its
// evolution level; SIFT: octave and size are its own), as detectAndCompute would. Other
// families: as describe().
Features describeOwnKeypoints(const MethodSpec& method, const cv::Mat& image, std::vector<cv::KeyPoint> keypoints);

// Distance of row i of a and row j of b: bits (plain or masked, in bits) or L2 for SIFT.
double descriptorDistance(const Features& a, int i, const Features& b, int j);

// Nearest train row for every query row (no threshold), with the distance. Empty input gives
// no matches. Deterministic (ties to the lowest train index).
std::vector<cv::DMatch> nearestNeighbours(const Features& query, const Features& train);

// The comparison's standard set: name -> spec. bits/orientation/form/mask angle as given.
MethodSpec briefFamilyMethod(const std::string& name, DescriptorKind kind, int bits, bool oriented,
                             DistortionForm form = DistortionForm::Affine, double maskDeg = DescriptorOptions{}.maskRotationDeg,
                             const std::string& pattern = "");
MethodSpec opencvMethod(const std::string& name, MethodFamily family);

}  // namespace mdbrief::eval

#pragma once
// Image pairs with exact ground truth for the precision-recall evaluation:
// - perspective: the Oxford affine sequences (img1..6, homographies H1toNp in pixels);
// - fisheye: a photo rendered as a textured plane through a calibrated camera at several poses
//   (ground truth through the plane coordinates, exact);
// - user data: images + camera + homographies between bearings (b2 ~ H * b1, the paper's
//   ground truth between undistorted coordinates).
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "mdbrief/camera/camera.hpp"
#include "precision_recall.hpp"
#include "toolkit/data_folders.hpp"
#include "toolkit/homography_file.hpp"
#include "scenes/plane_renderer.hpp"

namespace mdbrief::eval {

// Where the default evaluations read their images (held_out.hpp lists them for the training):
// the opencv-doc sample photos (the commands' --opencv-doc-dir) and the Oxford sequences.
inline const std::vector<std::string> kOxfordSequences{"bikes", "boat", "graf", "leuven", "trees", "ubc"};
// opencv-doc photos rendered as fisheye sequences (besides img1 of every Oxford sequence).
inline const std::vector<std::string> kDocFisheyeTextures{"building.jpg", "home.jpg",   "aero1.jpg",
                                                          "baboon.jpg",   "fruits.jpg", "messi5.jpg"};
// Every opencv-doc photo an evaluation reads: graf1 (sim, timing), graf3 (export-user-sample)
// and the fisheye textures.
inline const std::vector<std::string> kDocEvaluationPhotos{"graf1.png", "graf3.png", "building.jpg", "home.jpg",
                                                           "aero1.jpg", "baboon.jpg", "fruits.jpg", "messi5.jpg"};

// The real fisheye frames with ground truth (poster_dev.hpp), under <data>/fisheye/poster-dev.
inline const std::vector<std::string> kPosterDevFrames{"m1.jpg",  "m5.jpg",  "m7.jpg",  "m8.jpg",  "m10.jpg",
                                                       "m11.jpg", "m14.jpg", "m16.jpg", "m17.jpg", "m18.jpg"};
// The real fisheye photos of the shared data folder with their calibrations, seen again by the
// lens turned (turnedLensSequence; scripts/real_fisheye_photos.sh lists the same three).
struct TurnedLensPhoto {
  const char* name;
  const char* image;   // relative to the shared data folder
  const char* camera;
};
inline constexpr TurnedLensPhoto kTurnedLensPhotos[] = {
    {"ocamcalib_sample", "fisheye/ocamcalib-sample/test_fisheye.jpg", "fisheye/ocamcalib-sample/calib_results.txt"},
    {"calib_adapter_kb", "fisheye/calib-adapter/kalibr/image.png", "fisheye/calib-adapter/kalibr/KB.yml"},
    {"calib_adapter_ocam", "fisheye/calib-adapter/OcamCalib/image.jpg", "fisheye/calib-adapter/OcamCalib/OcamCalib.yml"}};

struct EvalPair {
  int first = 0, second = 0;  // image indices
  GroundTruthMap map;         // pixel of `first` -> pixel of `second`
};

struct EvalSequence {
  std::string name;
  // The camera dBRIEF/mdBRIEF use; for the perspective Oxford images an ideal pinhole (focal
  // length = image width, principal point at the centre), where dBRIEF reduces to BRIEF.
  CameraPtr camera;
  bool cameraIsModel = false;  // true when the detector should respect the camera's valid area
  std::vector<cv::Mat> images;  // 8UC1
  std::vector<EvalPair> pairs;
  // Per image, where the ground truth holds (CV_8UC1, nonzero = on the scene): keypoints are
  // sought there only. Empty: the whole image (inside the camera's valid area).
  std::vector<cv::Mat> regions;
  // The camera moves between images (the scene is not seen from one centre), so an essential
  // matrix is defined; false for pure rotations and the Oxford sequences, whose ground truth is
  // a homography only.
  bool baseline = false;
};

// <dir>/img1..6.png (or .ppm) and H1to2p..H1to6p. Empty if the folder or a file is missing;
// throws std::runtime_error naming the file if a present file is unreadable.
std::optional<EvalSequence> loadOxfordSequence(const std::string& dir, const std::string& name);

// `texture` rendered through `camera` at `poses` poses: the reference faces the plane, the
// others translate / yaw / pitch / roll progressively towards the rim. Pairs 1-k.
EvalSequence renderedFisheyeSequence(const std::string& name, const cv::Mat& texture, const CameraPtr& camera,
                                     int poses);

// The poses of renderedFisheyeSequence: k = 0 faces the plane from 1 unit, the last is
// translated (1.2, 0.4), yawed 20, pitched -10 and rolled 30 degrees.
std::vector<CameraPose> renderedSequencePoses(int poses);

// Writes a rendered sequence as user data into `dir` (created if missing): img1.png..imgN.png,
// camera.yaml and the bearing homographies H1to2..H1toN (the format loadUserSequence reads).
// Each file is written to a temporary name and renamed. Returns the paths: images, camera,
// homographies.
struct UserSequenceFiles {
  std::vector<std::string> images;
  std::string camera;
  std::vector<std::string> homographies;
};
UserSequenceFiles exportUserSequence(const std::string& dir, const cv::Mat& texture, const CameraPtr& camera,
                                     int poses);
// The paths of a user sequence of `images` images in dir, as the exports write them.
UserSequenceFiles userSequenceFiles(const std::string& dir, int images);
// Every path of files, for the check that no output is an input.
std::vector<std::string> allPaths(const UserSequenceFiles& files);

// A real photo of `camera` (its calibration size) and the same lens turned: view k (k = 2..views)
// is the photo as a camera turned by cameraRotation(8 (k-1), -4 (k-1), 12 (k-1)) degrees sees it,
// resampled exactly (a pure rotation needs no scene depth); the bearing homographies are the
// rotations. Written like exportUserSequence. Throws std::runtime_error on a size mismatch.
UserSequenceFiles exportRotatedViews(const std::string& dir, const cv::Mat& photo, const CameraPtr& camera,
                                     int views);

// The same views in memory (pairs 1-k, ground truth the rotations, no baseline).
EvalSequence turnedLensSequence(const std::string& name, const cv::Mat& photo, const CameraPtr& camera, int views);

// User data: images[0] is the reference; homographyFiles[k] relates bearings of image 0 and
// image k+1 (3x3, nine numbers, whitespace separated, bearing_k ~ H * bearing_0). A homography
// is defined up to scale, but for a wide-angle lens its sign decides front from back: it is
// taken with det(H) > 0, true for every plane seen from one side (and for rotations). Throws
// std::runtime_error naming the file and the problem (unreadable, singular).
EvalSequence loadUserSequence(const std::string& name, const std::vector<std::string>& images,
                              const std::string& cameraPath, const std::vector<std::string>& homographyFiles,
                              const std::string& cameraId = "");

// An image the evaluation reads, as 8-bit grey. Throws std::runtime_error naming the file when it
// is missing, truncated (toolkit/image_file.hpp) or cannot be decoded.
cv::Mat loadEvaluationImage(const std::string& path);

}  // namespace mdbrief::eval

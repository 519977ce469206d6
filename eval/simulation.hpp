#pragma once
// The paper's simulation (section "Simulations"): Graffiti as the textured plane z = 0 seen by
// a virtual camera, and the extension of issue 5 with detected keypoints and tilted poses.
//
// Experiment "projected" (the paper's): 200 ORB keypoints of the texture projected into every
// view of a translation along X, descriptors without orientation, so every keypoint has a
// known true match. Outputs: Hamming distance of one patch (and the mean over all) from view 1
// to view k, recognition rate over a 10-view version of the path, matching / non-matching
// distance distributions and their Bhattacharyya coefficients.
//
// Experiment "detected", for every lens: the project's Detector in every view, poses that
// translate, tilt and roll the camera until the plane reaches the rim of the fisheye; a true
// match is the detected keypoint nearest to the projected true position within 3 px. Compares
// distortion forms, mask angles and orientation sources (the detector's angle vs the one
// re-measured on the tangent plane): it decides the defaults.
#include <string>
#include <vector>

#include "mdbrief/camera/camera.hpp"
#include "mdbrief/describe/descriptor.hpp"
#include "scenes/plane_renderer.hpp"

namespace mdbrief::eval {

struct SimCamera {
  std::string name;    // label used in file names: "pinhole", "radial", "fisheye", ...
  CameraPtr camera;
  // Projected experiment: length of the translation along X. 0 = the shared path (the paper
  // keeps the exterior orientation of a view the same for all cameras); < 0 = this camera's
  // own longest path, until the texture touches the edge of its valid area (the fisheye rim).
  double pathLength = 0.0;
};

struct SimOptions {
  std::string texturePath;            // graf1.png
  std::string outDir;                 // CSVs and view images are written here
  int views = 40;                     // positions of the distance-evolution path
  int recognitionViews = 10;          // views of the recognition / distribution sequence
  int keypoints = 200;                // ORB keypoints on the texture (projected experiment)
  int bits = DescriptorOptions{}.bits;
  double maskDeg = DescriptorOptions{}.maskRotationDeg;  // mask angle of the projected experiment
  // Detected experiment.
  int detectedViews = 10;
  int detectedKeypoints = 500;        // detector budget per view
  std::vector<double> maskAngles{10, 15, 20, 25, 30};
  double matchRadiusPx = 3.0;
  // The shared path: the longest for which the texture stays inside this camera's image
  // (the pinhole camera's, so the perspective row of the paper's figure stays complete).
  std::string sharedPathCamera = "pinhole";
  bool runProjected = true;
  bool runDetected = true;
};

// Per camera the summary numbers that docs/RESULTS.md quotes.
struct SimSummary {
  std::string camera;
  std::vector<std::string> methods;
  std::vector<double> recognitionAtLast;  // projected, view recognitionViews
  std::vector<double> bhattacharyyaLast;  // projected, pair 1-recognitionViews
  std::vector<double> patchDistanceLast;  // projected, view `views`
  // Mean over the common keypoints and over views 2..`views` of the distance between a
  // keypoint's descriptors in view 1 and view k (bits, masked distance for masked methods).
  std::vector<double> meanMatchingDistance;
  int commonKeypoints = 0;
};

// Largest displacement (px) between the radial camera's image of a ray and the pinhole image
// of the same ray, over the radial image's border pixels (where it is largest), for a radial
// camera and the pinhole camera with the same intrinsics.
double maxRadialDisplacement(const Camera& radial, const Camera& pinhole);

// Runs the projected experiment for one camera along a translation of length xEnd; writes
// sim_<name>_*.csv. Throws std::runtime_error naming the file on unreadable input.
SimSummary runProjectedSimulation(const SimCamera& camera, double xEnd, const SimOptions& options);

// Runs the detected experiment for one camera in three variants: "rolled" (translation, yaw,
// pitch and a 45 degree roll; oriented descriptors), "upright" (no roll; descriptors without
// orientation, as the paper's fig. "Ignoring patch orientation") and "upright_oriented" (no
// roll, oriented descriptors). Oriented variants also run dBRIEF / mdBRIEF with the detector's
// angle ("-kp") next to the default tangent-plane angle.
// Writes sim_detected_<name>_<variant>.csv and ..._summary.csv.
void runDetectedSimulation(const SimCamera& camera, const SimOptions& options);

// Runs what the options enable for every camera, plus sim_info.csv (path lengths, radial
// displacement). Prints a short progress line per experiment to stderr.
void runSimulation(const std::vector<SimCamera>& cameras, const SimOptions& options);

// Bhattacharyya coefficient of two histograms (normalised internally); 0 if either is empty.
double bhattacharyya(const std::vector<double>& p, const std::vector<double>& q);

}  // namespace mdbrief::eval

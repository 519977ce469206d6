#pragma once
// SURF's fast-Hessian detector (Bay, Ess, Tuytelaars, Van Gool, "Speeded-Up Robust Features",
// CVIU 2008), written from the paper because Debian's OpenCV has no xfeatures2d:
// - an integral image; box-filter approximations Dxx, Dyy, Dxy of the Gaussian second
//   derivatives at filter sizes L = 9, 15, 21, 27 (octave 1), 15, 27, 39, 51 (octave 2), ...,
//   sampled every 2^(octave-1) pixels; response det(H) = Dxx Dyy - (0.9 Dxy)^2, area-normalised;
// - 3x3x3 non-maximum suppression in (x, y, scale) and a quadratic (Taylor) refinement of
//   position and scale;
// - orientation from Haar-wavelet responses of size 4s in a circle of radius 6s, Gaussian
//   weighted (sigma 2.5s), the longest vector sum over a sliding pi/3 window.
// Keypoints: pt in pixels, size = 20s (the SURF descriptor window, s = 1.2 L / 9), angle in
// degrees (cv::KeyPoint convention, y down, [0, 360)), response = det(H), octave = SURF octave
// (0-based) and class_id = sign of the Laplacian (1 bright blob on dark, 0 otherwise).
#include <vector>

#include <opencv2/core.hpp>

namespace mdbrief::train {

struct SurfOptions {
  int octaves = 4;                   // paper: 4
  // det(H) threshold for 8-bit intensities (0..255); 26 = 0.0004 for intensities in [0, 1].
  double hessianThreshold = 26.0;
  bool upright = false;              // true: skip the orientation (angle = -1)
  int maxKeypoints = 0;              // keep the strongest N (0 = all)
};

// image: 8UC1. Output sorted by response (descending), then y, then x.
// Throws std::invalid_argument on an empty image or another type.
std::vector<cv::KeyPoint> detectSurf(const cv::Mat& image, const SurfOptions& options = {});

}  // namespace mdbrief::train

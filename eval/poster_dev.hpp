#pragma once
// The real fisheye frames of ../shared/data/fisheye/poster-dev: ten 752x480 frames of one
// OCamCalib lens looking at a hand-held printed poster, with the poster's pose per frame
// (ground_truth.json, its README). For evaluation and for choosing defaults, never for training:
// its frames are in configs/held-out-images.txt.
//
// Ground truth, read with the project's own OCamCalib model (loadCamera of calib_results.txt):
// frame i pixel -> bearing -> poster point (G_i^-1) -> G_j -> bearing -> frame j pixel; valid on
// the printed region, in front of both cameras, within the file's incidence limit in both frames
// and inside both frames' poster masks (masks/m<k>_poster.png: hand and glare removed).
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "eval_datasets.hpp"

namespace mdbrief::eval {

struct PosterFrame {
  int id = 0;              // k of m<k>.jpg
  std::string path;        // the frame's file
  cv::Mat image;           // CV_8UC1
  cv::Matx33d g;           // pattern pixel (x, y, 1) -> ray (X right, Y down, Z forward), up to a positive factor
  cv::Matx33d gInverse;
  cv::Mat mask;            // CV_8UC1, nonzero = visible poster
};

struct PosterDev {
  CameraPtr camera;
  std::vector<PosterFrame> frames;
  cv::Rect2d printed;      // the printed region, pattern pixels (x0, y0, x1 - x0, y1 - y0)
  double maxIncidenceDeg = 88.0;

  // Frame a's pixel in frame b (indices into frames), empty where the ground truth does not hold.
  std::optional<cv::Point2d> map(int a, int b, const cv::Point2d& pixel) const;
};

// Reads dir/ground_truth.json, its calibration, masks and frames. Throws std::runtime_error
// naming the file at fault and why (missing, unreadable, malformed, a size that differs from the
// calibration).
PosterDev loadPosterDev(const std::string& dir);

// Every pair (i < j) of the frames as an evaluation sequence (45 pairs for 10 frames); the
// regions are the poster masks, the baseline is set (the poster is seen from many places).
EvalSequence posterDevSequence(const PosterDev& poster);

}  // namespace mdbrief::eval

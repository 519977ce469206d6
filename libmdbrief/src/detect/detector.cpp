#include "mdbrief/detect/detector.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <tuple>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <tbb/parallel_for.h>

#include "detect/blob_localisation.hpp"
#include "detect/conformal_view.hpp"
#include "detect/candidate.hpp"
#include "detect/harris.hpp"
#include "detect/hessian.hpp"
#include "detect/orientation.hpp"
#include "detect/quadtree.hpp"
#include "detect/resize_kernels.hpp"
#include "mdbrief/internal/base/size_text.hpp"

namespace mdbrief {

namespace {

using internal::sizeText;

// Corners of one level inside `inner` (level pixels). FAST/AGAST ignore the 3 pixels next
// to their input's border, so they run on `inner` grown by 3: no work is wasted on the
// margin and every corner lands inside `inner`.
std::vector<cv::KeyPoint> fastOrAgastCorners(const cv::Mat& image, const cv::Rect& inner,
                                             CornerDetector kind, int threshold) {
  const cv::Rect roi(inner.x - 3, inner.y - 3, inner.width + 6, inner.height + 6);
  std::vector<cv::KeyPoint> corners;
  if (kind == CornerDetector::Fast)
    cv::FAST(image(roi), corners, threshold, true, cv::FastFeatureDetector::TYPE_9_16);
  else
    cv::AGAST(image(roi), corners, threshold, true, cv::AgastFeatureDetector::OAST_9_16);
  for (cv::KeyPoint& corner : corners) corner.pt += cv::Point2f(roi.tl());
  return corners;
}

// The output order of detect(): response (descending), then y, x, octave. An object, which the
// sorts inline: a function's address cost them a call per comparison.
constexpr auto strongerKeypoint = [](const cv::KeyPoint& a, const cv::KeyPoint& b) {
  if (a.response != b.response) return a.response > b.response;
  return std::tie(a.pt.y, a.pt.x, a.octave) < std::tie(b.pt.y, b.pt.x, b.octave);
};

// cv::Feature2D's mask semantics: the mask (empty = everything) allows the pixel nearest the
// keypoint's own position (input pixels), the position detect() returns.
bool maskAllows(const cv::Mat& mask, const cv::Point2f& position) {
  if (mask.empty()) return true;
  const int x = cvRound(position.x), y = cvRound(position.y);
  return x >= 0 && y >= 0 && x < mask.cols && y < mask.rows && mask.at<uchar>(y, x) != 0;
}

// The input-pixel position of a corner at level pixel (x, y), and of a blob refined to sub-pixel
// position on its level: the keypoints' pt.
cv::Point2f cornerPosition(int x, int y, const LevelGrid& grid) {
  return grid.toInput(cv::Point2d(x, y));
}
cv::Point2f blobPosition(const detail::Blob& b, const LevelGrid& grid) {
  return grid.toInput(cv::Point2d(b.x + b.dx, b.y + b.dy));
}

}  // namespace

// Per pyramid level of a valid-area mask (255 = valid): the pixels whose distance (level pixels)
// to the nearest invalid pixel is at least `margin`. The mask is resampled like the image and a
// level pixel counts as valid only if everything it was resampled from was (255 after resizing).
std::vector<Detector::MarginRuns> Detector::keepingMargin(const cv::Mat& validMask, const PyramidOptions& pyramid,
                                                          int margin) {
  const ImagePyramid area(validMask, pyramid);
  std::vector<MarginRuns> kept(area.levels());
  for (int level = 0; level < area.levels(); ++level) {
    cv::Mat valid, distance;
    cv::compare(area.image(level), 255, valid, cv::CMP_EQ);
    cv::distanceTransform(valid, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
    MarginRuns& runs = kept[level];
    runs.rowStart.assign(1, 0);
    for (int y = 0; y < distance.rows; ++y) {
      const float* row = distance.ptr<float>(y);
      for (int x = 0; x < distance.cols;) {
        if (!(row[x] >= margin)) {
          ++x;
          continue;
        }
        const int begin = x;
        while (x < distance.cols && row[x] >= margin) ++x;
        runs.runs.emplace_back(begin, x);
      }
      runs.rowStart.push_back(static_cast<int>(runs.runs.size()));
    }
  }
  return kept;
}

bool Detector::MarginRuns::contains(int x, int y) const {
  for (int i = rowStart[y]; i < rowStart[y + 1]; ++i)
    if (x >= runs[i][0] && x < runs[i][1]) return true;
  return false;
}

std::vector<int> featuresPerLevel(int nfeatures, int levels, double scaleFactor) {
  if (nfeatures < 0) throw std::invalid_argument("featuresPerLevel: nfeatures must be >= 0");
  if (levels < 1) throw std::invalid_argument("featuresPerLevel: levels must be >= 1");
  if (!(scaleFactor > 1.0) || !std::isfinite(scaleFactor))
    throw std::invalid_argument("featuresPerLevel: scaleFactor must be a finite number > 1");
  // Geometric series n0 * f^k, f = 1 / scaleFactor, summing to nfeatures over the levels.
  const double factor = 1.0 / scaleFactor;
  double share = nfeatures * (1.0 - factor) / (1.0 - std::pow(factor, levels));
  std::vector<int> perLevel(levels);
  int assigned = 0;
  for (int level = 0; level + 1 < levels; ++level) {
    perLevel[level] = std::min(nfeatures - assigned, static_cast<int>(std::lround(share)));
    assigned += perLevel[level];
    share *= factor;
  }
  perLevel[levels - 1] = nfeatures - assigned;
  return perLevel;
}

cv::Mat validAreaMask(const Camera& camera, cv::Size size) {
  if (size.width <= 0 || size.height <= 0)
    throw std::invalid_argument("validAreaMask: empty image size " + sizeText(size));
  std::shared_ptr<Camera> resized;
  const Camera* model = &camera;
  if (size != camera.imageSize()) {
    resized = camera.resized(size);
    model = resized.get();
  }
  cv::Mat mask(size, CV_8UC1);
  for (int y = 0; y < size.height; ++y) {
    uchar* row = mask.ptr<uchar>(y);
    for (int x = 0; x < size.width; ++x) row[x] = model->isValid(cv::Point2d(x, y)) ? 255 : 0;
  }
  return mask;
}

Detector::Detector(CameraPtr camera, DetectorOptions options)
    : options_(std::move(options)), camera_(std::move(camera)) {
  validate(options_);
  if (!camera_) return;
  keepsMargin_ = keepingMargin(validAreaMask(*camera_, camera_->imageSize()), options_.pyramid, options_.borderMargin);
  if (options_.conformal) {
    conformal_ = std::make_shared<const detail::ConformalView>(camera_);
    conformalKeepsMargin_ = keepingMargin(conformal_->validMask(), options_.pyramid, options_.borderMargin);
  }
}

std::vector<cv::KeyPoint> Detector::detect(const cv::Mat& image, const cv::Mat& mask) const {
  if (image.empty()) throw std::invalid_argument("Detector::detect: the image is empty");
  return detect(ImagePyramid(image, options_.pyramid), mask);
}

std::vector<cv::KeyPoint> Detector::detect(const ImagePyramid& pyramid, const cv::Mat& mask,
                                           bool measureAngles) const {
  if (pyramid.levels() == 0) throw std::invalid_argument("Detector::detect: the pyramid is empty");
  if (pyramid.options().levels != options_.pyramid.levels ||
      pyramid.options().scaleFactor != options_.pyramid.scaleFactor ||
      pyramid.options().firstLevel != options_.pyramid.firstLevel)
    throw std::invalid_argument(
        "Detector::detect: the pyramid's levels/scaleFactor/firstLevel (" +
        std::to_string(pyramid.options().levels) + ", " + std::to_string(pyramid.options().scaleFactor) + ", " +
        std::to_string(pyramid.options().firstLevel) + ") differ from DetectorOptions::pyramid (" +
        std::to_string(options_.pyramid.levels) + ", " + std::to_string(options_.pyramid.scaleFactor) + ", " +
        std::to_string(options_.pyramid.firstLevel) + ")");
  const cv::Size imageSize = pyramid.inputSize();
  if (!mask.empty() && (mask.type() != CV_8UC1 || mask.size() != imageSize))
    throw std::invalid_argument("Detector::detect: the mask must be 8UC1 of the image's size " +
                                sizeText(imageSize) + ", got " + cv::typeToString(mask.type()) + " " +
                                sizeText(mask.size()));
  if (camera_ && camera_->imageSize() != imageSize)
    throw std::invalid_argument("Detector::detect: image size " + sizeText(imageSize) +
                                " differs from the camera's " + sizeText(camera_->imageSize()));

  std::vector<cv::KeyPoint> keypoints;
  if (conformal_) {
    keypoints = detectConformal(pyramid, mask, measureAngles);
  } else {
    // A candidate at level pixel (x, y) keeps borderMargin level pixels from the camera's invalid area.
    const auto allowed = [&](int level, int x, int y) { return !camera_ || keepsMargin_[level].contains(x, y); };
    keypoints = options_.method == DetectorMethod::Hessian
                    ? detectBlobs(pyramid, allowed, mask, options_.nfeatures, measureAngles)
                    : detectCorners(pyramid, allowed, mask, options_.nfeatures, measureAngles);
  }
  std::sort(keypoints.begin(), keypoints.end(), strongerKeypoint);
  return keypoints;
}

std::vector<cv::KeyPoint> Detector::detectCorners(const ImagePyramid& pyramid, const Allowed& allowed,
                                                  const cv::Mat& mask, int budget, bool measureAngles) const {
  const std::vector<int> budgets = featuresPerLevel(budget, options_.pyramid.levels, options_.pyramid.scaleFactor);
  const detail::IntensityCentroid centroid(options_.orientationRadius);
  const int margin = options_.borderMargin;
  std::vector<cv::KeyPoint> keypoints;
  keypoints.reserve(budget);
  for (int level = 0; level < pyramid.levels(); ++level) {
    const cv::Mat& image = pyramid.image(level);
    const LevelGrid grid = pyramid.grid(level);
    const int levelBudget = budgets[level];
    const cv::Rect inner(margin, margin, image.cols - 2 * margin, image.rows - 2 * margin);
    if (levelBudget == 0 || inner.width <= 0 || inner.height <= 0) continue;
    const auto findCandidates = [&](int threshold) {
      std::vector<detail::Candidate> found;
      for (const cv::KeyPoint& corner : fastOrAgastCorners(image, inner, options_.corners, threshold)) {
        const int x = cvRound(corner.pt.x), y = cvRound(corner.pt.y);
        if (allowed(level, x, y) && maskAllows(mask, cornerPosition(x, y, grid))) found.push_back({x, y, 0.f});
      }
      return found;
    };
    std::vector<detail::Candidate> candidates = findCandidates(options_.threshold);
    if (static_cast<int>(candidates.size()) < levelBudget && options_.fallbackThreshold < options_.threshold)
      candidates = findCandidates(options_.fallbackThreshold);
    for (detail::Candidate& c : candidates)
      c.response = detail::harrisResponse(image, c.x, c.y, options_.harrisBlockSize, options_.harrisK);

    if (options_.spread) {
      candidates = detail::spreadWithQuadtree(candidates, levelBudget, inner);
    } else if (static_cast<int>(candidates.size()) > levelBudget) {
      std::nth_element(candidates.begin(), candidates.begin() + levelBudget, candidates.end(),
                       detail::strongerThan);
      candidates.resize(levelBudget);
    }

    for (const detail::Candidate& c : candidates) {
      keypoints.emplace_back(cornerPosition(c.x, c.y, grid), static_cast<float>(options_.patchSize * grid.scale),
                             measureAngles ? centroid.angleDegrees(image, c.x, c.y) : -1.f, c.response, level);
    }
  }
  return keypoints;
}

std::vector<cv::KeyPoint> Detector::detectBlobs(const ImagePyramid& pyramid, const Allowed& allowed,
                                                const cv::Mat& mask, int budget, bool measureAngles) const {
  const int levels = pyramid.levels();
  std::vector<detail::HessianLevel> responses(levels);
  std::vector<LevelGrid> grids(levels);
  for (int k = 0; k < levels; ++k) grids[k] = pyramid.grid(k);
  // The descriptors' smoothed levels when the sigmas and the kernel agree (the defaults): one
  // blur for detection and description.
  const PyramidOptions& po = pyramid.options();
  const bool shared = po.smoothingSigma == options_.hessianSigma &&
                      po.smoothingKernel == detail::hessianTaps(options_.hessianSigma);
  const auto wholeLevel = [&](int k) {
    // Maxima are searched for on the inner levels only (hessianMaxima).
    responses[k] = detail::hessianLevel(pyramid.image(k), options_.hessianSigma, k > 0 && k + 1 < levels,
                                        static_cast<float>(options_.hessianThreshold), options_.borderMargin);
    if (shared) pyramid.adoptSmoothed(k, responses[k].bytes);
  };
  tbb::parallel_for(1, levels, wholeLevel);
  // Level 0, the largest, is read by level 1's candidates alone, 3x3 pixels each: computed at
  // those pixels only when they are few (the same responses; no blob lies on it, so no
  // descriptor needs its smoothing). A candidate costs about what 50 of the whole level's pixels
  // do (avx2, bench BM_Detect; two thirds of them get that far): below 40, the reads are cheaper.
  constexpr size_t kPixelsPerCandidate = 40;
  const cv::Mat& finest = pyramid.image(0);
  if (levels >= 3 && responses[1].candidates.size() * kPixelsPerCandidate < finest.total())
    responses[0] = detail::hessianPoints(finest, options_.hessianSigma);
  else
    wholeLevel(0);
  std::vector<detail::Blob> blobs = detail::hessianMaxima(responses, grids, allowed);
  const double logFactor = std::log(options_.pyramid.scaleFactor);
  const auto refinedScale = [&](const detail::Blob& b) {
    return grids[b.level].scale * std::exp(b.dlevel * logFactor);
  };
  // After the maxima, which choose each blob's scale by the determinant alone: the weight only
  // decides which blobs the budget keeps. scale^e = (level scale)^e factor^(dlevel e): each
  // level's power once and one exponential a blob, where pow on every blob was a measurable share
  // of the detection.
  if (const double e = options_.hessianScaleExponent; e != 0.0) {
    std::vector<double> levelWeight(grids.size());
    for (size_t k = 0; k < grids.size(); ++k) levelWeight[k] = std::pow(grids[k].scale, e);
    for (detail::Blob& b : blobs)
      b.response = static_cast<float>(b.response * levelWeight[b.level] * std::exp(e * b.dlevel * logFactor));
  }
  // The mask after the refinement, which moves a blob up to half a level pixel from its maximum
  // (several input pixels on coarse levels), and before the budget, which it must not eat.
  if (!mask.empty())
    blobs.erase(std::remove_if(blobs.begin(), blobs.end(),
                               [&](const detail::Blob& b) { return !maskAllows(mask, blobPosition(b, grids[b.level])); }),
                blobs.end());

  if (options_.spread) {
    // One quadtree over the whole image, in input pixels: blobs of every level compete.
    std::vector<detail::Candidate> candidates;
    candidates.reserve(blobs.size());
    for (size_t i = 0; i < blobs.size(); ++i) {
      const detail::Blob& b = blobs[i];
      const cv::Point2f p = blobPosition(b, grids[b.level]);
      candidates.push_back({cvRound(p.x), cvRound(p.y), b.response, static_cast<int>(i)});
    }
    std::vector<detail::Blob> kept;
    for (const detail::Candidate& c : detail::spreadWithQuadtree(candidates, budget,
                                                                 cv::Rect(cv::Point(), pyramid.inputSize())))
      kept.push_back(blobs[c.id]);
    blobs = std::move(kept);
  } else if (static_cast<int>(blobs.size()) > budget) {
    std::nth_element(blobs.begin(), blobs.begin() + budget, blobs.end(),
                     [](const detail::Blob& a, const detail::Blob& b) { return detail::strongerBlob(a, b); });
    blobs.resize(budget);
  }

  // Each kept blob located again on the input image at its own scale (blob_localisation.hpp):
  // after the budget, which the level positions decide, so that only the blobs kept pay for it.
  // Blobs of the input's own level keep their position (it is the input's), and so do those of
  // enlarged levels (interpolated from it), the widest ones, and a blob that the input moves by
  // more than a level pixel, or outside the mask or the camera's margin.
  std::vector<cv::Point2f> positions(blobs.size());
  const int input = pyramid.options().firstLevel;
  const auto relocalised = [&](const detail::Blob& b) {
    const double sigma = options_.hessianSigma * refinedScale(b);
    return options_.relocalise && b.level > input && sigma <= detail::kMaxSigma;
  };
  cv::Mat half;
  for (const detail::Blob& b : blobs)
    if (relocalised(b) && options_.hessianSigma * refinedScale(b) > detail::kHalvedFromSigma) {
      // cv::pyrDown's bits, in a third of its time (resize_kernels.hpp).
      const cv::Mat& image = pyramid.image(input);
      half.create((image.rows + 1) / 2, (image.cols + 1) / 2, CV_8UC1);
      resize_kernels::halveImage(image.data, image.step, image.cols, image.rows, half.data, half.step);
      break;
    }
  tbb::parallel_for(size_t(0), blobs.size(), [&](size_t i) {
    const detail::Blob& b = blobs[i];
    positions[i] = blobPosition(b, grids[b.level]);
    if (!relocalised(b)) return;
    const double scale = refinedScale(b);
    const auto found =
        detail::relocaliseBlob(pyramid.image(input), half, positions[i], options_.hessianSigma * scale, scale);
    if (!found || !maskAllows(mask, *found)) return;
    const cv::Point2d onLevel = grids[b.level].toLevel(*found);
    if (!allowed(b.level, cvRound(onLevel.x), cvRound(onLevel.y))) return;
    positions[i] = cv::Point2f(*found);
  });
  const detail::IntensityCentroid centroid(options_.orientationRadius);
  std::vector<cv::KeyPoint> keypoints;
  keypoints.reserve(blobs.size());
  for (size_t i = 0; i < blobs.size(); ++i) {
    const detail::Blob& b = blobs[i];
    keypoints.emplace_back(positions[i], static_cast<float>(options_.patchSize * refinedScale(b)),
                           measureAngles ? centroid.angleDegrees(pyramid.image(b.level), b.x, b.y) : -1.f,
                           b.response, b.level);
  }
  return keypoints;
}

std::vector<cv::KeyPoint> Detector::detectConformal(const ImagePyramid& pyramid, const cv::Mat& mask,
                                                    bool measureAngles) const {
  const int margin = options_.borderMargin;
  const ImagePyramid view(conformal_->remap(pyramid.image(pyramid.options().firstLevel)), options_.pyramid);
  const auto inView = [&](int level, int x, int y) { return conformalKeepsMargin_[level].contains(x, y); };
  // Some keypoints are lost on the way back (the margin, in camera pixels, is wider where the view
  // magnifies): detect a quarter more, keep the strongest nfeatures of those that survive.
  const int budget = options_.nfeatures + (options_.nfeatures + 3) / 4;
  std::vector<cv::KeyPoint> found = options_.method == DetectorMethod::Hessian
                                        ? detectBlobs(view, inView, cv::Mat(), budget, false)
                                        : detectCorners(view, inView, cv::Mat(), budget, false);
  // Back to the camera image: position and size through the camera model, octave = the level
  // whose scale is nearest the size's, which must keep the margin there too.
  const detail::IntensityCentroid centroid(options_.orientationRadius);
  std::vector<cv::KeyPoint> keypoints;
  keypoints.reserve(found.size());
  for (const cv::KeyPoint& k : found) {
    cv::Point2d pixel;
    double scale = 0;
    if (!conformal_->toCamera(cv::Point2d(k.pt.x, k.pt.y), pixel, scale)) continue;
    const double size = k.size * scale;
    int level = 0;
    for (int j = 1; j < pyramid.levels(); ++j)
      if (std::abs(std::log(size / (options_.patchSize * pyramid.scale(j)))) <
          std::abs(std::log(size / (options_.patchSize * pyramid.scale(level)))))
        level = j;
    const cv::Point2d onLevel = pyramid.grid(level).toLevel(pixel);
    const int x = cvRound(onLevel.x), y = cvRound(onLevel.y);
    const cv::Mat& image = pyramid.image(level);
    if (x < margin || y < margin || x >= image.cols - margin || y >= image.rows - margin) continue;
    if (!keepsMargin_[level].contains(x, y)) continue;
    const cv::Point2f position(static_cast<float>(pixel.x), static_cast<float>(pixel.y));
    if (!maskAllows(mask, position)) continue;
    keypoints.emplace_back(position, static_cast<float>(size),
                           measureAngles ? centroid.angleDegrees(image, x, y) : -1.f, k.response, level);
  }
  if (static_cast<int>(keypoints.size()) > options_.nfeatures) {
    std::nth_element(keypoints.begin(), keypoints.begin() + options_.nfeatures, keypoints.end(),
                     strongerKeypoint);
    keypoints.resize(options_.nfeatures);
  }
  return keypoints;
}

}  // namespace mdbrief

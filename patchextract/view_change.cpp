#include "patchextract/view_change.hpp"

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace mdbrief::train {

namespace {

// Uniform in [lo, hi) from the raw engine output: std::uniform_real_distribution is not
// specified bit for bit across standard libraries.
double uniform(std::mt19937& rng, double lo, double hi) { return lo + (hi - lo) * (rng() / 4294967296.0); }

cv::Matx33d axisAngle(const cv::Vec3d& axis, double angle) {
  cv::Matx33d r;
  cv::Rodrigues(cv::Vec3d(axis * angle), r);
  return r;
}

struct Draw {
  cv::Matx33d rotation;  // tilt about a random in-plane axis, then roll about the optical axis
  double zoom, blur, noise;
};

Draw drawChange(const ViewChangeOptions& o, uint64_t seed) {
  std::seed_seq seq{static_cast<uint32_t>(seed), static_cast<uint32_t>(seed >> 32)};
  std::mt19937 rng(seq);
  const double axis = uniform(rng, 0, 2 * CV_PI);
  const double tilt = uniform(rng, 0, o.maxTiltDeg) * CV_PI / 180;
  const double roll = uniform(rng, -o.maxRollDeg, o.maxRollDeg) * CV_PI / 180;
  const double zoom = std::exp(uniform(rng, -1, 1) * std::log(o.maxZoom));
  const double blur = uniform(rng, 0, o.maxBlurSigma), noise = uniform(rng, 0, o.maxNoiseSigma);
  const cv::Matx33d r = axisAngle({0, 0, 1}, roll) * axisAngle({std::cos(axis), std::sin(axis), 0}, tilt);
  return {r, zoom, blur, noise};
}

// Perspective: source pixel -> view pixel by a homography about the image centre.
class HomographyChange : public ViewChange {
 public:
  HomographyChange(cv::Size size, const Draw& d) : size_(size) {
    const double f = size.width, cx = size.width / 2.0, cy = size.height / 2.0;
    const cv::Matx33d k(f, 0, cx, 0, f, cy, 0, 0, 1);
    const cv::Matx33d zoom(d.zoom, 0, (1 - d.zoom) * cx, 0, d.zoom, (1 - d.zoom) * cy, 0, 0, 1);
    h_ = zoom * k * d.rotation * k.inv();
    inv_ = h_.inv();
  }
  bool toView(const cv::Point2d& s, cv::Point2d& v) const override { return apply(h_, s, v); }
  bool toSource(const cv::Point2d& v, cv::Point2d& s) const override { return apply(inv_, v, s); }
  CameraPtr viewCamera() const override { return nullptr; }
  cv::Size viewSize() const override { return size_; }

 private:
  static bool apply(const cv::Matx33d& h, const cv::Point2d& p, cv::Point2d& out) {
    const cv::Vec3d q = h * cv::Vec3d(p.x, p.y, 1);
    if (!(q[2] > 1e-9)) return false;  // the point is behind the turned camera
    out = {q[0] / q[2], q[1] / q[2]};
    return true;
  }
  cv::Size size_;
  cv::Matx33d h_, inv_;
};

// Fisheye: the lens turned by a rotation and resampled by the zoom.
class RotationChange : public ViewChange {
 public:
  RotationChange(CameraPtr camera, const cv::Matx33d& rotation, double zoom)
      : source_(std::move(camera)), rotation_(rotation) {
    const cv::Size s = source_->imageSize();
    view_ = zoom == 1.0 ? source_
                        : source_->resized({static_cast<int>(std::lround(s.width * zoom)),
                                            static_cast<int>(std::lround(s.height * zoom))});
  }
  bool toView(const cv::Point2d& s, cv::Point2d& v) const override {
    cv::Vec3d b;
    return source_->isValid(s) && source_->pixelToBearing(s, b) && view_->bearingToPixel(rotation_ * b, v) &&
           view_->isValid(v);
  }
  bool toSource(const cv::Point2d& v, cv::Point2d& s) const override {
    cv::Vec3d b;
    return view_->isValid(v) && view_->pixelToBearing(v, b) && source_->bearingToPixel(rotation_.t() * b, s) &&
           source_->isValid(s);
  }
  CameraPtr viewCamera() const override { return view_; }
  cv::Size viewSize() const override { return view_->imageSize(); }

 private:
  CameraPtr source_, view_;
  cv::Matx33d rotation_;
};

}  // namespace

cv::Mat ViewChange::render(const cv::Mat& source, uint64_t noiseSeed) const {
  CV_Assert(source.type() == CV_8UC1);
  const cv::Size size = viewSize();
  cv::Mat mapX(size, CV_32F), mapY(size, CV_32F);
  cv::parallel_for_(cv::Range(0, size.height), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y)
      for (int x = 0; x < size.width; ++x) {
        cv::Point2d s;
        const bool ok = toSource({double(x), double(y)}, s);
        mapX.at<float>(y, x) = ok ? static_cast<float>(s.x) : -1e6f;
        mapY.at<float>(y, x) = ok ? static_cast<float>(s.y) : -1e6f;
      }
  });
  // Where the view shrinks the source, low-pass it first so the bilinear resampling does not
  // alias (sigma of a Gaussian matching the footprint of one view pixel).
  const double zoom = localZoom({source.cols / 2.0, source.rows / 2.0});
  // Into a buffer of its own: a header copy of `source` would blur the caller's image in place.
  cv::Mat src = source;
  if (zoom > 0 && zoom < 0.95) {
    cv::Mat blurred;
    cv::GaussianBlur(source, blurred, {0, 0}, 0.5 * std::sqrt(1 / (zoom * zoom) - 1));
    src = blurred;
  }
  cv::Mat view;
  cv::remap(src, view, mapX, mapY, cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0);
  if (blurSigma > 0.05) cv::GaussianBlur(view, view, {0, 0}, blurSigma);
  if (noiseSigma > 0.05) {
    cv::Mat noise(size, CV_32F);
    cv::RNG rng(noiseSeed | 1);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, noiseSigma);
    cv::Mat sum;
    view.convertTo(sum, CV_32F);
    sum += noise;
    sum.convertTo(view, CV_8U);
  }
  return view;
}

double ViewChange::localZoom(const cv::Point2d& s) const {
  cv::Point2d c, x, y;
  if (!toView(s, c) || !toView(s + cv::Point2d(1, 0), x) || !toView(s + cv::Point2d(0, 1), y)) return 0;
  const cv::Point2d dx = x - c, dy = y - c;
  return std::sqrt(std::abs(dx.x * dy.y - dx.y * dy.x));
}

std::unique_ptr<ViewChange> randomViewChange(cv::Size size, const CameraPtr& camera, const ViewChangeOptions& o,
                                             uint64_t seed) {
  validate(o);
  const Draw d = drawChange(o, seed);
  std::unique_ptr<ViewChange> change;
  if (camera)
    change = std::make_unique<RotationChange>(camera, d.rotation, d.zoom);
  else
    change = std::make_unique<HomographyChange>(size, d);
  change->blurSigma = d.blur;
  change->noiseSigma = d.noise;
  return change;
}

std::unique_ptr<ViewChange> lensRotation(const CameraPtr& camera, const cv::Matx33d& rotation) {
  if (!camera) throw std::invalid_argument("lensRotation: needs a camera");
  return std::make_unique<RotationChange>(camera, rotation, 1.0);
}

}  // namespace mdbrief::train

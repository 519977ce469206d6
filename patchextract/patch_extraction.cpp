#include "patchextract/patch_extraction.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "mdbrief/camera/io.hpp"
#include "mdbrief/detect/detector.hpp"
#include "mdbrief/detect/image_pyramid.hpp"
#include "mdbrief/internal/describe/patch_sampling.hpp"
#include "mdbrief/internal/base/size_text.hpp"
#include "mdbrief/describe/comparison_set.hpp"
#include "patchextract/patch_sampler.hpp"
#include "toolkit/image_file.hpp"
#include "scenes/plane_renderer.hpp"

namespace mdbrief::train {

namespace fs = std::filesystem;

namespace {

// The pyramid the library's defaults describe on (its levels and smoothing), so that training
// patches are sampled as the run time samples them.
const PyramidOptions kTrainingPyramid = DetectorOptions{}.pyramid;


bool isImageFile(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  for (const char* e : {".png", ".jpg", ".jpeg", ".pgm", ".ppm", ".bmp", ".tif", ".tiff"})
    if (ext == e) return true;
  return false;
}

using internal::sizeText;

// The camera for an image: the calibration itself, or the same lens resampled to the image's
// size when the aspect ratio agrees. Null with a reason otherwise.
CameraPtr cameraFor(const CameraPtr& camera, cv::Size size, std::string& reason) {
  const cv::Size c = camera->imageSize();
  if (c == size) return camera;
  if (std::abs(double(size.width) * c.height - double(size.height) * c.width) >
      0.01 * double(c.width) * size.height) {
    reason = "size " + sizeText(size) + " does not match the camera's " + sizeText(c);
    return nullptr;
  }
  return camera->resized(size);
}

// One changed view of an image and, per usable reference keypoint, its keypoint there.
struct View {
  cv::Mat image;
  CameraPtr camera;
  std::vector<cv::KeyPoint> keypoints;  // usable in the view
};

// A reference keypoint's counterpart: view index and keypoint index in that view.
struct Counterpart {
  int view;
  int keypoint;
};

struct ImageKeypoints {
  std::vector<cv::KeyPoint> usable;  // strongest first; size = patch diameter
  std::vector<std::vector<Counterpart>> counterparts;  // per usable keypoint (with views)
  CameraPtr camera;                  // the camera at this image's size (null: perspective)
  cv::Mat rendered;                  // renderThroughCamera: the rendering, reused by pass 2
  std::vector<View> views;
  size_t beforeViewCheck = 0;
  std::string digest;
  bool heldOut = false;
  bool otherSize = false;  // no camera for its size
  std::string skipReason;
};

cv::Mat renderThrough(const Camera& camera, const cv::Mat& photo, double halfFovDeg) {
  PlaneScene scene{photo, std::tan(halfFovDeg * CV_PI / 180.0) / (photo.cols / 2.0)};
  RenderOptions ro;
  ro.supersampling = 2;
  return renderPlane(camera, CameraPose{}, scene, ro);
}

// The keypoints whose whole patch can be sampled (camera: null = the photo camera).
std::vector<cv::KeyPoint> detectUsable(const cv::Mat& grey, const ExtractionOptions& o, const CameraPtr& camera) {
  const ImagePyramid pyramid(grey, kTrainingPyramid);
  std::vector<cv::KeyPoint> detected = detectKeypoints(grey, o.detector, o.keypointsPerImage);
  for (auto& kp : detected) kp.size = static_cast<float>(patchDiameter(o.detector, kp));
  std::vector<cv::KeyPoint> usable;
  uint8_t patch[kPatchSize * kPatchSize];
  float angle;
  for (const auto& kp : detected)
    if (samplePatch(o.placement, camera.get(), pyramid, kp, patch, angle)) usable.push_back(kp);
  return usable;
}

// Seed of view k of image i: distinct per (seed, image, view), the same on every platform.
uint64_t viewSeed(uint32_t seed, size_t image, int view) {
  return (uint64_t(seed) << 32) ^ (uint64_t(image) * 0x9E3779B97F4A7C15ull) ^ (uint64_t(view + 1) * 0xBF58476D1CE4E5B9ull);
}

// True when the whole footprint of a view keypoint sees the source image (not the empty border
// of the warped view): its corners, with the rotation's margin, map back inside.
bool footprintSeesSource(const ViewChange& change, const cv::KeyPoint& kp, cv::Size sourceSize) {
  const double r = kp.size / internal::kReferenceKeypointSize * kPatchHalf * std::sqrt(2.0) + 1;
  for (int k = 0; k < 8; ++k) {
    const double a = k * CV_PI / 4;
    cv::Point2d s;
    if (!change.toSource({kp.pt.x + r * std::cos(a), kp.pt.y + r * std::sin(a)}, s)) return false;
    if (!(s.x >= 0 && s.y >= 0 && s.x <= sourceSize.width - 1 && s.y <= sourceSize.height - 1)) return false;
  }
  return true;
}

// The view keypoint nearest to where the change puts `kp`, within the radius and size ratio;
// -1 if none (ties to the lower index).
int findCounterpart(const ViewChange& change, const cv::KeyPoint& kp, const std::vector<cv::KeyPoint>& view,
                    const ExtractionOptions& o) {
  cv::Point2d q;
  const double zoom = change.localZoom(kp.pt);
  if (!(zoom > 0) || !change.toView(kp.pt, q)) return -1;
  const double size = kp.size * zoom, radius = o.matchRadius * size / internal::kReferenceKeypointSize;
  const double maxLogRatio = std::log(o.matchSizeRatio);
  int best = -1;
  double bestDist = radius * radius;
  for (size_t j = 0; j < view.size(); ++j) {
    const double dx = view[j].pt.x - q.x, dy = view[j].pt.y - q.y, d = dx * dx + dy * dy;
    if (d <= bestDist && (best < 0 || d < bestDist) && std::abs(std::log(view[j].size / size)) <= maxLogRatio) {
      best = static_cast<int>(j);
      bestDist = d;
    }
  }
  return best;
}

// Loads (and renders), detects and keeps the keypoints whose patch can be sampled completely
// (and, with counterparts, that some changed view finds again).
ImageKeypoints usableKeypoints(const fs::path& path, size_t index, const ExtractionOptions& o,
                               const CameraPtr& camera) {
  ImageKeypoints out;
  cv::Mat grey = decodeGreyImage(path);
  if (grey.empty()) {
    out.skipReason = "unreadable";
    return out;
  }
  // A partly decoded image would train on the decoder's fill.
  if (const std::string problem = truncationProblem(path); !problem.empty()) {
    out.skipReason = problem;
    return out;
  }
  out.digest = imageDigest(grey);
  if (const auto h = o.heldOut.find(out.digest); h != o.heldOut.end()) {
    out.heldOut = true;
    out.skipReason = "held out: an evaluation or validation image";
    return out;
  }
  if (o.renderThroughCamera) {
    grey = out.rendered = renderThrough(*camera, grey, o.renderHalfFovDeg);
    out.camera = camera;
  } else if (camera && !(out.camera = cameraFor(camera, grey.size(), out.skipReason))) {
    out.otherSize = true;
    return out;
  }
  std::vector<cv::KeyPoint> usable = detectUsable(grey, o, out.camera);
  out.beforeViewCheck = usable.size();
  if (o.counterparts > 0) {
    std::vector<std::vector<Counterpart>> found(usable.size());
    for (int k = 0; k < o.counterparts; ++k) {
      const uint64_t seed = viewSeed(o.seed, index, k);
      const auto change = randomViewChange(grey.size(), out.camera, o.viewChange, seed);
      View v{change->render(grey, seed), change->viewCamera(), {}};
      for (const auto& kp : detectUsable(v.image, o, v.camera))
        if (footprintSeesSource(*change, kp, grey.size())) v.keypoints.push_back(kp);
      for (size_t r = 0; r < usable.size(); ++r)
        if (const int j = findCounterpart(*change, usable[r], v.keypoints, o); j >= 0) found[r].push_back({k, j});
      out.views.push_back(std::move(v));
    }
    for (size_t r = 0; r < usable.size(); ++r)
      if (!found[r].empty()) {
        out.usable.push_back(usable[r]);
        out.counterparts.push_back(std::move(found[r]));
      }
  } else {
    out.usable = std::move(usable);
  }
  if (out.usable.empty())
    out.skipReason = o.counterparts > 0 ? "no keypoint with a complete patch found again in a changed view"
                                        : "no keypoint with a complete patch";
  return out;
}

std::string counterpartAttribute(const ExtractionOptions& o) {
  if (o.counterparts == 0) return "none";
  const auto& v = o.viewChange;
  std::ostringstream s;
  s << o.counterparts << " view(s) per image: tilt <= " << v.maxTiltDeg << " deg, roll <= " << v.maxRollDeg
    << " deg, zoom <= " << v.maxZoom << ", blur sigma <= " << v.maxBlurSigma << ", noise sigma <= "
    << v.maxNoiseSigma << "; match radius " << o.matchRadius << " steps, size ratio " << o.matchSizeRatio;
  return s.str();
}

std::string placementAttribute(const DescriptorOptions& p) {
  std::ostringstream s;
  s << "as " << toString(p.kind) << " compute() samples rotation 0: form " << toString(p.form) << ", orientation ";
  if (!p.useOrientation)
    s << "none";
  else if (usesCamera(p.kind) && p.orientation == OrientationSource::TangentPlane)
    s << "tangent-plane (radius " << p.orientationRadius << ")";
  else
    s << "keypoint";
  s << ", support scale " << p.supportScale << ", max incidence " << p.maxIncidenceDeg << " deg, sampling "
    << toString(p.sampling) << "; uncalibrated images through the photo camera (pinhole, f = image width)";
  return s.str();
}

}  // namespace

std::vector<fs::path> listImages(const std::vector<fs::path>& dirs) {
  if (dirs.empty()) throw std::invalid_argument("no image folder given");
  std::vector<fs::path> images;
  for (const auto& dir : dirs) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
      throw std::invalid_argument(dir.string() + ": image folder does not exist");
    const size_t before = images.size();
    for (auto it = fs::recursive_directory_iterator(dir, fs::directory_options::skip_permission_denied, ec);
         !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
      if (it->is_regular_file(ec) && isImageFile(it->path())) images.push_back(it->path());
    if (ec) throw std::invalid_argument(dir.string() + ": cannot list: " + ec.message());
    if (images.size() == before)
      throw std::invalid_argument(dir.string() +
                                  ": no images (png, jpg, jpeg, pgm, ppm, bmp, tif) in the folder");
  }
  std::sort(images.begin(), images.end());
  images.erase(std::unique(images.begin(), images.end()), images.end());
  return images;
}

std::vector<size_t> allocatePatches(const std::vector<size_t>& available, size_t budget) {
  std::vector<size_t> take(available.size(), 0);
  std::vector<size_t> open;
  for (size_t i = 0; i < available.size(); ++i)
    if (available[i] > 0) open.push_back(i);
  size_t remaining = budget;
  // Water filling: images that cannot fill their share give all they have; repeat with the rest.
  while (remaining > 0 && !open.empty()) {
    const size_t share = remaining / open.size(), extra = remaining % open.size();
    std::vector<size_t> still;
    bool saturated = false;
    for (size_t k = 0; k < open.size(); ++k) {
      const size_t i = open[k], want = share + (k < extra ? 1 : 0);
      if (available[i] - take[i] <= want) {
        remaining -= available[i] - take[i];
        take[i] = available[i];
        saturated = true;
      } else {
        still.push_back(i);
      }
    }
    if (!saturated) {
      for (size_t k = 0; k < still.size(); ++k) take[still[k]] += share + (k < extra ? 1 : 0);
      remaining = 0;
    }
    open = std::move(still);
  }
  return take;
}

PatchSet extractPatches(const ExtractionOptions& o, ExtractionReport& report,
                        const ExtractionProgress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  validate(o);
  if (o.renderThroughCamera && o.cameraPath.empty())
    throw std::invalid_argument("rendering through the camera needs a camera");
  if (o.renderThroughCamera && !(o.renderHalfFovDeg > 0 && o.renderHalfFovDeg < 89))
    throw std::invalid_argument("renderHalfFovDeg must be in (0, 89)");
  if (!(o.matchRadius > 0) || !(o.matchSizeRatio >= 1))
    throw std::invalid_argument("matchRadius must be positive and matchSizeRatio at least 1");
  validate(o.placement);
  CameraPtr camera;
  if (o.cameraPath.empty() && (!o.cameraId.empty() || o.cameraFormat != CameraFormat::Auto))
    throw std::invalid_argument("a camera id or format needs a camera (the calibration file they describe)");
  if (!o.cameraPath.empty()) camera = loadCamera(o.cameraPath, {o.cameraFormat, o.cameraId});
  const std::vector<fs::path> images = listImages(o.imageDirs);
  report = ExtractionReport{};
  report.imagesFound = images.size();

  // Pass 1: the usable keypoints of every image (keypoints only: every usable patch of a large
  // folder would not fit in memory; pass 2 samples the chosen ones).
  std::vector<ImageKeypoints> pools(images.size());
  std::atomic<size_t> done{0};
  tbb::parallel_for(size_t(0), images.size(), [&](size_t i) {
    pools[i] = usableKeypoints(images[i], i, o, camera);
    const size_t n = ++done;
    if (progress) progress("detect", n, images.size());
  });
  std::vector<size_t> available(images.size());
  for (size_t i = 0; i < images.size(); ++i) {
    available[i] = pools[i].usable.size();
    report.usableKeypoints += available[i];
    report.detectedInViews += pools[i].beforeViewCheck;
    report.heldOut += pools[i].heldOut;
    if (!pools[i].skipReason.empty())
      report.skipped.push_back({images[i].string(), pools[i].skipReason, pools[i].heldOut, pools[i].otherSize});
  }
  const std::vector<size_t> take = allocatePatches(available, o.patches);

  // Which keypoints: evenly spaced strength ranks, random phase per image (seed, image index).
  std::vector<std::vector<size_t>> chosen(images.size());
  std::vector<size_t> offset(images.size() + 1, 0), counterpartOffset(images.size() + 1, 0);
  for (size_t i = 0; i < images.size(); ++i) {
    if (take[i] > 0) {
      std::seed_seq seq{o.seed, static_cast<uint32_t>(i)};
      std::mt19937 rng(seq);
      // Phase in [0, 1) from the raw engine output: portable across standard libraries.
      const double phase = rng() / 4294967296.0;
      for (size_t k = 0; k < take[i]; ++k)
        chosen[i].push_back(std::min(static_cast<size_t>((k + phase) * available[i] / take[i]), available[i] - 1));
    }
    size_t counterparts = 0;
    if (o.counterparts > 0)
      for (size_t r : chosen[i]) counterparts += pools[i].counterparts[r].size();
    offset[i + 1] = offset[i] + take[i];
    counterpartOffset[i + 1] = counterpartOffset[i] + counterparts;
  }
  PatchSet set;
  set.records.resize(offset.back());
  set.pixels.assign(offset.back() * kPatchSize * kPatchSize, 0);
  set.counterpartOf.resize(counterpartOffset.back());
  set.counterpartPixels.assign(counterpartOffset.back() * kPatchSize * kPatchSize, 0);
  for (size_t i = 0; i < images.size(); ++i) {
    set.images.push_back(images[i].string());
    set.imageDigests.push_back(pools[i].digest);
  }
  std::vector<char> failed(images.size(), 0);
  done = 0;
  tbb::parallel_for(size_t(0), images.size(), [&](size_t i) {
    if (take[i] > 0) {
      const cv::Mat grey = o.renderThroughCamera ? pools[i].rendered : decodeGreyImage(images[i]);
      const ImagePyramid pyramid(grey.empty() ? cv::Mat(1, 1, CV_8UC1) : grey, kTrainingPyramid);
      pyramid.prepareSmoothed(-1);
      std::vector<ImagePyramid> views;
      for (const auto& v : pools[i].views) {
        views.emplace_back(v.image, kTrainingPyramid);
        views.back().prepareSmoothed(-1);
      }
      size_t c = counterpartOffset[i];
      for (size_t k = 0; k < take[i] && !failed[i]; ++k) {
        const size_t rank = chosen[i][k];
        const cv::KeyPoint& kp = pools[i].usable[rank];
        const size_t slot = offset[i] + k;
        // Fails only if the file changed since the first pass.
        float angle = kp.angle;
        failed[i] = !samplePatch(o.placement, pools[i].camera.get(), pyramid, kp,
                                 set.pixels.data() + slot * kPatchSize * kPatchSize, angle);
        set.records[slot] = {static_cast<int32_t>(i), kp.pt.x, kp.pt.y, kp.size, angle,
                             kp.response, static_cast<uint8_t>(o.detector)};
        if (o.counterparts == 0) continue;
        for (const Counterpart& cp : pools[i].counterparts[rank]) {
          const View& v = pools[i].views[cp.view];
          // The view keypoint's patch was sampled in pass 1 on this very image.
          float viewAngle;
          failed[i] = failed[i] || !samplePatch(o.placement, v.camera.get(), views[cp.view], v.keypoints[cp.keypoint],
                                                set.counterpartPixels.data() + c * kPatchSize * kPatchSize, viewAngle);
          set.counterpartOf[c++] = static_cast<int32_t>(slot);
        }
      }
    }
    const size_t n = ++done;
    if (progress) progress("sample", n, images.size());
  });
  for (size_t i = 0; i < images.size(); ++i)
    if (failed[i]) throw std::runtime_error(images[i].string() + ": changed during extraction");
  pools.clear();
  for (size_t t : take) report.imagesUsed += t > 0;

  set.attributes = {{"detector", detectorName(o.detector)},
                    {"seed", std::to_string(o.seed)},
                    {"patch_budget", std::to_string(o.patches)},
                    {"keypoints_per_image", std::to_string(o.keypointsPerImage)},
                    {"camera", o.cameraPath.empty() ? "none"
                               : o.cameraPath + (o.cameraId.empty() ? "" : " (camera " + o.cameraId + ")")},
                    {"render_through_camera",
                     o.renderThroughCamera ? "half fov " + std::to_string(o.renderHalfFovDeg) + " deg"
                                           : "no"},
                    {"counterparts", counterpartAttribute(o)},
                    {"placement", placementAttribute(o.placement)},
                    {"smoothing", "Gaussian 7x7 sigma 2 per pyramid level (8 levels, 1.2)"},
                    {"scale_convention", "scale = patch diameter in level-0 pixels, 31 = step 1"}};
  report.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return set;
}

}  // namespace mdbrief::train

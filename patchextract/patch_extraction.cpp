#include "patchextract/patch_extraction.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <random>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>
#include <tbb/parallel_for.h>

#include "mdbrief/camera_io.hpp"
#include "mdbrief/image_pyramid.hpp"
#include "mdbrief/plane_renderer.hpp"
#include "mdbrief/test_set.hpp"
#include "patchextract/patch_sampler.hpp"

namespace mdbrief::train {

namespace fs = std::filesystem;

namespace {

bool isImageFile(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  for (const char* e : {".png", ".jpg", ".jpeg", ".pgm", ".ppm", ".bmp", ".tif", ".tiff"})
    if (ext == e) return true;
  return false;
}

std::string sizeText(cv::Size s) { return std::to_string(s.width) + "x" + std::to_string(s.height); }

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

struct ImageKeypoints {
  std::vector<cv::KeyPoint> usable;  // strongest first; size = patch diameter
  CameraPtr camera;                  // the camera at this image's size (null: perspective)
  cv::Mat rendered;                  // renderThroughCamera: the rendering, reused by pass 2
  std::string skipReason;
};

cv::Mat loadGrey(const fs::path& path) { return cv::imread(path.string(), cv::IMREAD_GRAYSCALE); }

cv::Mat renderThrough(const Camera& camera, const cv::Mat& photo, double halfFovDeg) {
  PlaneScene scene{photo, std::tan(halfFovDeg * CV_PI / 180.0) / (photo.cols / 2.0)};
  RenderOptions ro;
  ro.supersampling = 2;
  return renderPlane(camera, CameraPose{}, scene, ro);
}

// Loads (and renders), detects and keeps the keypoints whose patch can be sampled completely.
ImageKeypoints usableKeypoints(const fs::path& path, const ExtractionOptions& o,
                               const CameraPtr& camera) {
  ImageKeypoints out;
  cv::Mat grey = loadGrey(path);
  if (grey.empty()) {
    out.skipReason = "unreadable";
    return out;
  }
  if (o.renderThroughCamera) {
    grey = out.rendered = renderThrough(*camera, grey, o.renderHalfFovDeg);
    out.camera = camera;
  } else if (camera && !(out.camera = cameraFor(camera, grey.size(), out.skipReason))) {
    return out;
  }
  const ImagePyramid pyramid(grey, PyramidOptions{});
  for (cv::KeyPoint kp : detectKeypoints(grey, o.detector, o.keypointsPerImage)) {
    kp.size = static_cast<float>(patchDiameter(o.detector, kp));
    if (patchFits(pyramid, kp, out.camera.get())) out.usable.push_back(kp);
  }
  if (out.usable.empty()) out.skipReason = "no keypoint with a complete patch";
  return out;
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
  if (o.patches == 0) throw std::invalid_argument("patch budget must be positive");
  if (o.keypointsPerImage < 1) throw std::invalid_argument("keypointsPerImage must be positive");
  if (o.renderThroughCamera && o.cameraPath.empty())
    throw std::invalid_argument("rendering through the camera needs a camera");
  if (o.renderThroughCamera && !(o.renderHalfFovDeg > 0 && o.renderHalfFovDeg < 89))
    throw std::invalid_argument("renderHalfFovDeg must be in (0, 89)");
  CameraPtr camera;
  if (!o.cameraPath.empty()) camera = loadCamera(o.cameraPath);
  const std::vector<fs::path> images = listImages(o.imageDirs);
  report = ExtractionReport{};
  report.imagesFound = images.size();

  // Pass 1: the usable keypoints of every image (keypoints only: every usable patch of a large
  // folder would not fit in memory; pass 2 samples the chosen ones).
  std::vector<ImageKeypoints> pools(images.size());
  std::atomic<size_t> done{0};
  tbb::parallel_for(size_t(0), images.size(), [&](size_t i) {
    pools[i] = usableKeypoints(images[i], o, camera);
    const size_t n = ++done;
    if (progress) progress("detect", n, images.size());
  });
  std::vector<size_t> available(images.size());
  for (size_t i = 0; i < images.size(); ++i) {
    available[i] = pools[i].usable.size();
    report.usableKeypoints += available[i];
    if (!pools[i].skipReason.empty()) report.skipped.push_back({images[i].string(), pools[i].skipReason});
  }
  const std::vector<size_t> take = allocatePatches(available, o.patches);

  // Which keypoints: evenly spaced strength ranks, random phase per image (seed, image index).
  std::vector<size_t> offset(images.size() + 1, 0);
  for (size_t i = 0; i < images.size(); ++i) offset[i + 1] = offset[i] + take[i];
  PatchSet set;
  set.records.resize(offset.back());
  set.pixels.assign(offset.back() * kPatchSize * kPatchSize, 0);
  for (const auto& p : images) set.images.push_back(p.string());
  std::vector<char> failed(images.size(), 0);
  done = 0;
  tbb::parallel_for(size_t(0), images.size(), [&](size_t i) {
    if (take[i] > 0) {
      std::seed_seq seq{o.seed, static_cast<uint32_t>(i)};
      std::mt19937 rng(seq);
      // Phase in [0, 1) from the raw engine output: portable across standard libraries.
      const double phase = rng() / 4294967296.0;
      const cv::Mat grey = o.renderThroughCamera ? pools[i].rendered : loadGrey(images[i]);
      const ImagePyramid pyramid(grey.empty() ? cv::Mat(1, 1, CV_8UC1) : grey, PyramidOptions{});
      pyramid.prepareSmoothed(-1);
      for (size_t k = 0; k < take[i] && !failed[i]; ++k) {
        const size_t rank = static_cast<size_t>((k + phase) * available[i] / take[i]);
        const cv::KeyPoint& kp = pools[i].usable[std::min(rank, available[i] - 1)];
        const size_t slot = offset[i] + k;
        // Fails only if the file changed since the first pass.
        failed[i] = !samplePatch(pyramid, kp, pools[i].camera.get(),
                                 set.pixels.data() + slot * kPatchSize * kPatchSize);
        set.records[slot] = {static_cast<int32_t>(i), kp.pt.x, kp.pt.y, kp.size, kp.angle,
                             kp.response, static_cast<uint8_t>(o.detector)};
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
                    {"camera", o.cameraPath.empty() ? "none" : o.cameraPath},
                    {"render_through_camera",
                     o.renderThroughCamera ? "half fov " + std::to_string(o.renderHalfFovDeg) + " deg"
                                           : "no"},
                    {"smoothing", "Gaussian 7x7 sigma 2 per pyramid level (8 levels, 1.2)"},
                    {"scale_convention", "scale = patch diameter in level-0 pixels, 31 = step 1"}};
  report.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return set;
}

}  // namespace mdbrief::train

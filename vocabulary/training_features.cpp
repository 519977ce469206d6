#include "vocabulary/training_features.hpp"

#include <algorithm>
#include <stdexcept>

#include <opencv2/features2d.hpp>

#include "mdbrief/api/feature2d.hpp"
#include "mdbrief/internal/base/io/input_file.hpp"
#include "patchextract/patch_extraction.hpp"
#include "toolkit/image_file.hpp"
#include "scenes/photo_camera.hpp"

namespace mdbrief::vocab {

namespace fs = std::filesystem;

MdBriefOptions mdBriefOptions(const FeatureOptions& o) {
  MdBriefOptions m = presetSettings(o.preset).features;
  if (o.bits) m.descriptor.bits = o.bits;
  m.detector.nfeatures = o.nfeatures;
  validate(m);
  return m;
}

TrainingImage describeImage(const cv::Mat& grey, const FeatureOptions& o, const CameraPtr& camera, const cv::Mat& region) {
  TrainingImage out;
  std::vector<cv::KeyPoint> keypoints;
  if (o.kind == FeatureKind::Orb) {
    cv::ORB::create(o.nfeatures)->detectAndCompute(grey, region, keypoints, out.descriptors);
    if (out.descriptors.empty()) out.descriptors.create(0, 32, CV_8UC1);
    return out;
  }
  const auto f2d = MdBrief::create(camera ? camera : photoCamera(grey.size()), mdBriefOptions(o));
  f2d->detectAndComputeWithMasks(grey, region, keypoints, out.descriptors, out.masks);
  return out;
}

std::vector<fs::path> imageFiles(const std::vector<std::string>& paths) {
  std::vector<fs::path> out;
  for (const auto& p : paths) {
    std::error_code ec;
    if (fs::is_directory(p, ec)) {
      const std::vector<fs::path> found = train::listImages({p});
      out.insert(out.end(), found.begin(), found.end());
    } else if (fs::is_regular_file(p, ec)) {
      out.emplace_back(p);
    } else if (const std::string problem = internal::inputFileProblem(p); problem != "no such file") {
      // A FIFO or a device is named for what it is, not as missing (issue 29).
      throw std::invalid_argument(p + ": " + problem);
    } else {
      throw std::invalid_argument(p + ": no such image or folder");
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

uint64_t digestNumber(const std::string& digest) { return std::stoull(digest, nullptr, 16); }

cv::Mat readTrainingImage(const fs::path& path, const train::HeldOutImages& heldOut, uint64_t& digest) {
  const cv::Mat grey = decodeGreyImage(path);
  if (grey.empty()) throw std::invalid_argument(path.string() + ": cannot be decoded as an image");
  // A partly decoded image would train on the decoder's fill.
  if (const std::string problem = truncationProblem(path); !problem.empty())
    throw std::invalid_argument(path.string() + ": " + problem);
  const std::string d = train::imageDigest(grey);
  if (const auto h = heldOut.find(d); h != heldOut.end())
    throw std::invalid_argument(path.string() + ": held out (it is " + h->second +
                                ", which an evaluation uses); training on it would measure the vocabulary on its "
                                "own training data");
  digest = digestNumber(d);
  return grey;
}

}  // namespace mdbrief::vocab

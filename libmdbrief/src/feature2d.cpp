#include "mdbrief/feature2d.hpp"

#include <stdexcept>
#include <utility>

#include "mdbrief/image_pyramid.hpp"
#include "mdbrief/internal/size_text.hpp"

namespace mdbrief {
namespace {

// FileNode readers: a missing key keeps `value`; a present key of the wrong type throws.
std::string keyName(const cv::FileNode& node, const char* key) {
  return node.name().empty() ? std::string(key) : node.name() + "." + key;
}

void readInt(const cv::FileNode& node, const char* key, int& value) {
  const cv::FileNode n = node[key];
  if (n.empty()) return;
  if (!n.isInt()) throw std::invalid_argument("MdBrief::read: '" + keyName(node, key) + "' must be an integer");
  value = static_cast<int>(n);
}

void readBool(const cv::FileNode& node, const char* key, bool& value) {
  int v = value ? 1 : 0;
  readInt(node, key, v);
  if (v != 0 && v != 1) throw std::invalid_argument("MdBrief::read: '" + keyName(node, key) + "' must be 0 or 1");
  value = v == 1;
}

void readDouble(const cv::FileNode& node, const char* key, double& value) {
  const cv::FileNode n = node[key];
  if (n.empty()) return;
  if (!n.isInt() && !n.isReal())
    throw std::invalid_argument("MdBrief::read: '" + keyName(node, key) + "' must be a number");
  value = static_cast<double>(n);
}

void readString(const cv::FileNode& node, const char* key, std::string& value) {
  const cv::FileNode n = node[key];
  if (n.empty()) return;
  if (!n.isString()) throw std::invalid_argument("MdBrief::read: '" + keyName(node, key) + "' must be a string");
  value = static_cast<std::string>(n);
}

template <typename Enum>
void readEnum(const cv::FileNode& node, const char* key, Enum& value, Enum (*parse)(const std::string&)) {
  std::string s;
  readString(node, key, s);
  if (s.empty()) return;
  try {
    value = parse(s);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("MdBrief::read: '" + keyName(node, key) + "': " + e.what());
  }
}

}  // namespace

void validate(const MdBriefOptions& options) {
  validate(options.detector);
  validate(options.descriptor);
}

cv::Ptr<MdBrief> MdBrief::create(CameraPtr camera, const MdBriefOptions& options) {
  return cv::makePtr<MdBrief>(std::move(camera), options);
}

MdBrief::MdBrief(CameraPtr camera, const MdBriefOptions& options)
    : camera_(std::move(camera)),
      options_((validate(options), options)),
      detector_(camera_, options.detector),
      extractor_(camera_, options.descriptor) {}

void MdBrief::detectAndCompute(cv::InputArray image, cv::InputArray mask, std::vector<cv::KeyPoint>& keypoints,
                               cv::OutputArray descriptors, bool useProvidedKeypoints) {
  detectAndComputeWithMasks(image, mask, keypoints, descriptors, cv::noArray(), useProvidedKeypoints);
}

void MdBrief::detectAndComputeWithMasks(cv::InputArray image, cv::InputArray mask,
                                        std::vector<cv::KeyPoint>& keypoints, cv::OutputArray descriptors,
                                        cv::OutputArray masks, bool useProvidedKeypoints) {
  const cv::Mat img = image.getMat();
  if (img.empty()) throw std::invalid_argument("MdBrief: the image is empty");
  if (camera_ && img.size() != camera_->imageSize())
    throw std::invalid_argument("MdBrief: image size " + internal::sizeText(img.size()) + " differs from the camera's " +
                                internal::sizeText(camera_->imageSize()) + " (use Camera::resized)");
  const bool describe = descriptors.needed() || masks.needed();
  if (useProvidedKeypoints && !describe) return;

  // One pyramid for both steps; describing given keypoints only needs the levels their sizes
  // fall on (their octave is not read: it may come from another detector's pyramid).
  const int levels = useProvidedKeypoints ? extractor_.levelsFor(keypoints, options_.detector.pyramid) : -1;
  const ImagePyramid pyramid(img, options_.detector.pyramid, levels);  // converts colour input
  // A descriptor that re-measures the angle overwrites the detector's: skip measuring it twice.
  if (!useProvidedKeypoints)
    keypoints = detector_.detect(pyramid, mask.getMat(), !(describe && extractor_.measuresOrientation()));
  if (!describe) return;

  cv::Mat desc, msk;
  extractor_.compute(pyramid, keypoints, desc, msk);
  if (descriptors.needed()) desc.copyTo(descriptors);
  if (masks.needed()) {
    if (msk.empty())
      masks.release();
    else
      msk.copyTo(masks);
  }
}

void MdBrief::write(cv::FileStorage& fs) const {
  writeFormat(fs);
  const DetectorOptions& d = options_.detector;
  const DescriptorOptions& e = options_.descriptor;
  fs << "name" << getDefaultName();
  fs << "pyramid" << "{";
  fs << "levels" << d.pyramid.levels << "scaleFactor" << d.pyramid.scaleFactor;
  fs << "firstLevel" << d.pyramid.firstLevel;
  fs << "smoothingKernel" << d.pyramid.smoothingKernel << "smoothingSigma" << d.pyramid.smoothingSigma;
  fs << "}";
  fs << "detector" << "{";
  fs << "method" << toString(d.method);
  fs << "nfeatures" << d.nfeatures << "corners" << toString(d.corners) << "threshold" << d.threshold;
  fs << "fallbackThreshold" << d.fallbackThreshold << "harrisBlockSize" << d.harrisBlockSize;
  fs << "harrisK" << d.harrisK << "spread" << static_cast<int>(d.spread);
  fs << "hessianSigma" << d.hessianSigma << "hessianThreshold" << d.hessianThreshold;
  fs << "orientationRadius" << d.orientationRadius << "patchSize" << d.patchSize;
  fs << "borderMargin" << d.borderMargin << "conformal" << static_cast<int>(d.conformal);
  fs << "}";
  fs << "descriptor" << "{";
  fs << "kind" << toString(e.kind) << "bits" << e.bits << "pattern" << e.pattern;
  fs << "useOrientation" << static_cast<int>(e.useOrientation) << "orientation" << toString(e.orientation);
  fs << "orientationRadius" << e.orientationRadius << "form" << toString(e.form);
  fs << "sampling" << toString(e.sampling) << "maskRotationDeg" << e.maskRotationDeg;
  fs << "maxIncidenceDeg" << e.maxIncidenceDeg << "supportScale" << e.supportScale;
  fs << "}";
}

void MdBrief::read(const cv::FileNode& node) {
  std::string name;
  readString(node, "name", name);
  if (!name.empty() && name != getDefaultName())
    throw std::invalid_argument("MdBrief::read: the node holds '" + name + "', not " + getDefaultName());

  MdBriefOptions o = options_;
  const cv::FileNode p = node["pyramid"];
  PyramidOptions& pyramid = o.detector.pyramid;
  readInt(p, "levels", pyramid.levels);
  readDouble(p, "scaleFactor", pyramid.scaleFactor);
  readInt(p, "firstLevel", pyramid.firstLevel);
  readInt(p, "smoothingKernel", pyramid.smoothingKernel);
  readDouble(p, "smoothingSigma", pyramid.smoothingSigma);

  const cv::FileNode d = node["detector"];
  readEnum(d, "method", o.detector.method, &parseDetectorMethod);
  readInt(d, "nfeatures", o.detector.nfeatures);
  readEnum(d, "corners", o.detector.corners, &parseCornerDetector);
  readInt(d, "threshold", o.detector.threshold);
  readInt(d, "fallbackThreshold", o.detector.fallbackThreshold);
  readInt(d, "harrisBlockSize", o.detector.harrisBlockSize);
  readDouble(d, "harrisK", o.detector.harrisK);
  readBool(d, "spread", o.detector.spread);
  readBool(d, "conformal", o.detector.conformal);
  readDouble(d, "hessianSigma", o.detector.hessianSigma);
  readDouble(d, "hessianThreshold", o.detector.hessianThreshold);
  readInt(d, "orientationRadius", o.detector.orientationRadius);
  readInt(d, "patchSize", o.detector.patchSize);
  readInt(d, "borderMargin", o.detector.borderMargin);

  const cv::FileNode e = node["descriptor"];
  readEnum(e, "kind", o.descriptor.kind, &parseDescriptorKind);
  readInt(e, "bits", o.descriptor.bits);
  readString(e, "pattern", o.descriptor.pattern);
  readBool(e, "useOrientation", o.descriptor.useOrientation);
  readEnum(e, "orientation", o.descriptor.orientation, &parseOrientationSource);
  readInt(e, "orientationRadius", o.descriptor.orientationRadius);
  readEnum(e, "form", o.descriptor.form, &parseDistortionForm);
  readEnum(e, "sampling", o.descriptor.sampling, &parseSampling);
  readDouble(e, "maskRotationDeg", o.descriptor.maskRotationDeg);
  readDouble(e, "maxIncidenceDeg", o.descriptor.maxIncidenceDeg);
  readDouble(e, "supportScale", o.descriptor.supportScale);

  // Build first, assign after: a bad file leaves the object as it was.
  MdBrief updated(camera_, o);
  options_ = updated.options_;
  detector_ = std::move(updated.detector_);
  extractor_ = std::move(updated.extractor_);
}

}  // namespace mdbrief

#include "mdbrief/api/feature2d.hpp"

#include <stdexcept>
#include <utility>

#include "mdbrief/detect/image_pyramid.hpp"
#include "mdbrief/internal/base/size_text.hpp"

namespace mdbrief {
namespace {

// The FileStorage spelling of field i: "<section>.<key>".
std::string storageName(const OptionField<MdBriefOptions>& field) { return std::string(field.section) + "." + field.key(); }

// The value of a present key as the field's type wants it; throws naming the key for a wrong type.
FieldValue readValue(const OptionField<MdBriefOptions>& field, const cv::FileNode& n) {
  const auto wrongType = [&](const char* wanted) {
    return std::invalid_argument("MdBrief::read: '" + storageName(field) + "' must be " + wanted);
  };
  switch (field.type) {
    case FieldType::Integer:
      if (!n.isInt()) throw wrongType("an integer");
      return static_cast<long long>(static_cast<int>(n));
    case FieldType::Real:
      if (!n.isInt() && !n.isReal()) throw wrongType("a number");
      return static_cast<double>(n);
    case FieldType::Flag: {
      if (!n.isInt()) throw wrongType("an integer");
      const int v = static_cast<int>(n);
      if (v != 0 && v != 1) throw wrongType("0 or 1");
      return v == 1;
    }
    case FieldType::Text:
    case FieldType::Choice:
      if (!n.isString()) throw wrongType("a string");
      return static_cast<std::string>(n);
    case FieldType::TextList: break;
  }
  throw wrongType("a value of a known type");
}

}  // namespace

cv::Ptr<MdBrief> MdBrief::create(CameraPtr camera, const MdBriefOptions& options) {
  return cv::makePtr<MdBrief>(std::move(camera), options);
}

MdBrief::MdBrief(CameraPtr camera, const MdBriefOptions& options)
    : camera_(std::move(camera)),
      options_((validate(options), options)),
      detector_(camera_, options.detector),
      extractor_(camera_, options.descriptor) {}

MdBrief::MdBrief(CameraPtr camera, const MdBriefOptions& options, const ComparisonSet& tests)
    : camera_(std::move(camera)),
      options_((validate(options), options)),
      detector_(camera_, options.detector),
      extractor_(camera_, options.descriptor, tests) {}

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
  fs << "name" << getDefaultName();
  const OptionTable<MdBriefOptions>& table = mdBriefOptionFields();
  for (const char* section : {"pyramid", "detector", "descriptor"}) {
    fs << section << "{";
    for (const OptionField<MdBriefOptions>& field : table) {
      if (std::string(field.section) != section) continue;
      const FieldValue value = field.get(options_);
      fs << field.key();
      if (const auto* i = std::get_if<long long>(&value)) fs << static_cast<int>(*i);
      else if (const auto* d = std::get_if<double>(&value)) fs << *d;
      else if (const auto* b = std::get_if<bool>(&value)) fs << static_cast<int>(*b);
      else fs << std::get<std::string>(value);
    }
    fs << "}";
  }
}

void MdBrief::read(const cv::FileNode& node) {
  const cv::FileNode nameNode = node["name"];
  if (!nameNode.empty()) {
    if (!nameNode.isString()) throw std::invalid_argument("MdBrief::read: 'name' must be a string");
    const std::string name = static_cast<std::string>(nameNode);
    if (!name.empty() && name != getDefaultName())
      throw std::invalid_argument("MdBrief::read: the node holds '" + name + "', not " + getDefaultName());
  }

  // A missing key keeps the current value.
  MdBriefOptions o = options_;
  const OptionTable<MdBriefOptions>& table = mdBriefOptionFields();
  try {
    for (size_t i = 0; i < table.size(); ++i) {
      const cv::FileNode n = node[table[i].section][table[i].key()];
      if (!n.empty()) setField(table, i, o, readValue(table[i], n), storageName(table[i]));
    }
    validate(o);
  } catch (const OptionError& e) {
    throw OptionError(e.field(), storageName(table[e.field()]), e.problem());
  }

  // Build first, assign after: a bad file leaves the object as it was.
  MdBrief updated(camera_, o);
  options_ = updated.options_;
  detector_ = std::move(updated.detector_);
  extractor_ = std::move(updated.extractor_);
}

}  // namespace mdbrief

#pragma once
// mdbrief as a cv::Feature2D: a drop-in for cv::ORB (detect, compute, detectAndCompute,
// BFMatcher(defaultNorm()), FileStorage read/write). Detection and description share one
// ImagePyramid per image. The mdBRIEF masks, which cv::Feature2D has no place for, come from
// the extra call detectAndComputeWithMasks().
//
// The camera is not part of the serialized state (it is a calibration file of its own, see
// camera/io.hpp): read() changes the options and keeps the camera.
#include <string>
#include <vector>

#include <opencv2/features2d.hpp>

#include "mdbrief/camera/camera.hpp"
#include "mdbrief/describe/descriptor.hpp"
#include "mdbrief/detect/detector.hpp"

namespace mdbrief {

struct MdBriefOptions {
  // detector.pyramid is the pyramid of both steps: the descriptor samples the one built for the
  // detector.
  DetectorOptions detector;
  DescriptorOptions descriptor;
};

// The fields of MdBriefOptions: the detector's ("detector.<member>", the pyramid's in FileStorage
// section "pyramid") and the descriptor's ("descriptor.<member>"). FileStorage, the Python
// keywords and the command line's detection flags all read this table.
const OptionTable<MdBriefOptions>& mdBriefOptionFields();
// Throws OptionError naming the first option out of its field's range.
void validate(const MdBriefOptions& options);

class MdBrief : public cv::Feature2D {
 public:
  // camera may be null only for DescriptorKind::Brief and MaskedBrief (then no valid-area
  // mask and any image size). Throws std::invalid_argument on unusable options or a missing camera.
  static cv::Ptr<MdBrief> create(CameraPtr camera, const MdBriefOptions& options = {});

  MdBrief(CameraPtr camera, const MdBriefOptions& options);
  // With an explicit test set (one just learned, say): options.descriptor.pattern is not read;
  // the set's first options.descriptor.bits tests are used.
  MdBrief(CameraPtr camera, const MdBriefOptions& options, const ComparisonSet& tests);

  // cv::Feature2D: detect() and compute() of the base class forward here. image: 8UC1, 8UC3
  // or 8UC4 (BGR/BGRA) of the camera's size; mask: empty or 8UC1 of the image size. With
  // useProvidedKeypoints, keypoints that cannot be described are removed (as cv::ORB does).
  // Throws std::invalid_argument on bad input.
  void detectAndCompute(cv::InputArray image, cv::InputArray mask, std::vector<cv::KeyPoint>& keypoints,
                        cv::OutputArray descriptors, bool useProvidedKeypoints = false) override;

  // The same, plus the mdBRIEF masks (N x bytes CV_8U, row i for keypoint i; released for
  // BRIEF and dBRIEF). descriptors and masks may be cv::noArray().
  void detectAndComputeWithMasks(cv::InputArray image, cv::InputArray mask, std::vector<cv::KeyPoint>& keypoints,
                                 cv::OutputArray descriptors, cv::OutputArray masks,
                                 bool useProvidedKeypoints = false);

  int descriptorSize() const override { return options_.descriptor.bits / 8; }
  int descriptorType() const override { return CV_8U; }
  int defaultNorm() const override { return cv::NORM_HAMMING; }
  cv::String getDefaultName() const override { return "Feature2D.MdBrief"; }
  bool empty() const override { return false; }

  // Every option of MdBriefOptions (detector and descriptor; the pyramid once), by the keys and
  // sections of mdBriefOptionFields(). read() keeps the current value of a missing key and throws
  // std::invalid_argument naming the key for a value of the wrong type, and OptionError
  // "<section>.<key> must be in [...], got <value>" for one out of range (the object is
  // unchanged then).
  void write(cv::FileStorage& fs) const override;
  void read(const cv::FileNode& node) override;
  using cv::Feature2D::read;
  using cv::Feature2D::write;

  const MdBriefOptions& options() const { return options_; }
  const CameraPtr& camera() const { return camera_; }
  const Detector& detector() const { return detector_; }
  const DescriptorExtractor& extractor() const { return extractor_; }

 private:
  CameraPtr camera_;
  MdBriefOptions options_;
  Detector detector_;
  DescriptorExtractor extractor_;
};

}  // namespace mdbrief

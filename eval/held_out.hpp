#pragma once
// Training and evaluation images kept apart by content (patchextract/image_digest.hpp): the
// list of images the shipped evaluations read, written as configs/held-out-images.txt (which
// every training leaves out), and the check that refuses to evaluate a learned test set on an
// image it was trained on.
#include <string>
#include <vector>

#include "descriptor_method.hpp"
#include "eval_datasets.hpp"

namespace mdbrief::eval {

struct EvaluationImage {
  std::string path;
  std::string label;  // e.g. "oxford-affine/graf/img1.png", "opencv-doc/building.jpg"
};

// Every image the default evaluations read (those present on this machine): of the shared data
// folder the Oxford sequences, the poster-dev frames and the turned-lens photos; the photos of
// opencvDocDir.
std::vector<EvaluationImage> defaultEvaluationImages(const std::string& dataDir,
                                                     const std::string& opencvDocDir = kDebianOpencvDocData);

// The held-out list text ("<digest> <label>" per image, sorted by label, header comments).
// Images that cannot be decoded are left out.
std::string heldOutListText(const std::vector<EvaluationImage>& images);

// Throws std::invalid_argument naming the test set and the image when a BRIEF-family method
// uses a learned set whose training images include one of `imagePaths` (by digest).
void requireDisjointTraining(const std::vector<MethodSpec>& methods, const std::vector<std::string>& imagePaths);

}  // namespace mdbrief::eval

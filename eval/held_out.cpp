#include "held_out.hpp"

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>
#include <stdexcept>

#include "eval_datasets.hpp"
#include "mdbrief/describe/patterns.hpp"
#include "patchextract/image_digest.hpp"

namespace mdbrief::eval {

namespace fs = std::filesystem;

std::vector<EvaluationImage> defaultEvaluationImages(const std::string& dataDir, const std::string& opencvDocDir) {
  std::vector<EvaluationImage> out;
  const auto add = [&](const fs::path& path, const std::string& label) {
    if (fs::exists(path)) out.push_back({path.string(), label});
  };
  const fs::path data(dataDir);
  for (const auto& seq : kOxfordSequences)
    for (int k = 1; k <= 6; ++k) {
      const std::string name = seq + "/img" + std::to_string(k) + ".png";
      add(data / "oxford-affine" / name, "oxford-affine/" + name);
    }
  for (const auto& frame : kPosterDevFrames)
    add(data / "fisheye" / "poster-dev" / frame, "fisheye/poster-dev/" + frame);
  for (const auto& photo : kTurnedLensPhotos) add(data / photo.image, photo.image);
  for (const auto& name : kDocEvaluationPhotos) add(fs::path(opencvDocDir) / name, "opencv-doc/" + name);
  return out;
}

std::string heldOutListText(const std::vector<EvaluationImage>& images) {
  std::map<std::string, std::string> byLabel;
  for (const auto& im : images)
    if (const std::string d = train::imageFileDigest(im.path); !d.empty()) byLabel[im.label] = d;
  std::string text =
      "# Images never to train on, by the digest of their decoded grey pixels (patchextract/image_digest.hpp),\n"
      "# written by mdbrief-eval held-out-images.\n";
  for (const auto& [label, digest] : byLabel) text += digest + " " + label + "\n";
  return text;
}

void requireDisjointTraining(const std::vector<MethodSpec>& methods, const std::vector<std::string>& imagePaths) {
  std::map<std::string, std::string> evaluated;  // digest -> path
  for (const auto& p : imagePaths)
    if (const std::string d = train::imageFileDigest(p); !d.empty()) evaluated.emplace(d, p);
  std::set<std::string> checked;
  for (const auto& m : methods) {
    if (m.family != MethodFamily::Library) continue;
    const std::string set = m.options.pattern.empty() ? defaultComparisonSetName() : m.options.pattern;
    if (!checked.insert(set).second) continue;
    for (const auto& d : resolveComparisonSet(set).trainingImages)
      if (const auto hit = evaluated.find(d); hit != evaluated.end())
        throw std::invalid_argument("test set " + set + " was trained on " + hit->second +
                                    ", an image of this evaluation: its figures would be measured on training "
                                    "data; evaluate on other images or retrain without it");
  }
}

}  // namespace mdbrief::eval

// The learned test sets against the random one on images they never saw: the shipped sets'
// training images are disjoint from every evaluation image (by content digest), the evaluation
// refuses a set trained on its images, and on the Oxford sequences the default set beats
// brief_random_512 by a margin in PR AUC (docs/RESULTS.md "Learned vs random test sets").
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <gtest/gtest.h>

#include "eval/eval_datasets.hpp"
#include "eval/held_out.hpp"
#include "mdbrief/describe/patterns.hpp"
#include "patchextract/image_digest.hpp"
#include "eval/pr_experiment.hpp"
#include "test_data.hpp"

namespace fs = std::filesystem;
using namespace mdbrief;
using namespace mdbrief::eval;

namespace {

std::optional<fs::path> oxfordDir() {
  if (const auto shared = mdbrief::testing::sharedDataDir(); shared && fs::is_directory(*shared / "oxford-affine"))
    return *shared / "oxford-affine";
  return std::nullopt;
}

// method name -> AUC over all pairs of the group, as eval_summary.csv reports it.
std::map<std::string, double> groupAuc(const fs::path& summaryCsv, const std::string& group) {
  std::map<std::string, double> auc;
  std::ifstream f(summaryCsv);
  std::string line;
  while (std::getline(f, line)) {
    std::stringstream row(line);
    std::string g, sequence, method, value;
    std::getline(row, g, ',');
    std::getline(row, sequence, ',');
    std::getline(row, method, ',');
    std::getline(row, value, ',');
    if (g == group && sequence == "ALL") auc[method] = std::stod(value);
  }
  return auc;
}

}  // namespace

TEST(LearnedSets, ShippedSetsRecordTheirTrainingImagesAndNoneIsHeldOut) {
  const auto& heldOut = train::shippedHeldOutImages();
  ASSERT_GT(heldOut.size(), 8u) << "configs/held-out-images.txt lists the evaluation images";
  for (const auto& name : builtinComparisonSetNames()) {
    const ComparisonSet set = builtinComparisonSet(name);
    if (name.rfind("brief_random", 0) == 0) {
      EXPECT_TRUE(set.trainingImages.empty()) << name;
      continue;
    }
    EXPECT_GT(set.trainingImages.size(), 100u) << name << " records the images it was trained on";
    for (const auto& d : set.trainingImages) EXPECT_EQ(heldOut.count(d), 0u) << name << " trained on " << heldOut.at(d);
  }
}

TEST(LearnedSets, HeldOutListCoversEveryDefaultEvaluationImage) {
  const auto images = defaultEvaluationImages(mdbrief::testing::sharedDataDir().value_or("/nonexistent").string());
  if (images.empty()) MDBRIEF_SKIP_WITHOUT_DATA("neither opencv-doc nor ../shared/data present");
  const auto& heldOut = train::shippedHeldOutImages();
  for (const auto& im : images)
    EXPECT_EQ(heldOut.count(train::imageFileDigest(im.path)), 1u)
        << im.label << " is read by an evaluation but missing from configs/held-out-images.txt "
        << "(regenerate it: mdbrief-eval held-out-images --out configs/held-out-images.txt)";
}

TEST(LearnedSets, EvaluationRefusesASetTrainedOnItsImages) {
  const auto doc = mdbrief::testing::opencvDocDataDir();
  if (!doc) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc not installed");
  const fs::path graf = *doc / "graf1.png";
  mdbrief::testing::TempDir dir("refuse");
  const fs::path json = dir.path / "contaminated.json";
  std::ofstream(json) << R"({"name": "contaminated", "tests": [)" << [] {
    std::string t;
    for (int i = 0; i < 32; ++i) t += (i ? ", " : "") + std::string("[0, 0, 1, ") + std::to_string(i % 14 + 1) + "]";
    return t;
  }() << R"(], "training_images": [")" << train::imageFileDigest(graf) << R"("]})";
  const std::vector<MethodSpec> methods{briefFamilyMethod("dBRIEF-32@contaminated", DescriptorKind::DBrief, 32, true,
                                                          DistortionForm::Affine, 20.0, json.string())};
  try {
    requireDisjointTraining(methods, {graf.string()});
    FAIL() << "an evaluation on graf1 must refuse a set trained on it";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("graf1.png"), std::string::npos) << e.what();
  }
  // Images it was not trained on are fine, and so is every shipped set on the default images.
  EXPECT_NO_THROW(requireDisjointTraining(methods, {(*doc / "box.png").string()}));
  std::vector<std::string> paths;
  for (const auto& im : defaultEvaluationImages(mdbrief::testing::sharedDataDir().value_or("/nonexistent").string())) paths.push_back(im.path);
  EXPECT_NO_THROW(requireDisjointTraining(standardPrMethods(true), paths));
}

// The issue's targets, checked with a margin below the measured figures (docs/RESULTS.md):
// the default set at 256 bits at least 8 % above random at 256, and at 128 bits at least random
// at 256 (mdBRIEF, the library's default descriptor), on the six Oxford sequences it never saw.
TEST(LearnedSets, DefaultBeatsRandomOnHeldOutOxford) {
  const auto dir = oxfordDir();
  if (!dir) MDBRIEF_SKIP_WITHOUT_DATA("../shared/data/oxford-affine not found (set MDBRIEF_DATA)");
  EvalGroup group{"perspective", {}};
  std::vector<std::string> paths;
  for (const auto& s : kOxfordSequences)
    if (auto seq = loadOxfordSequence((*dir / s).string(), s)) {
      group.sequences.push_back(std::move(*seq));
      for (int k = 1; k <= 6; ++k) paths.push_back((*dir / s / ("img" + std::to_string(k) + ".png")).string());
    }
  ASSERT_EQ(group.sequences.size(), kOxfordSequences.size());
  const std::string learned = defaultComparisonSetName(), random = "brief_random_512";
  const std::vector<MethodSpec> methods{
      briefFamilyMethod("learned-256", DescriptorKind::MdBrief, 256, true, DistortionForm::Affine, 20.0, learned),
      briefFamilyMethod("learned-128", DescriptorKind::MdBrief, 128, true, DistortionForm::Affine, 20.0, learned),
      briefFamilyMethod("random-256", DescriptorKind::MdBrief, 256, true, DistortionForm::Affine, 20.0, random)};
  ASSERT_NO_THROW(requireDisjointTraining(methods, paths));
  mdbrief::testing::TempDir out("learned");
  PrOptions o;
  o.outDir = out.path.string();
  runPrecisionRecall({group}, methods, o);
  const auto auc = groupAuc(out.path / "eval_summary.csv", "perspective");
  ASSERT_EQ(auc.size(), 3u);
  RecordProperty("auc_learned_256", std::to_string(auc.at("learned-256")));
  RecordProperty("auc_learned_128", std::to_string(auc.at("learned-128")));
  RecordProperty("auc_random_256", std::to_string(auc.at("random-256")));
  EXPECT_GT(auc.at("learned-256"), 1.08 * auc.at("random-256"));
  EXPECT_GE(auc.at("learned-128"), auc.at("random-256"));
}

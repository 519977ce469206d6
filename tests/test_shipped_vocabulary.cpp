// The vocabulary shipped for the default preset (configs/vocabularies/, scripts/train-vocabulary.sh):
// what its header promises, training images disjoint from every evaluation image by pixel
// digest, and place recognition with it: a scene's other view is found among unrelated photos.
#include <gtest/gtest.h>

#include <algorithm>

#include "mdbrief/recognition/database.hpp"
#include "mdbrief/api/feature2d.hpp"
#include "mdbrief/api/presets.hpp"
#include "mdbrief/recognition/vocabulary.hpp"
#include "patchextract/image_digest.hpp"
#include "test_data.hpp"
#include "toolkit/image_file.hpp"
#include "scenes/photo_camera.hpp"

using namespace mdbrief;

namespace {

const std::string kShipped = (mdbrief::testing::sourceDir() / "configs" / "vocabularies" / "tracking_k10_L4.mdbvoc").string();

}  // namespace

TEST(ShippedVocabulary, IsMaskedForTheDefaultPresetsDescriptors) {
  const Vocabulary v = Vocabulary::load(kShipped);
  EXPECT_TRUE(v.masked());
  EXPECT_EQ(v.bits(), presetSettings(Preset::Tracking).features.descriptor.bits);
  EXPECT_EQ(v.bits(), MdBriefOptions{}.descriptor.bits);
  EXPECT_EQ(v.branching(), 10);
  EXPECT_EQ(v.depth(), 4);
  EXPECT_GT(v.wordCount(), 9000u);
  EXPECT_EQ(v.weighting(), Weighting::TfIdf);
}

TEST(ShippedVocabulary, NoTrainingImageIsAnEvaluationImage) {
  const Vocabulary v = Vocabulary::load(kShipped);
  const std::vector<uint64_t> trained = v.trainingImages();
  EXPECT_EQ(trained.size(), 400u);
  const train::HeldOutImages& heldOut = train::shippedHeldOutImages();
  ASSERT_FALSE(heldOut.empty());
  for (const auto& [digest, name] : heldOut)
    EXPECT_EQ(std::count(trained.begin(), trained.end(), std::stoull(digest, nullptr, 16)), 0) << name;
}

TEST(ShippedVocabulary, FindsTheOtherViewOfASceneAmongUnrelatedPhotos) {
  const auto dir = mdbrief::testing::opencvDocDataDir();
  if (!dir) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc's example photos not found");
  Database database(Vocabulary::load(kShipped));
  const auto describe = [](const cv::Mat& grey, cv::Mat& descriptors, cv::Mat& masks) {
    std::vector<cv::KeyPoint> keypoints;
    MdBrief::create(photoCamera(grey.size()))->detectAndComputeWithMasks(grey, cv::noArray(), keypoints, descriptors, masks);
  };
  const std::vector<std::string> photos{"graf1.png", "baboon.jpg", "building.jpg", "fruits.jpg", "box_in_scene.png"};
  for (const std::string& name : photos) {
    const cv::Mat grey = decodeGreyImage(*dir / name);
    ASSERT_FALSE(grey.empty()) << name;
    cv::Mat descriptors, masks;
    describe(grey, descriptors, masks);
    database.addDescriptors(descriptors, masks);
  }
  cv::Mat descriptors, masks;
  describe(decodeGreyImage(*dir / "graf3.png"), descriptors, masks);
  const std::vector<QueryResult> results = database.queryDescriptors(descriptors, masks, 2);
  ASSERT_EQ(results.size(), 2u);
  EXPECT_EQ(results[0].entry, 0u) << "graf3 should find graf1";
  EXPECT_GT(results[0].score, results[1].score);
}

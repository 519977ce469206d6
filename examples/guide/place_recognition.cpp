// The user guide's place recognition in C++ (docs/guide/README.md "Vocabularies and place
// recognition"): load a vocabulary, put images into a database, query it. ctest
// `guide_place_recognition` runs it with the shipped vocabulary.
// Usage: guide_place_recognition CALIBRATION VOCABULARY
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include <mdbrief/mdbrief.hpp>

#include "synthetic_scene.hpp"

namespace {

int fail(const std::string& what) {
  std::fprintf(stderr, "guide_place_recognition: %s\n", what.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) try {
  if (argc != 3) return fail("usage: guide_place_recognition CALIBRATION VOCABULARY");
  const auto camera = mdbrief::loadCamera(argv[1]);
  const std::string vocabularyPath = argv[2];
  const cv::Ptr<mdbrief::MdBrief> features = mdbrief::MdBrief::create(camera);
  // Five places, and a second visit of place 3 with the lens rolled.
  std::vector<cv::Mat> places;
  for (uint64_t seed = 1; seed <= 5; ++seed) places.push_back(guide::texturedImage(camera->imageSize(), seed));
  cv::Point2d centre;
  camera->bearingToPixel(cv::Vec3d(0, 0, 1), centre);
  cv::Matx23d unused;
  const cv::Mat revisit = guide::rolled(places[2], cv::Point2f(centre), 8.0, unused);

  // [guide:database]
  // The vocabulary must have been trained on the same features (preset and length): the shipped
  // one is the defaults' (configs/vocabularies/tracking_k10_L4.mdbvoc, installed in share/mdbrief).
  mdbrief::Vocabulary vocabulary = mdbrief::Vocabulary::load(vocabularyPath);
  mdbrief::Database database(vocabulary);
  for (const cv::Mat& image : places) {
    std::vector<cv::KeyPoint> keypoints;
    cv::Mat descriptors, masks;
    features->detectAndComputeWithMasks(image, cv::noArray(), keypoints, descriptors, masks);
    database.addDescriptors(descriptors, masks);  // entry ids 0, 1, 2, ... in this order
  }
  // [guide]

  // [guide:query]
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors, masks;
  features->detectAndComputeWithMasks(revisit, cv::noArray(), keypoints, descriptors, masks);
  std::vector<mdbrief::QueryResult> best = database.queryDescriptors(descriptors, masks, 3);
  // best[0].entry: the most similar image; best[0].score: its L1 score in (0, 1]
  // [guide]
  if (best.empty()) return fail("no result");
  for (const mdbrief::QueryResult& r : best) std::printf("entry %u score %.4f\n", r.entry, r.score);
  if (best[0].entry != 2) return fail("the revisit did not find its place first");
  return 0;
} catch (const std::exception& e) {
  return fail(e.what());
}

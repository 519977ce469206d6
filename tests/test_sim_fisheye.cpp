// Reduced version of the paper's simulation (eval/simulation.hpp) for CI: graf1 as a
// plane seen by the paper's fisheye camera along a short translation, 50 projected ORB
// keypoints, 4 views. Distortion-aware tests must keep corresponding descriptors closer than
// BRIEF's, and the masks must bring mdBRIEF closer still.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "mdbrief/camera/io.hpp"
#include "eval/simulation.hpp"
#include "test_data.hpp"

namespace mdbrief::eval {
namespace {

struct TempDir {
  std::filesystem::path path = std::filesystem::temp_directory_path() /
                               ("mdbrief_test_sim_" + std::to_string(::getpid()));
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};

double byName(const SimSummary& s, const std::vector<double>& values, const std::string& name) {
  const auto it = std::find(s.methods.begin(), s.methods.end(), name);
  if (it == s.methods.end()) ADD_FAILURE() << "no method " << name;
  return it == s.methods.end() ? 0.0 : values[it - s.methods.begin()];
}

TEST(SimFisheye, DBriefKeepsMatchingDescriptorsCloserThanBrief) {
  const auto doc = testing::opencvDocDataDir();
  if (!doc || !std::filesystem::exists(*doc / "graf1.png")) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc graf1.png not installed");
  TempDir tmp;
  SimOptions o;
  o.texturePath = (*doc / "graf1.png").string();
  o.outDir = tmp.path.string();
  o.views = 4;
  o.recognitionViews = 4;
  o.keypoints = 50;
  const SimCamera cam{"fisheye", loadCamera((testing::sourceDir() / "configs/cameras/lafida_fisheye0.yaml").string())};
  // 1.5 plane units to the side: the 0.8-unit wide texture ends up 48-62 degrees off-axis,
  // where the fisheye compresses it strongly.
  const SimSummary s = runProjectedSimulation(cam, 1.5, o);
  ASSERT_GE(s.commonKeypoints, 30);
  const double brief = byName(s, s.meanMatchingDistance, "BRIEF");
  const double dbrief = byName(s, s.meanMatchingDistance, "dBRIEF");
  const double mdbrief = byName(s, s.meanMatchingDistance, "mdBRIEF");
  EXPECT_LT(dbrief, brief);
  EXPECT_LT(mdbrief, dbrief);
  // A far-from-trivial gap: BRIEF drifts towards the random level (128 of 256 bits).
  EXPECT_LT(dbrief, 0.8 * brief);
  // Recognition (nearest neighbour among the keypoints) follows the distances.
  EXPECT_GE(byName(s, s.recognitionAtLast, "dBRIEF"), byName(s, s.recognitionAtLast, "BRIEF"));
  // The outputs the plot script reads exist.
  EXPECT_TRUE(std::filesystem::exists(tmp.path / "sim_fisheye_hamming_evolution.csv"));
  EXPECT_TRUE(std::filesystem::exists(tmp.path / "sim_fisheye_bhattacharyya.csv"));
}

TEST(SimFisheye, BhattacharyyaOfIdenticalAndDisjointHistograms) {
  EXPECT_NEAR(bhattacharyya({1, 2, 3}, {2, 4, 6}), 1.0, 1e-12);
  EXPECT_NEAR(bhattacharyya({1, 0, 0}, {0, 0, 5}), 0.0, 1e-12);
  EXPECT_NEAR(bhattacharyya({1, 1}, {1, 0}), std::sqrt(0.5), 1e-12);
  EXPECT_EQ(bhattacharyya({}, {1}), 0.0);
}

}  // namespace
}  // namespace mdbrief::eval

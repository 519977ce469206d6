// The place-recognition evaluation of eval/ (retrieval_experiment.hpp) on synthetic textures
// whose answers are known: every query is its sequence's first image with another gamma and
// contrast and with noise, so that its descriptors differ from the first's and only the
// vocabulary's words bring them together; every method finds its sequence first among
// distractors. A distractor that is also a training image is refused;
// `mdbrief-eval retrieval` exits 2 on bad input, naming the option or file.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "eval/eval_cli.hpp"
#include "eval/eval_commands.hpp"
#include "eval/retrieval_experiment.hpp"
#include "mdbrief/detect/detector.hpp"
#include "option_flag_message.hpp"
#include "test_data.hpp"
#include "scenes/photo_camera.hpp"

namespace mdbrief::eval {
namespace {

namespace fs = std::filesystem;

// A blurred random texture: corners and blobs everywhere, different for every seed.
cv::Mat texture(int seed, cv::Size size = {400, 300}) {
  cv::Mat m(size, CV_8UC1);
  cv::RNG rng(static_cast<uint64>(seed));
  rng.fill(m, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(m, m, {0, 0}, 2.0);
  cv::normalize(m, m, 0, 255, cv::NORM_MINMAX);
  return m;
}

std::vector<std::string> writeTextures(const std::filesystem::path& dir, const std::string& tag, int first, int n) {
  std::vector<std::string> out;
  for (int i = 0; i < n; ++i) {
    const auto path = dir / (tag + std::to_string(i) + ".png");
    EXPECT_TRUE(cv::imwrite(path.string(), texture(first + i)));
    out.push_back(path.string());
  }
  return out;
}

// Two sequences: the texture, then two views of it with another gamma and contrast and with
// noise, which change its descriptors (a constant brightness offset, as before, changed none:
// every test compares two pixels of one image, so any vocabulary found the copies).
EvalGroup changedViewSequences() {
  EvalGroup g{"synthetic", {}};
  for (int s = 0; s < 2; ++s) {
    EvalSequence seq;
    seq.name = "seq" + std::to_string(s);
    const cv::Mat first = texture(100 + s);
    seq.images.push_back(first);
    cv::RNG rng(static_cast<uint64>(200 + s));
    for (int view = 1; view <= 2; ++view) {
      cv::Mat changed, noise(first.size(), CV_32F);
      first.convertTo(changed, CV_32F, 1.0 / 255);
      cv::pow(changed, view == 1 ? 0.7 : 1.4, changed);
      rng.fill(noise, cv::RNG::NORMAL, 0.0, 0.02);
      changed = changed * (0.8 + 0.1 * view) + noise;
      changed.convertTo(changed, CV_8U, 255);
      seq.images.push_back(changed);
    }
    seq.camera = photoCamera({400, 300});
    g.sequences.push_back(seq);
  }
  return g;
}

RetrievalOptions smallOptions(const std::string& out) {
  RetrievalOptions o;
  o.training.branching = 6;
  o.training.depth = 3;
  o.nfeatures = 300;
  o.outDir = out;
  return o;
}

std::vector<std::vector<std::string>> readCsv(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
    rows.push_back(cells);
  }
  return rows;
}

TEST(Retrieval, ChangedViewsFindTheirSequenceAmongDistractors) {
  testing::TempDir dir("retrieval");
  // 20 training images, 216 words: with 3 images and 64 words (as before) every image held
  // nearly every word, whose weight is then zero, and the changed views were found by chance.
  const auto training = writeTextures(dir.path, "train", 1, 20);
  const auto distractors = writeTextures(dir.path, "distractor", 50, 4);
  runRetrieval({changedViewSequences()}, training, distractors, smallOptions((dir.path / "out").string()));

  const auto recall = readCsv((dir.path / "out/retrieval.csv").string());
  ASSERT_EQ(recall.size(), 7u);  // header + 3 methods x (the group, all)
  EXPECT_EQ(recall[0], (std::vector<std::string>{"method", "group", "words", "queries", "recall_at_1", "recall_at_5"}));
  std::vector<std::string> methods;
  for (size_t r = 1; r < recall.size(); ++r) {
    methods.push_back(recall[r][0]);
    EXPECT_EQ(recall[r][3], "4") << recall[r][0];
    EXPECT_EQ(recall[r][4], "1") << recall[r][0] << " " << recall[r][1];
  }
  EXPECT_EQ(methods, (std::vector<std::string>{"mdbrief-masked", "mdbrief-masked", "mdbrief-blind", "mdbrief-blind",
                                               "orb", "orb"}));
  const auto speed = readCsv((dir.path / "out/retrieval_speed.csv").string());
  ASSERT_EQ(speed.size(), 4u);
  EXPECT_EQ(speed[1][3], "6") << "database: 2 sequences + 4 distractors";
  EXPECT_EQ(speed[1][10], "-1") << "no DBoW2 text of a masked vocabulary";
  EXPECT_NE(speed[2][10], "-1");
  EXPECT_TRUE(std::filesystem::exists(dir.path / "out/mdbrief-masked.mdbvoc"));
  EXPECT_TRUE(std::filesystem::exists(dir.path / "out/orb.dbow2.txt"));
}

TEST(Retrieval, RefusesADistractorThatIsATrainingImage) {
  testing::TempDir dir("retrieval_overlap");
  const auto training = writeTextures(dir.path, "train", 1, 2);
  auto distractors = writeTextures(dir.path, "distractor", 10, 2);
  const auto copy = dir.path / "renamed_copy.png";
  std::filesystem::copy_file(training[1], copy);
  distractors.push_back(copy.string());
  try {
    runRetrieval({changedViewSequences()}, training, distractors, smallOptions((dir.path / "out").string()));
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("renamed_copy.png"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir.path / "out/retrieval.csv"));
}

struct EvalRun {
  int code;
  std::string err;
};

EvalRun runRetrievalCli(std::vector<std::string> args) {
  args.insert(args.begin(), "retrieval");
  std::ostringstream out, err;
  ::testing::internal::CaptureStdout();  // the subcommand's progress
  const int code = runEvalCli(args, out, err);
  ::testing::internal::GetCapturedStdout();
  return {code, err.str()};
}

// Every case fails before any image is described; nothing is written.
TEST(RetrievalCli, BadInputExitsWith2NamingTheOptionOrFile) {
  testing::TempDir dir("retrieval_cli");
  const fs::path photos = dir.path / "photos", out = dir.path / "out", noData = dir.path / "no-data";
  fs::create_directories(photos);
  writeTextures(photos, "p", 1, 3);
  std::ofstream(dir.path / "a-file") << "x";
  // 3 photos: 2 train, 1 distracts (the default --training-count, 100, leaves none).
  const std::vector<std::string> common{"--photos", photos.string(), "--out", out.string()};
  const auto with = [&](std::vector<std::string> more) {
    more.insert(more.begin(), common.begin(), common.end());
    return more;
  };
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--photos", photos.string()}, "--out is required"},
      {{"--photos", (dir.path / "missing").string(), "--out", out.string()},
       "--photos: " + (dir.path / "missing").string() + ": no such image or folder"},
      {with({}), "--training-count 100"},
      {with({"--training-count", "3"}), "--training-count 3"},
      {with({"--training-count", "0"}), "--training-count"},
      {with({"--branching", "1"}), "--branching"},
      {with({"--depth", "0"}), "--depth"},
      // Issue 46: the library's flag, with its range and message (the tool's own was [10, 100000]).
      {with({"--nfeatures", "0"}), testing::optionFlagMessage(detectorOptionFields(), "nfeatures", "0")},
      {with({"--recall-at", "0"}), "--recall-at"},
      {with({"--datasets", "nope"}), "--datasets"},
      {with({"--seed", "x"}), "--seed"},
      // A data set named but not found names it and its folder; none found at all is an error too.
      {with({"--training-count", "2", "--data", noData.string(), "--datasets", "oxford"}), "oxford: " + noData.string()},
      {with({"--training-count", "2", "--data", noData.string(), "--datasets", "poster-dev"}),
       "poster-dev: " + noData.string()},
      {with({"--training-count", "2", "--data", noData.string(), "--fisheye-camera",
             (dir.path / "a-file").string()}),
       "no data set could be read"},
      // A calibration that is no file is refused before any data set is looked for.
      {with({"--training-count", "2", "--data", noData.string(), "--fisheye-camera",
             (dir.path / "no-camera.yaml").string()}),
       "--fisheye-camera: " + (dir.path / "no-camera.yaml").string() + ": no such file"},
      {{"--photos", photos.string(), "--training-count", "2", "--data", noData.string(), "--out",
        (dir.path / "a-file" / "out").string()},
       "--out " + (dir.path / "a-file" / "out").string()},
  };
  for (const auto& [args, expected] : cases) {
    const EvalRun r = runRetrievalCli(args);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << "expected '" << expected << "' in: " << r.err;
    ASSERT_FALSE(r.err.empty());
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "one line: " << r.err;
    EXPECT_FALSE(fs::exists(out / "retrieval.csv"));
  }
}

// Issue 29: an output that is one of the inputs is refused before any image is described.
TEST(RetrievalCli, AnOutputThatIsAnInputIsRefused) {
  MDBRIEF_REQUIRE_SHARED_DATA(data);
  testing::TempDir dir("retrieval_same");
  const fs::path photos = dir.path / "photos";
  fs::create_directories(photos);
  writeTextures(photos, "p", 1, 3);
  for (const char* name : {"retrieval.csv", "orb.dbow2.txt"}) {
    const std::string output = (dir.path / name).string();
    std::ofstream(output) << "previous results\n";
    const EvalRun r = runRetrievalCli({"--photos", photos.string(), "--training-count", "2", "--data", data.string(),
                                       "--datasets", "oxford", "--fisheye-camera", output, "--out", dir.path.string()});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("the output is the same file as the input " + output), std::string::npos) << r.err;
    EXPECT_EQ(testing::readFile(output), "previous results\n");
  }
}

}  // namespace
}  // namespace mdbrief::eval

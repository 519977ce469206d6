// mdbrief-train end to end (in-process): bad input gives exit code 2 and writes nothing,
// the same inputs and seed give a byte-identical header, --patches-file reuses a patch set.
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include "mdbrief/describe/patterns.hpp"
#include "patchextract/patch_extraction.hpp"
#include "patchextract/patch_set.hpp"
#include "patchextract/image_digest.hpp"
#include "test_data.hpp"
#include "toolkit/image_file.hpp"
#include "trainer/train_cli.hpp"
#include "write_limits.hpp"

namespace fs = std::filesystem;
using namespace mdbrief;
using namespace mdbrief::train;

namespace {

using mdbrief::testing::TempDir;
using mdbrief::testing::readFile;

struct CliRun {
  int code;
  std::string out, err;
};

CliRun runTrain(const std::vector<std::string>& args) {
  std::ostringstream out, err;
  const int code = runTrainCli(args, out, err);
  return {code, out.str(), err.str()};
}

// The arguments every case of a test shares, then the case's own.
CliRun runTrain(std::vector<std::string> common, const std::vector<std::string>& extra) {
  common.insert(common.end(), extra.begin(), extra.end());
  return runTrain(common);
}

// A small image folder copied from opencv-doc.
fs::path smallImageFolder(const TempDir& dir) {
  const auto doc = mdbrief::testing::opencvDocDataDir();
  const fs::path images = dir.path / "images";
  fs::create_directories(images);
  for (const char* f : {"graf1.png", "box_in_scene.png", "building.jpg", "lena.jpg"})
    if (doc && fs::exists(*doc / f)) fs::copy_file(*doc / f, images / f);
  return images;
}

}  // namespace

TEST(TrainCli, BadInputExitsWith2AndWritesNothing) {
  TempDir dir("bad");
  const fs::path out = dir.path / "out";
  fs::create_directories(out);
  fs::create_directories(dir.path / "empty");
  fs::create_directories(dir.path / "textonly");
  std::ofstream(dir.path / "textonly" / "a.txt") << "x";
  const std::string o = out.string();
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--images", (dir.path / "missing").string(), "--out", o}, "does not exist"},
      {{"--images", (dir.path / "empty").string(), "--out", o}, "no images"},
      {{"--images", (dir.path / "textonly").string(), "--out", o}, "no images"},
      {{"--camera", (dir.path / "nocam.yaml").string(), "--out", o}, "nocam.yaml"},
      {{"--camera", (dir.path / "empty").string(), "--out", o}, "--camera: " + (dir.path / "empty").string() + ": is a folder"},
      {{"--patches-file", (dir.path / "empty").string(), "--out", o},
       "--patches-file: " + (dir.path / "empty").string() + ": is a folder"},
      {{"--out", (dir.path / "missing_out").string()}, "missing_out"},
      // Issue 29: a file was reported as a missing folder.
      {{"--out", (dir.path / "textonly" / "a.txt").string()}, "a.txt: the output folder is a file, not a folder"},
      {{"--tests", "33", "--out", o}, "multiple of 32"},
      // Before: -1 became 18446744073709551615 patches and the run exited 0; -32 was reported as
      // "exceeds the candidates".
      {{"--patches", "-1", "--out", o}, "error: --patches must be in [1, 200000], got -1\n"},
      {{"--tests", "-32", "--out", o}, "error: --tests must be a multiple of 32 in [32, 512], got -32\n"},
      // Before: --out defaulted to "patterns" and failed when run elsewhere.
      {{"--tests", "64"}, "--out is required"},
      {{"--detector", "sift", "--out", o}, "sift"},
      {{"--patches-file", (dir.path / "none.h5").string(), "--out", o}, "none.h5"},
      {{"--no-such-flag"}, ""},
      {{"--selection", "boosting", "--out", o}, "boosting not in {paper,stability,separation}"},
      {{"--held-out", (dir.path / "nolist.txt").string(), "--out", o}, "nolist.txt: no such file"},
      {{"--form", "warped", "--out", o}, "--form: warped not in {affine,paper}"},
      {{"--orientation", "north", "--out", o}, "--orientation: north not in {tangent-plane,keypoint}"},
      {{"--patches-file", (dir.path / "textonly" / "a.txt").string(), "--form", "paper", "--out", o},
       "--patches-file cannot be combined with --images, --camera, --form or --orientation"},
  };
  for (const auto& [args, message] : cases) {
    const CliRun r = runTrain(args);
    EXPECT_EQ(r.code, 2) << args[0] << " " << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
  }
  EXPECT_TRUE(fs::is_empty(out));
}

// Outputs that cannot be written (a folder as --save-patches, a missing folder, a folder in the
// way of the header) fail at once, before the extraction and selection, which take minutes on
// real data.
TEST(TrainCli, UnwritableOutputsFailBeforeTheExtraction) {
  TempDir dir("unwritable");
  const fs::path images = smallImageFolder(dir);
  if (fs::is_empty(images)) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc not installed");
  const fs::path out = dir.path / "out";
  fs::create_directories(out / "blocked_64.hpp");
  const std::vector<std::string> common{"--images", images.string(), "--patches", "300", "--tests", "64",
                                        "--out", out.string()};
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--name", "tiny_64", "--save-patches", out.string()}, out.string() + ": the output exists and is a folder"},
      {{"--name", "tiny_64", "--save-patches", (dir.path / "no" / "p.h5").string()}, "does not exist"},
      {{"--name", "blocked_64"}, (out / "blocked_64.hpp").string() + ": the output exists and is a folder"},
  };
  for (const auto& [extra, message] : cases) {
    const CliRun r = runTrain(common, extra);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "") << "the extraction ran first";
  }
  EXPECT_EQ(mdbrief::testing::temporaryFiles(out), std::vector<std::string>{});
}

// Issue 29: an output that is an input (under any name) is refused before anything is read, and
// the input keeps its bytes.
TEST(TrainCli, AnOutputThatIsAnInputIsRefused) {
  TempDir dir("same");
  const fs::path out = dir.path / "out", images = dir.path / "images", list = dir.path / "list.txt";
  fs::create_directories(out);
  fs::create_directories(images);
  std::ofstream(list) << "0123456789abcdef held\n";
  std::ofstream(out / "registry.hpp") << "// registry\n";
  fs::create_symlink(list, dir.path / "link.txt");
  const std::vector<std::string> common{"--images", images.string(), "--out", out.string(), "--name", "t_64",
                                        "--tests", "64"};
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--held-out", list.string(), "--save-patches", (dir.path / "link.txt").string()},
       "the same file as the input " + list.string()},
      {{"--camera", (out / "registry.hpp").string()}, "the same file as the input " + (out / "registry.hpp").string()},
  };
  for (const auto& [extra, message] : cases) {
    const CliRun r = runTrain(common, extra);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
  }
  EXPECT_EQ(readFile(list), "0123456789abcdef held\n");
  EXPECT_EQ(readFile(out / "registry.hpp"), "// registry\n");
}

// Issue 29: --held-out /dev/zero read without bound, a FIFO blocked for ever, --config /dev/zero
// hung; a misspelt key in --config (patchs = 300), an unknown key and a malformed line were
// ignored. Each is an error naming the file, before any image is read (issue 45: when the flags
// are parsed, naming the flag).
TEST(TrainCli, SpecialFilesAndUnknownConfigurationKeysAreRefused) {
  TempDir dir("special");
  const fs::path out = dir.path / "out", images = dir.path / "images", fifo = dir.path / "fifo.txt";
  fs::create_directories(out);
  fs::create_directories(images);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const auto config = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir.path / name) << text;
    return (dir.path / name).string();
  };
  const std::vector<std::string> common{"--images", images.string(), "--out", out.string()};
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--held-out", "/dev/zero"}, "--held-out: /dev/zero: is a character device, not a regular file"},
      {{"--held-out", fifo.string()}, "--held-out: " + fifo.string() + ": is a FIFO, not a regular file"},
      {{"--config", "/dev/zero"}, "--config: /dev/zero: is a character device"},
      {{"--config=" + fifo.string()}, "--config: " + fifo.string() + ": is a FIFO"},
      {{"--config", config("misspelt.toml", "patchs = 300\n")}, "patchs"},
      {{"--config", config("bogus.toml", "bogus_key = 3\n")}, "bogus_key"},
      {{"--config", config("malformed.toml", "[x\nfoo=\n")}, "foo"},
  };
  for (const auto& [extra, message] : cases) {
    const CliRun r = runTrain(common, extra);
    EXPECT_EQ(r.code, 2) << extra[0] << ": " << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
  }
  EXPECT_TRUE(fs::is_empty(out));
}

TEST(TrainCli, HelpNamesTheProgramAndListsTheChoices) {
  const CliRun r = runTrain({"--help"});
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("Usage: mdbrief-train [OPTIONS]"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("{orb,akaze,surf}"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("{paper,stability,separation}=separation"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--pool"), std::string::npos) << "every selection option is a flag";
}

// The detectors reserve room for the whole budget: INT_MAX asked OpenCV for 26 GB.
TEST(TrainCli, KeypointBudgetBeyondTheLimitIsRefusedBeforeAnyImageIsRead) {
  TempDir dir("budget");
  const std::string o = dir.path.string();
  for (const std::string& budget : std::vector<std::string>{"2147483647", std::to_string(kMaxKeypointsPerImage + 1), "0", "-5"}) {
    const CliRun r = runTrain({"--images", (dir.path / "missing").string(), "--keypoints-per-image", budget, "--out", o});
    EXPECT_EQ(r.code, 2) << budget;
    EXPECT_NE(r.err.find("--keypoints-per-image"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("missing"), std::string::npos) << "checked before the images: " << r.err;
  }
}

TEST(TrainCli, CriteriaThatNeedPairsRefuseAPatchFileWithout) {
  TempDir dir("nopairs");
  const fs::path images = smallImageFolder(dir);
  if (fs::is_empty(images)) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc not installed");
  const fs::path patchFile = dir.path / "plain.h5";
  ASSERT_EQ(runTrain({"--images", images.string(), "--selection", "paper", "--patches", "300", "--tests", "64",
                      "--name", "plain_64",
                      "--out", dir.path.string(), "--save-patches", patchFile.string()})
                .code,
            0);
  for (const char* criterion : {"stability", "separation"}) {
    const CliRun r = runTrain({"--patches-file", patchFile.string(), "--selection", criterion, "--tests", "64",
                               "--name", "pairs_64", "--out", dir.path.string()});
    EXPECT_EQ(r.code, 2) << criterion;
    EXPECT_NE(r.err.find("no counterpart patches"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("mdbrief-patchextract --counterparts"), std::string::npos) << r.err;
  }
  EXPECT_FALSE(fs::exists(dir.path / "pairs_64.hpp"));
}

TEST(TrainCli, SeparationIsByteIdenticalAndRecordsCriterionPairsAndImages) {
  TempDir dir("sep");
  const fs::path images = smallImageFolder(dir);
  if (fs::is_empty(images)) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc not installed");
  std::vector<std::string> common{"--images", images.string(), "--patches", "600", "--tests", "64",
                                  "--selection", "separation", "--name", "sep_64"};
  for (const char* sub : {"a", "b"}) {
    fs::create_directories(dir.path / sub);
    auto args = common;
    args.insert(args.end(), {"--out", (dir.path / sub).string()});
    // Other block sizes change time and memory only: the second run streams in the smallest.
    if (sub[0] == 'b') args.insert(args.end(), {"--chunk-words", "1", "--candidate-batch", "7"});
    const CliRun r = runTrain(args);
    ASSERT_EQ(r.code, 0) << r.err;
    // graf1.png (Oxford graf img1) and building.jpg are evaluation images: left out by content.
    EXPECT_NE(r.out.find("held out (evaluation or validation images): 2 images"), std::string::npos) << r.out;
  }
  const std::string header = readFile(dir.path / "a" / "sep_64.hpp");
  EXPECT_EQ(header, readFile(dir.path / "b" / "sep_64.hpp"));
  EXPECT_NE(header.find("--counterparts 1 --selection separation --tests 64"), std::string::npos);
  EXPECT_NE(header.find("Learned (separation forward selection)"), std::string::npos);
  EXPECT_NE(header.find("Placement: as mdbrief compute() samples rotation 0: form affine, orientation tangent-plane"),
            std::string::npos)
      << header;
  EXPECT_NE(header.find(" flip 0."), std::string::npos) << "per-test flip rates";
  const ComparisonSet learned = loadComparisonSetJson((dir.path / "a" / "sep_64.json").string());
  EXPECT_EQ(learned.tests.size(), 64u);
  ASSERT_EQ(learned.trainingImages.size(), 1u) << "box_in_scene only";
  EXPECT_EQ(learned.trainingImages[0], imageFileDigest(images / "box_in_scene.png"));
}

TEST(TrainCli, FewerPatchesThanTestsExitsWith2) {
  TempDir dir("few");
  const fs::path images = smallImageFolder(dir);
  if (fs::is_empty(images)) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc not installed");
  const CliRun r = runTrain({"--images", images.string(), "--patches", "100", "--tests", "128", "--out",
                       dir.path.string()});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("fewer than the 128 requested tests"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir.path / "orb_perspective_128.hpp"));
}

// Too few patches says why and what to do: the budget, every image held out, a calibration of
// another size than the photos, each named.
TEST(TrainCli, TooFewPatchesSaysWhyAndWhatToDo) {
  TempDir dir("why");
  const fs::path images = smallImageFolder(dir);
  if (fs::is_empty(images)) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc not installed");
  const fs::path list = dir.path / "held_out.txt";
  int count = 0;
  {
    std::ofstream out(list);
    for (const auto& image : fs::directory_iterator(images)) {
      out << mdbrief::train::imageDigest(mdbrief::decodeGreyImage(image.path())) << " "
          << image.path().filename().string() << "\n";
      ++count;
    }
  }
  const struct {
    std::vector<std::string> args;
    std::string why;
  } cases[] = {
      {{"--patches", "100", "--tests", "128"}, "the --patches budget (100) is below --tests"},
      {{"--held-out", list.string()}, "every one of the " + std::to_string(count) + " images is held out"},
      {{"--camera", MDBRIEF_SOURCE_DIR "/configs/cameras/lafida_fisheye0.yaml"},
       "does not match the camera's 754x480; give --camera the calibration of these images"},
  };
  for (const auto& c : cases) {
    std::vector<std::string> args{"--images", images.string(), "--out", dir.path.string()};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const CliRun r = runTrain(args);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("requested tests"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.why), std::string::npos) << r.err;
  }
}

TEST(TrainCli, SameInputsAndSeedGiveByteIdenticalHeaders) {
  TempDir dir("det");
  const fs::path images = smallImageFolder(dir);
  if (fs::is_empty(images)) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc not installed");
  fs::create_directories(dir.path / "a");
  fs::create_directories(dir.path / "b");
  const fs::path patchFile = dir.path / "patches.h5";
  const std::vector<std::string> common = {"--images", images.string(), "--patches", "800",
                                           "--tests", "64", "--seed", "3", "--name", "tiny_64",
                                           "--selection", "paper"};
  auto args = common;
  args.insert(args.end(), {"--out", (dir.path / "a").string(), "--save-patches", patchFile.string()});
  const CliRun first = runTrain(args);
  ASSERT_EQ(first.code, 0) << first.err;
  EXPECT_NE(first.out.find("candidates: 377650"), std::string::npos) << first.out;
  EXPECT_NE(first.out.find("peak memory"), std::string::npos);
  args = common;
  args.insert(args.end(), {"--out", (dir.path / "b").string()});
  ASSERT_EQ(runTrain(args).code, 0);
  const std::string header = readFile(dir.path / "a" / "tiny_64.hpp");
  EXPECT_EQ(header, readFile(dir.path / "b" / "tiny_64.hpp"));
  EXPECT_EQ(readFile(dir.path / "a" / "tiny_64.json"), readFile(dir.path / "b" / "tiny_64.json"));
  EXPECT_NE(header.find("--seed 3 --selection paper --tests 64 --name tiny_64. Do not edit."), std::string::npos);
  EXPECT_TRUE(fs::exists(dir.path / "a" / "registry.hpp"));

  // The JSON copy loads at run time; the patch file reproduces the same tests.
  const ComparisonSet learned = loadComparisonSetJson((dir.path / "a" / "tiny_64.json").string());
  ASSERT_EQ(learned.tests.size(), 64u);
  EXPECT_EQ(readPatchSet(patchFile).count(), 800u);
  fs::create_directories(dir.path / "c");
  const CliRun reuse = runTrain({"--patches-file", patchFile.string(), "--selection", "paper", "--tests", "64",
                                 "--name", "tiny_64",
                           "--out", (dir.path / "c").string()});
  ASSERT_EQ(reuse.code, 0) << reuse.err;
  const ComparisonSet again = loadComparisonSetJson((dir.path / "c" / "tiny_64.json").string());
  for (size_t i = 0; i < 64; ++i) {
    EXPECT_EQ(again.tests[i].x1, learned.tests[i].x1);
    EXPECT_EQ(again.tests[i].y2, learned.tests[i].y2);
  }
}

// A rig file's camera is chosen by --camera-id, as for mdbrief extract; the choice reaches the
// patch extraction (the size check names the chosen camera's size).
TEST(TrainCli, CameraIdChoosesTheCameraOfARigFile) {
  TempDir dir("camera_id");
  const fs::path images = smallImageFolder(dir);
  if (fs::is_empty(images)) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc not installed");
  const std::string kalibr = MDBRIEF_SOURCE_DIR "/tests/data/camera_formats/kalibr_camchain.yaml";
  const struct {
    std::vector<std::string> args;
    std::string why;
  } cases[] = {
      {{"--camera", kalibr}, "holds cameras cam0, cam1, cam2, cam3, cam4: choose one"},
      {{"--camera", kalibr, "--camera-id", "cam9"}, "has no camera 'cam9'"},
      {{"--camera", kalibr, "--camera-id", "cam1"}, "does not match the camera's 752x480"},
      {{"--camera", kalibr, "--camera-format", "basalt", "--camera-id", "cam1"}, "key 'value0' is missing"},
      {{"--camera-id", "cam1"}, "a camera id or format needs a camera"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.why);
    std::vector<std::string> args{"--images", images.string(), "--out", dir.path.string()};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const CliRun r = runTrain(args);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find(c.why), std::string::npos) << r.err;
  }
}

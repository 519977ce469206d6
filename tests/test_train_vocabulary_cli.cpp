// mdbrief-train-vocabulary end to end (in-process): .npy descriptor files and images in, a
// vocabulary file out, byte-identical for the same seed; bad input exits 2 naming the option or
// file and writes nothing; held-out images are refused by digest.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include <opencv2/imgcodecs.hpp>

#include "mdbrief/describe/descriptor.hpp"
#include "mdbrief/detect/detector.hpp"
#include "mdbrief/recognition/vocabulary.hpp"
#include "mdbrief/recognition/vocabulary_text.hpp"
#include "option_flag_message.hpp"
#include "test_data.hpp"
#include "vocabulary/descriptor_npy.hpp"
#include "vocabulary/train_vocabulary_cli.hpp"
#include "write_limits.hpp"

namespace fs = std::filesystem;
using namespace mdbrief;
using mdbrief::testing::readFile;
using mdbrief::testing::TempDir;

namespace {

struct CliRun {
  int code;
  std::string out, err;
};

CliRun run(const std::vector<std::string>& args) {
  std::ostringstream out, err;
  const int code = vocab::runTrainVocabularyCli(args, out, err);
  return {code, out.str(), err.str()};
}

void writeBytes(const fs::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary | std::ios::trunc) << bytes;
}

// Three images' worth of random 256-bit descriptors and masks as .npy files.
std::vector<std::string> npyFiles(const TempDir& dir, bool withMasks) {
  std::vector<std::string> args{"--descriptors"};
  std::vector<std::string> masks{"--masks"};
  cv::RNG rng(7);
  for (int i = 0; i < 3; ++i) {
    cv::Mat d(300, 32, CV_8UC1), m(300, 32, CV_8UC1);
    rng.fill(d, cv::RNG::UNIFORM, 0, 256);
    rng.fill(m, cv::RNG::UNIFORM, 0, 256);
    const fs::path dp = dir.path / ("d" + std::to_string(i) + ".npy"), mp = dir.path / ("m" + std::to_string(i) + ".npy");
    writeBytes(dp, vocab::descriptorNpyBytes(d));
    writeBytes(mp, vocab::descriptorNpyBytes(m));
    args.push_back(dp.string());
    masks.push_back(mp.string());
  }
  if (withMasks) args.insert(args.end(), masks.begin(), masks.end());
  return args;
}

std::vector<std::string> plus(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

}  // namespace

TEST(TrainVocabularyCli, DescriptorFilesGiveTheSameBytesForTheSameSeed) {
  TempDir dir("tv_npy");
  const std::string a = (dir.path / "a.mdbvoc").string(), b = (dir.path / "b.mdbvoc").string();
  const auto inputs = npyFiles(dir, true);
  const std::vector<std::string> common{"--branching", "5", "--depth", "3", "--seed", "4"};
  CliRun r = run(plus(plus(inputs, common), {"--out", a}));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("masked, 256 bits"), std::string::npos) << r.out;
  ASSERT_EQ(run(plus(plus(inputs, common), {"--out", b})).code, 0);
  EXPECT_EQ(readFile(a), readFile(b));
  const Vocabulary v = Vocabulary::load(a);
  EXPECT_TRUE(v.masked());
  EXPECT_EQ(v.branching(), 5);
  EXPECT_LE(v.wordCount(), 125u);
  EXPECT_GT(v.wordCount(), 60u);
  // Without masks, or with --plain: a plain vocabulary, also as DBoW2 text.
  const std::string c = (dir.path / "c.mdbvoc").string(), text = (dir.path / "c.txt").string();
  r = run(plus(plus(npyFiles(dir, false), common), {"--out", c, "--dbow2-text", text}));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(Vocabulary::load(c).masked());
  EXPECT_EQ(importDbow2Text(text).fileBytes(), readFile(c));
}

TEST(TrainVocabularyCli, BadInputExitsWith2NamingTheProblemAndWritesNothing) {
  TempDir dir("tv_bad");
  const std::string out = (dir.path / "v.mdbvoc").string();
  const auto inputs = npyFiles(dir, true);
  writeBytes(dir.path / "bad.npy", "\x93NUMPY\x01\x00\x10\x00{'descr': '<f4'}");
  writeBytes(dir.path / "wide.npy", vocab::descriptorNpyBytes(cv::Mat(5, 64, CV_8UC1, cv::Scalar(1))));
  const std::string image = (dir.path / "image.png").string();
  cv::Mat pixels(64, 64, CV_8UC1);
  cv::randu(pixels, 0, 256);
  ASSERT_TRUE(cv::imwrite(image, pixels));
  const std::string kalibr = MDBRIEF_SOURCE_DIR "/tests/data/camera_formats/kalibr_camchain.yaml";
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--out", out}, "give either --images"},
      {plus(inputs, {"--images", dir.path.string(), "--out", out}), "give either --images"},
      {plus(inputs, {}), "--out is required"},
      {plus(inputs, {"--out", (dir.path / "no" / "v.mdbvoc").string()}), "output folder " + (dir.path / "no").string() + " does not exist"},
      {plus(inputs, {"--out", out, "--dbow2-text", (dir.path / "t.txt").string()}), "has no masks"},
      {plus(inputs, {"--out", out, "--branching", "1"}), "--branching"},
      {{"--descriptors", (dir.path / "bad.npy").string(), "--out", out}, "bad.npy"},
      {{"--descriptors", inputs[1], (dir.path / "wide.npy").string(), "--plain", "--out", out}, "the images before have 32"},
      {{"--descriptors", inputs[1], "--masks", inputs[5], inputs[6], "--out", out}, "--masks: 2 files for 1"},
      {{"--descriptors", (dir.path / "missing.npy").string(), "--out", out}, "no such file"},
      {{"--images", (dir.path / "missing").string(), "--out", out}, "no such image or folder"},
      // Issue 29: a device was "no such image or folder".
      {{"--images", "/dev/zero", "--out", out}, "/dev/zero: is a character device, not a regular file"},
      // Issue 46: --bits and --nfeatures are the library's flags, with its ranges and messages.
      {{"--images", dir.path.string(), "--bits", "100", "--out", out},
       mdbrief::testing::optionFlagMessage(descriptorOptionFields(), "bits", "100")},
      {{"--images", dir.path.string(), "--nfeatures", "0", "--out", out},
       mdbrief::testing::optionFlagMessage(detectorOptionFields(), "nfeatures", "0")},
      {{"--images", dir.path.string(), "--extractor", "orb", "--nfeatures", "-1", "--out", out},
       mdbrief::testing::optionFlagMessage(detectorOptionFields(), "nfeatures", "-1")},
      {{"--images", dir.path.string(), "--nfeatures", "10000001", "--out", out},
       mdbrief::testing::optionFlagMessage(detectorOptionFields(), "nfeatures", "10000001")},
      {{"--images", dir.path.string(), "--extractor", "sift", "--out", out}, "--extractor"},
      // The old spelling of --extractor names the new one.
      {{"--images", dir.path.string(), "--features", "orb", "--out", out}, "--features: is now --extractor"},
      {{"--images", dir.path.string(), "--preset", "fast", "--out", out}, "--preset"},
      {plus(inputs, {"--out", out, "--depth", "0"}), "--depth"},
      {plus(inputs, {"--out", out, "--rounds", "0"}), "--rounds"},
      {plus(inputs, {"--out", out, "--mask-agreement", "1.5"}), "--mask-agreement"},
      {plus(inputs, {"--out", out, "--weighting", "bm25"}), "--weighting"},
      {plus(inputs, {"--out", out, "--seed", "x"}), "--seed"},
      {{"--images", image, "--camera", (dir.path / "none.yaml").string(), "--out", out},
       "--camera: " + (dir.path / "none.yaml").string() + ": no such file"},
      // A rig file: the camera is chosen by --camera-id, as for mdbrief extract.
      {{"--images", image, "--camera", kalibr, "--out", out}, "holds cameras cam0, cam1, cam2, cam3, cam4: choose one"},
      {{"--images", image, "--camera", kalibr, "--camera-id", "cam9", "--out", out}, "has no camera 'cam9'"},
      {{"--images", image, "--camera", kalibr, "--camera-id", "cam1", "--out", out},
       "64x64, but --camera " + kalibr + " is calibrated for 752x480"},
      {{"--images", image, "--camera-id", "cam1", "--out", out}, "--camera-format and --camera-id need --camera"},
      {{"--images", image, "--held-out", (dir.path / "none.txt").string(), "--out", out},
       "--held-out: " + (dir.path / "none.txt").string() + ": no such file"},
      // Issue 29: read without bound until std::bad_alloc. Issue 45: refused when the flags are
      // parsed, as every tool's input files.
      {{"--images", image, "--held-out", "/dev/zero", "--out", out},
       "--held-out: /dev/zero: is a character device, not a regular file"},
  };
  for (const auto& [args, expected] : cases) {
    const CliRun r = run(args);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << "expected '" << expected << "' in: " << r.err;
    EXPECT_FALSE(fs::exists(out));
  }
}

// Issue 29: `--descriptors dd.npy --plain --out dd.npy` replaced its input, `--out same.bin
// --dbow2-text same.bin` wrote the text over the binary.
TEST(TrainVocabularyCli, AnOutputThatIsAnInputOrTheOtherOutputIsRefusedAndNothingChanges) {
  TempDir dir("tv_same");
  const auto inputs = npyFiles(dir, false);
  const std::string input = inputs[1], before = readFile(input);
  fs::create_symlink(input, dir.path / "link.npy");
  const std::string out = (dir.path / "v.bin").string();
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {plus(inputs, {"--plain", "--out", input}), input + ": the output is the same file as the input " + input},
      {plus(inputs, {"--plain", "--out", (dir.path / "link.npy").string()}), "the same file as the input " + input},
      {plus(inputs, {"--plain", "--out", out, "--dbow2-text", input}), "the same file as the input " + input},
      {plus(inputs, {"--plain", "--out", out, "--dbow2-text", out}), "the same file as the output " + out},
  };
  for (const auto& [args, expected] : cases) {
    const CliRun r = run(args);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << "expected '" << expected << "' in: " << r.err;
    EXPECT_EQ(readFile(input), before);
    EXPECT_FALSE(fs::exists(out));
  }
}

// Issue 29: the binary was replaced before the text failed. Both are one set now: a text that
// cannot be written leaves the previous binary as well.
TEST(TrainVocabularyCli, TheBinaryAndTheTextAreReplacedTogether) {
  TempDir dir("tv_set");
  const auto inputs = npyFiles(dir, false);
  const std::string out = (dir.path / "v.mdbvoc").string(), text = (dir.path / "v.txt").string();
  const std::vector<std::string> args = plus(inputs, {"--plain", "--branching", "4", "--depth", "2", "--out", out,
                                                      "--dbow2-text", text});
  ASSERT_EQ(run(plus(args, {"--seed", "1"})).code, 0);
  const std::string binary = readFile(out), oldText = readFile(text);
  ASSERT_LT(binary.size() + 512, oldText.size());
  CliRun r;
  {
    // Room for the binary, not for the text.
    const mdbrief::testing::FileSizeLimit limit((binary.size() + oldText.size()) / 2);
    r = run(plus(args, {"--seed", "2"}));
  }
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find(text), std::string::npos) << r.err;
  EXPECT_EQ(readFile(out), binary);
  EXPECT_EQ(readFile(text), oldText);
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir.path)) names.push_back(entry.path().filename().string());
  EXPECT_EQ(std::count_if(names.begin(), names.end(), [](const std::string& n) { return n[0] == '.'; }), 0);
}

TEST(TrainVocabularyCli, ImagesAreDescribedAtTheAskedLengthAndHeldOutOnesRefused) {
  const auto doc = mdbrief::testing::opencvDocDataDir();
  if (!doc || !fs::exists(*doc / "box.png") || !fs::exists(*doc / "graf1.png"))
    MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc sample photos not found (scripts/setup-deps.sh)");
  TempDir dir("tv_images");
  const std::string out = (dir.path / "v.mdbvoc").string();
  CliRun r = run({"--images", (*doc / "box.png").string(), (*doc / "box_in_scene.png").string(), "--bits", "128",
                  "--branching", "4", "--depth", "2", "--out", out});
  ASSERT_EQ(r.code, 0) << r.err;
  const Vocabulary v = Vocabulary::load(out);
  EXPECT_EQ(v.bits(), 128);
  EXPECT_TRUE(v.masked());
  EXPECT_EQ(v.trainingImages().size(), 2u);
  r = run({"--images", (*doc / "box.png").string(), "--extractor", "orb", "--branching", "4", "--depth", "2", "--out", out});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(Vocabulary::load(out).masked());
  EXPECT_EQ(Vocabulary::load(out).bits(), 256);
  // graf1.png is an evaluation image (configs/held-out-images.txt).
  fs::remove(out);
  r = run({"--images", (*doc / "box.png").string(), (*doc / "graf1.png").string(), "--out", out});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("graf1.png: held out"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

// What numpy 1.24 wrote (/usr/bin/python3): a = (np.arange(112, dtype=np.uint8) * 37 + 11).reshape(7, 16),
// then np.lib.format.write_array(f, a, version=(1, 0)) (np.save's format) and version=(2, 0).
const char* const kNumpy1Hex =
    "934e554d5059010076007b276465736372273a20277c7531272c2027666f727472616e5f6f72646572273a2046616c73"
    "652c20277368617065273a2028372c203136292c207d2020202020202020202020202020202020202020202020202020"
    "202020202020202020202020202020202020202020202020202020202020200a0b30557a9fc4e90e33587da2c7ec1136"
    "5b80a5caef14395e83a8cdf2173c6186abd0f51a3f6489aed3f81d42678cb1d6fb20456a8fb4d9fe23486d92b7dc0126"
    "4b7095badf04294e7398bde2072c51769bc0e50a2f54799ec3e80d32577ca1c6eb10355a7fa4c9ee13385d82a7ccf116";
const char* const kNumpy2Hex =
    "934e554d50590200740000007b276465736372273a20277c7531272c2027666f727472616e5f6f72646572273a204661"
    "6c73652c20277368617065273a2028372c203136292c207d202020202020202020202020202020202020202020202020"
    "202020202020202020202020202020202020202020202020202020202020200a0b30557a9fc4e90e33587da2c7ec1136"
    "5b80a5caef14395e83a8cdf2173c6186abd0f51a3f6489aed3f81d42678cb1d6fb20456a8fb4d9fe23486d92b7dc0126"
    "4b7095badf04294e7398bde2072c51769bc0e50a2f54799ec3e80d32577ca1c6eb10355a7fa4c9ee13385d82a7ccf116";

std::string fromHex(const std::string& hex) {
  std::string bytes;
  for (size_t i = 0; i + 1 < hex.size(); i += 2) bytes += static_cast<char>(std::stoi(hex.substr(i, 2), nullptr, 16));
  return bytes;
}

TEST(DescriptorNpy, ReadsWhatNumpyWritesAndRefusesOtherArrays) {
  TempDir dir("npy");
  cv::Mat d(7, 16, CV_8UC1);
  for (int i = 0; i < 112; ++i) d.data[i] = static_cast<uint8_t>(i * 37 + 11);
  const fs::path p = dir.path / "d.npy";
  const std::string good = fromHex(kNumpy1Hex);
  for (const std::string& numpyBytes : {good, fromHex(kNumpy2Hex)}) {
    writeBytes(p, numpyBytes);
    EXPECT_EQ(cv::norm(vocab::readDescriptorNpy(p.string()), d, cv::NORM_L1), 0.0) << int(numpyBytes[6]);
  }
  EXPECT_EQ(vocab::descriptorNpyBytes(d), good) << "the writer's bytes are np.save's";
  const auto problem = [&](const std::string& bytes) -> std::string {
    writeBytes(p, bytes);
    try {
      vocab::readDescriptorNpy(p.string());
    } catch (const std::exception& e) {
      return e.what();
    }
    return "read";
  };
  const auto edited = [&](const std::string& from, const std::string& to) {
    std::string b = good;
    b.replace(b.find(from), from.size(), to);
    return b;
  };
  EXPECT_NE(problem("hello").find("not a NumPy .npy file"), std::string::npos);
  EXPECT_NE(problem(good.substr(0, good.size() - 1)).find("needs 112 data bytes, the file has 111"), std::string::npos);
  EXPECT_NE(problem(edited("|u1", "<f4")).find("dtype '<f4' is not uint8"), std::string::npos);
  EXPECT_NE(problem(edited("False", "True ")).find("C order"), std::string::npos);
  EXPECT_NE(problem(edited("(7, 16)", "(7, 18)")).find("18 bytes per descriptor"), std::string::npos);
  EXPECT_NE(problem(edited("(7, 16)", "(112,)")).find("is not (N, B)"), std::string::npos);
  EXPECT_EQ(problem(edited("(7, 16)", "(0, 16)") .substr(0, good.size() - 112)), "read") << "no descriptors is fine";
  // Issue 45: a shape whose product overflows 64 bits passed as "needs 9600 data bytes, the file
  // has 9600"; a dimension beyond 64 bits was "not (N, B)".
  const auto withShape = [](const std::string& shape, size_t dataBytes) {
    const std::string header = "{'descr': '|u1', 'fortran_order': False, 'shape': " + shape + ", }\n";
    std::string b("\x93NUMPY\x01\x00", 8);
    b += static_cast<char>(header.size() & 0xFF);
    b += static_cast<char>(header.size() >> 8);
    return b + header + std::string(dataBytes, '\0');
  };
  EXPECT_EQ(problem(withShape("(2400, 4)", 9600)), "read");
  EXPECT_NE(problem(withShape("(4611686018427390304, 4)", 9600))
                .find("shape (4611686018427390304, 4) is too large: 2^64 bytes or more (the file has 9600 data bytes)"),
            std::string::npos)
      << problem(withShape("(4611686018427390304, 4)", 9600));
  EXPECT_NE(problem(withShape("(1180591620717411303424, 4)", 9600))
                .find("shape (1180591620717411303424, 4) is too large: 2^64 bytes or more"),
            std::string::npos)
      << problem(withShape("(1180591620717411303424, 4)", 9600));
}

#include "fuzz_targets.hpp"

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string_view>

#include <unistd.h>

#include "cli/extraction_flags.hpp"
#include "mdbrief/camera/io.hpp"
#include "mdbrief/camera/rig.hpp"
#include "mdbrief/recognition/database.hpp"
#include "mdbrief/internal/base/io/framed_file.hpp"
#include "mdbrief/internal/base/io/nesting.hpp"
#include "mdbrief/describe/patterns.hpp"
#include "mdbrief/recognition/vocabulary_text.hpp"
#include "patchextract/image_digest.hpp"
#include "patchextract/patch_set.hpp"
#include "toolkit/homography_file.hpp"
#include "trainer/train_cli.hpp"
#include "vocabulary/descriptor_npy.hpp"

namespace mdbrief::fuzz {

namespace {

namespace fs = std::filesystem;

// The parsers read files: the input goes to a per-process file with the extension the parser
// keys on. The files are removed when the process exits, so fuzzing leaves nothing in the
// temporary directory.
class ScratchFiles {
 public:
  ~ScratchFiles() {
    for (const fs::path& p : paths_) {
      std::error_code ignored;
      fs::remove(p, ignored);
    }
  }
  std::string write(const uint8_t* data, size_t size, const std::string& extension) {
    const fs::path p =
        fs::temp_directory_path() / ("mdbrief_fuzz_" + std::to_string(::getpid()) + extension);
    paths_.insert(p);
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    out.close();
    // A lost write would fuzz a stale file; stop rather than report coverage that is not there.
    if (!out) {
      std::fprintf(stderr, "fuzz: cannot write %s\n", p.c_str());
      std::abort();
    }
    return p.string();
  }

 private:
  std::set<fs::path> paths_;
};

std::string asFile(const uint8_t* data, size_t size, const std::string& extension) {
  static ScratchFiles files;
  return files.write(data, size, extension);
}

template <class Parse>
void expectingErrors(Parse&& parse) {
  try {
    parse();
  } catch (const std::exception&) {
    // A clear error is the right answer to bad bytes.
  }
}

void camera(const uint8_t* d, size_t n) {
  const std::string path = asFile(d, n, ".yaml");
  expectingErrors([&] { loadCamera(path); });
  // Every camera of the file, its extrinsics, and the size and model a caller gives (which only
  // K and D alone, or four OpenCV coefficients, take).
  expectingErrors([&] {
    CameraFileOptions options;
    options.imageSize = cv::Size(752, 480);
    options.opencvModel = OpenCvModel::Fisheye;
    const CameraRig rig = readCameraRig(path, options);
    for (size_t i = 0; i < rig.size(); ++i)
      for (size_t j = 0; j < rig.size(); ++j)
        if (rig.hasRelativePose(i, j)) rig.relativePose(i, j);
  });
}
void patternJson(const uint8_t* d, size_t n) {
  expectingErrors([&] { loadComparisonSetJson(asFile(d, n, ".json")); });
}
void keypoints(const uint8_t* d, size_t n) {
  expectingErrors([&] { cli::loadKeypoints(asFile(d, n, ".yml")); });
}
void patchSet(const uint8_t* d, size_t n) {
  expectingErrors([&] { train::readPatchSet(asFile(d, n, ".h5")); });
}
// A vocabulary that loaded is used: descriptors of its width (with masks) descend its tree.
void quantise(const Vocabulary& v) {
  cv::Mat desc(4, v.descriptorBytes(), CV_8UC1), masks(4, v.descriptorBytes(), CV_8UC1);
  for (int i = 0; i < desc.rows * desc.cols; ++i) {
    desc.data[i] = static_cast<uint8_t>(i * 37 + 11);
    masks.data[i] = static_cast<uint8_t>(i * 91 + 5);
  }
  Database db(v);
  db.add(v.transform(desc, masks).bow);
  db.query(v.transform(desc).bow, 2);
}

// Binary files are tried as given and with their checksum repaired: otherwise nearly every
// mutation would stop at the checksum and the checks behind it would never run.
template <class Load>
void framed(const uint8_t* d, size_t n, const std::string& extension, Load&& load) {
  std::string bytes(reinterpret_cast<const char*>(d), n);
  expectingErrors([&] { load(asFile(d, n, extension)); });
  internal::repairChecksum(bytes);
  expectingErrors([&] { load(asFile(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), extension)); });
}

void vocabulary(const uint8_t* d, size_t n) {
  framed(d, n, ".mdbvoc", [](const std::string& path) { quantise(Vocabulary::load(path)); });
}
void vocabularyText(const uint8_t* d, size_t n) {
  expectingErrors([&] { quantise(importDbow2Text(asFile(d, n, ".txt"))); });
}
void database(const uint8_t* d, size_t n) {
  framed(d, n, ".mdbdb", [](const std::string& path) {
    const Database db = Database::load(path, databaseVocabulary());
    for (uint32_t e = 0; e < db.size(); ++e) db.query(db.entry(e), 3);
  });
}

void heldOutList(const uint8_t* d, size_t n) {
  expectingErrors([&] { train::readHeldOutImages(asFile(d, n, ".txt")); });
}
void homography(const uint8_t* d, size_t n) {
  expectingErrors([&] { readHomography(asFile(d, n, "")); });
}

void descriptorNpy(const uint8_t* d, size_t n) {
  expectingErrors([&] { vocab::readDescriptorNpy(asFile(d, n, ".npy")); });
}

// The scan before every structured-text parser: fed in parts (a decompressed stream's), it finds
// what it finds in the whole text, at the same line.
void nesting(const uint8_t* d, size_t n) {
  const std::string_view text(reinterpret_cast<const char*>(d), n);
  const std::string whole = internal::nestingProblem(text);
  internal::NestingScan parts;
  for (size_t at = 0, step = 1; at < n; at += step, step = step * 3 % 17 + 1)
    if (!parts.feed(text.substr(at, step))) break;
  if (parts.problem() != whole) std::abort();
}

void trainConfig(const uint8_t* d, size_t n) {
  // A missing output folder stops the tool right after parsing, before any training.
  std::ostringstream out, err;
  train::runTrainCli({"--config", asFile(d, n, ".toml"), "--out", "/nonexistent/mdbrief_fuzz"}, out, err);
}

}  // namespace

Vocabulary databaseVocabulary() {
  // Root -> 4 nodes -> 4 words each, 32 bits, centroids spread over the bytes.
  VocabularyTree t;
  t.bits = 32;
  t.branching = 4;
  t.depth = 2;
  t.childBegin.assign(21, 0);
  t.childCount.assign(21, 0);
  t.childBegin[0] = 1;
  t.childCount[0] = 4;
  for (uint32_t i = 1; i <= 4; ++i) {
    t.childBegin[i] = 1 + 4 * i;
    t.childCount[i] = 4;
  }
  t.centroids = cv::Mat(21, 4, CV_8UC1);
  for (int r = 0; r < 21; ++r)
    for (int c = 0; c < 4; ++c) t.centroids.at<uint8_t>(r, c) = r == 0 ? 0 : static_cast<uint8_t>(r * 53 + c * 17);
  t.wordWeights.assign(16, 1.0f);
  return Vocabulary::create(t);
}

const std::vector<Target>& targets() {
  static const std::vector<Target> all{{"camera", camera},
                                       {"pattern_json", patternJson},
                                       {"keypoints", keypoints},
                                       {"patch_set", patchSet},
                                       {"train_config", trainConfig},
                                       {"vocabulary", vocabulary},
                                       {"vocabulary_text", vocabularyText},
                                       {"database", database},
                                       {"held_out_list", heldOutList},
                                       {"homography", homography},
                                       {"descriptor_npy", descriptorNpy},
                                       {"nesting", nesting}};
  return all;
}

}  // namespace mdbrief::fuzz

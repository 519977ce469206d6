#include "fuzz_targets.hpp"

#include <exception>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include "cli/extraction_flags.hpp"
#include "mdbrief/camera_io.hpp"
#include "mdbrief/patterns.hpp"
#include "patchextract/patch_set.hpp"
#include "trainer/train_cli.hpp"

namespace mdbrief::fuzz {

namespace {

namespace fs = std::filesystem;

// The parsers read files: the input goes to a per-process file with the extension the parser
// keys on.
std::string asFile(const uint8_t* data, size_t size, const std::string& extension) {
  const fs::path p = fs::temp_directory_path() / ("mdbrief_fuzz_" + std::to_string(::getpid()) + extension);
  std::ofstream(p, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data),
                                                             static_cast<std::streamsize>(size));
  return p.string();
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
  expectingErrors([&] { loadCamera(asFile(d, n, ".yaml")); });
}
void patternJson(const uint8_t* d, size_t n) {
  expectingErrors([&] { loadTestSetJson(asFile(d, n, ".json")); });
}
void keypoints(const uint8_t* d, size_t n) {
  expectingErrors([&] { cli::loadKeypoints(asFile(d, n, ".yml")); });
}
void patchSet(const uint8_t* d, size_t n) {
  expectingErrors([&] { train::readPatchSet(asFile(d, n, ".h5")); });
}
void trainConfig(const uint8_t* d, size_t n) {
  // A missing output folder stops the tool right after parsing, before any training.
  std::ostringstream out, err;
  train::runTrainCli({"--config", asFile(d, n, ".toml"), "--out", "/nonexistent/mdbrief_fuzz"}, out, err);
}

}  // namespace

const std::vector<Target>& targets() {
  static const std::vector<Target> all{{"camera", camera},
                                       {"pattern_json", patternJson},
                                       {"keypoints", keypoints},
                                       {"patch_set", patchSet},
                                       {"train_config", trainConfig}};
  return all;
}

}  // namespace mdbrief::fuzz

// Vocabulary speed (issue 20's targets): transform of 1000 descriptors single-threaded at 10^5
// words (k = 10, L = 5), masked and plain, 256 and 512 bits; load of a 10^6-word vocabulary
// (k = 10, L = 6) from the binary file, against importing the same vocabulary from DBoW2's text.
// Random centroids: the descent's cost does not depend on them.
//   mdbrief_bench --benchmark_filter=Vocabulary
#include <benchmark/benchmark.h>

#include <filesystem>
#include <map>
#include <memory>
#include <random>
#include <tuple>

#include <opencv2/core.hpp>
#include <unistd.h>

#include "mdbrief/recognition/vocabulary.hpp"
#include "mdbrief/recognition/vocabulary_text.hpp"

namespace {

namespace fs = std::filesystem;

// A complete tree of k^L words, nodes breadth first, random centroids (and masks with about
// three bits in four set).
mdbrief::Vocabulary randomVocabulary(int k, int depth, int bits, bool masked) {
  mdbrief::VocabularyTree t;
  t.bits = bits;
  t.branching = k;
  t.depth = depth;
  t.masked = masked;
  size_t nodes = 1, levelSize = 1;
  for (int d = 0; d < depth; ++d) nodes += (levelSize *= static_cast<size_t>(k));
  t.childBegin.assign(nodes, 0);
  t.childCount.assign(nodes, 0);
  for (size_t n = 0; n < (nodes - levelSize); ++n) {
    t.childBegin[n] = static_cast<uint32_t>(1 + n * k);
    t.childCount[n] = static_cast<uint32_t>(k);
  }
  std::mt19937 rng(5);
  t.centroids.create(static_cast<int>(nodes), bits / 8, CV_8UC1);
  for (size_t i = 0; i < t.centroids.total(); ++i) t.centroids.data[i] = static_cast<uint8_t>(rng());
  t.centroids.row(0).setTo(0);
  if (masked) {
    t.masks.create(static_cast<int>(nodes), bits / 8, CV_8UC1);
    for (size_t i = 0; i < t.masks.total(); ++i) t.masks.data[i] = static_cast<uint8_t>(rng() | rng() | 1);
    t.masks.row(0).setTo(0);
  }
  t.wordWeights.assign(levelSize, 1.0f);
  return mdbrief::Vocabulary::create(t);
}

const mdbrief::Vocabulary& cachedVocabulary(int k, int depth, int bits, bool masked) {
  static std::map<std::tuple<int, int, int, bool>, std::unique_ptr<mdbrief::Vocabulary>> cache;
  auto& slot = cache[{k, depth, bits, masked}];
  if (!slot) slot = std::make_unique<mdbrief::Vocabulary>(randomVocabulary(k, depth, bits, masked));
  return *slot;
}

// Args: bits, masked.
void BM_VocabularyTransform1000(benchmark::State& state) {
  const int bits = static_cast<int>(state.range(0));
  const bool masked = state.range(1) != 0;
  const mdbrief::Vocabulary& v = cachedVocabulary(10, 5, bits, masked);
  cv::Mat desc(1000, bits / 8, CV_8UC1), masks(1000, bits / 8, CV_8UC1);
  cv::randu(desc, 0, 256);
  cv::randu(masks, 0, 256);
  for (auto _ : state) benchmark::DoNotOptimize(v.transform(desc, masked ? masks : cv::Mat()));
  state.SetLabel(std::to_string(v.wordCount()) + " words, " + (masked ? "masked" : "plain"));
}
BENCHMARK(BM_VocabularyTransform1000)
    ->Args({256, 1})
    ->Args({256, 0})
    ->Args({512, 1})
    ->Args({512, 0})
    ->Unit(benchmark::kMicrosecond);

struct VocabularyFiles {
  fs::path binary, masked, text;
  size_t words = 0;
  ~VocabularyFiles() {
    std::error_code ec;
    fs::remove(binary, ec);
    fs::remove(masked, ec);
    fs::remove(text, ec);
  }
};

// A plain 256-bit 10^6-word vocabulary written once in both formats, and a masked one.
const VocabularyFiles& millionWordFiles() {
  static VocabularyFiles files = [] {
    VocabularyFiles f;
    const fs::path dir = fs::temp_directory_path();
    f.binary = dir / ("mdbrief_bench_vocabulary_" + std::to_string(::getpid()) + ".mdbvoc");
    f.text = dir / ("mdbrief_bench_vocabulary_" + std::to_string(::getpid()) + ".txt");
    f.masked = dir / ("mdbrief_bench_vocabulary_masked_" + std::to_string(::getpid()) + ".mdbvoc");
    randomVocabulary(10, 6, 256, true).save(f.masked.string());
    const mdbrief::Vocabulary v = randomVocabulary(10, 6, 256, false);
    v.save(f.binary.string());
    mdbrief::exportDbow2Text(v, f.text.string());
    f.words = v.wordCount();
    return f;
  }();
  return files;
}

void BM_VocabularyLoadMillionWords(benchmark::State& state) {
  const VocabularyFiles& f = millionWordFiles();
  for (auto _ : state) benchmark::DoNotOptimize(mdbrief::Vocabulary::load(f.binary.string()));
  state.SetLabel(std::to_string(f.words) + " words, " + std::to_string(fs::file_size(f.binary)) + " bytes");
}
BENCHMARK(BM_VocabularyLoadMillionWords)->Unit(benchmark::kMillisecond);

void BM_VocabularyLoadMillionWordsMasked(benchmark::State& state) {
  const VocabularyFiles& f = millionWordFiles();
  for (auto _ : state) benchmark::DoNotOptimize(mdbrief::Vocabulary::load(f.masked.string()));
  state.SetLabel(std::to_string(fs::file_size(f.masked)) + " bytes");
}
BENCHMARK(BM_VocabularyLoadMillionWordsMasked)->Unit(benchmark::kMillisecond);

void BM_VocabularyImportDbow2TextMillionWords(benchmark::State& state) {
  const VocabularyFiles& f = millionWordFiles();
  for (auto _ : state) benchmark::DoNotOptimize(mdbrief::importDbow2Text(f.text.string()));
  state.SetLabel(std::to_string(f.words) + " words, " + std::to_string(fs::file_size(f.text)) + " bytes");
}
BENCHMARK(BM_VocabularyImportDbow2TextMillionWords)->Unit(benchmark::kMillisecond)->Iterations(2);

}  // namespace

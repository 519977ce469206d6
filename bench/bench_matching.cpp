// Brute-force matching speed: mdbrief plain and masked matchers against cv::BFMatcher
// (NORM_HAMMING) on the same 1000 x 1000 descriptors, 256 and 512 bits, single-threaded and
// with all cores. Counter "per_pair" = wall time per query/train pair.
// Guided matching (guided_matcher.hpp) against brute force on the same keypoints, 1000 and 5000
// per image, radius 15 px, one thread: the two are timed alternately within each iteration, so
// a change of the shared machine's load moves both and not their ratio (counter guided_over_bf).
//   mdbrief_bench --benchmark_filter=Match
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include "mdbrief/match/guided_matcher.hpp"
#include "mdbrief/match/matcher.hpp"

namespace {

constexpr int kQueries = 1000;
constexpr int kTrains = 1000;

struct MatchData {
  cv::Mat query, train, queryMasks, trainMasks;
};

// Fixed-seed data; half the queries are noisy copies of train rows so that matching finds real
// neighbours, masks keep ~80% of the bits as mdBRIEF's typically do.
const MatchData& data(int bytes) {
  static std::unique_ptr<MatchData> cache[2];
  auto& slot = cache[bytes == 64 ? 1 : 0];
  if (slot) return *slot;
  slot = std::make_unique<MatchData>();
  std::mt19937 rng(123 + bytes);
  std::uniform_int_distribution<int> byte(0, 255), row(0, kTrains - 1), bitIndex(0, bytes * 8 - 1);
  std::bernoulli_distribution keep(0.8);
  auto randomMat = [&](int rows) {
    cv::Mat m(rows, bytes, CV_8UC1);
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < bytes; ++c) m.at<uint8_t>(r, c) = static_cast<uint8_t>(byte(rng));
    return m;
  };
  auto maskMat = [&](int rows) {
    cv::Mat m(rows, bytes, CV_8UC1, cv::Scalar(0));
    for (int r = 0; r < rows; ++r)
      for (int d = 0; d < bytes * 8; ++d)
        if (keep(rng)) m.at<uint8_t>(r, d / 8) |= static_cast<uint8_t>(1u << (d % 8));
    return m;
  };
  slot->train = randomMat(kTrains);
  slot->query = randomMat(kQueries);
  for (int q = 0; q < kQueries; q += 2) {
    slot->train.row(row(rng)).copyTo(slot->query.row(q));
    for (int f = 0; f < bytes; ++f) {
      const int d = bitIndex(rng);
      slot->query.at<uint8_t>(q, d / 8) ^= static_cast<uint8_t>(1u << (d % 8));
    }
  }
  slot->trainMasks = maskMat(kTrains);
  slot->queryMasks = maskMat(kQueries);
  return *slot;
}

// Arg 0: descriptor bytes; arg 1: 1 = single thread (TBB and OpenCV limited to one), 0 = all
// cores.
struct Threads {
  explicit Threads(bool single)
      : control(tbb::global_control::max_allowed_parallelism,
                single ? 1 : tbb::info::default_concurrency()),
        previousCv(cv::getNumThreads()) {
    cv::setNumThreads(single ? 1 : -1);  // -1: OpenCV's default thread count
  }
  ~Threads() { cv::setNumThreads(previousCv); }
  tbb::global_control control;
  int previousCv;
};

void setCounters(benchmark::State& state) {
  state.counters["per_pair"] = benchmark::Counter(
      static_cast<double>(kQueries) * kTrains,
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_MatchPlain(benchmark::State& state) {
  const MatchData& d = data(static_cast<int>(state.range(0)));
  const Threads threads(state.range(1) == 1);
  mdbrief::MatchOptions options = mdbrief::nearestNeighbourOptions();  // as cv::BFMatcher::match
  options.parallel = state.range(1) != 1;
  for (auto _ : state) {
    benchmark::DoNotOptimize(mdbrief::matchBruteForce(d.query, d.train, options));
  }
  setCounters(state);
}

void BM_MatchMasked(benchmark::State& state) {
  const MatchData& d = data(static_cast<int>(state.range(0)));
  const Threads threads(state.range(1) == 1);
  mdbrief::MatchOptions options = mdbrief::nearestNeighbourOptions();  // as cv::BFMatcher::match
  options.parallel = state.range(1) != 1;
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        mdbrief::matchBruteForceMasked(d.query, d.queryMasks, d.train, d.trainMasks, options));
  }
  setCounters(state);
}

void BM_MatchOpenCvBF(benchmark::State& state) {
  const MatchData& d = data(static_cast<int>(state.range(0)));
  const Threads threads(state.range(1) == 1);
  cv::BFMatcher matcher(cv::NORM_HAMMING);
  std::vector<cv::DMatch> matches;
  for (auto _ : state) {
    matcher.match(d.query, d.train, matches);
    benchmark::DoNotOptimize(matches.data());
  }
  setCounters(state);
}

void matchArgs(benchmark::internal::Benchmark* b) {
  b->ArgNames({"bytes", "single"});
  for (int bytes : {32, 64})
    for (int single : {1, 0}) b->Args({bytes, single});
  b->UseRealTime()->Unit(benchmark::kMicrosecond);
}

// A tracker's frame pair: n keypoints spread over a VGA image, n queries each a noisy copy of a
// train descriptor (8 of 256 bits flipped) whose prediction is within 10 px of its keypoint.
struct GuidedData {
  cv::Mat query, queryMasks, train, trainMasks;
  std::vector<cv::KeyPoint> trainKeypoints;
  std::vector<cv::Point2f> predicted;
};

const cv::Size kGuidedImage(640, 480);

GuidedData guidedData(int n) {
  GuidedData g;
  std::mt19937 rng(77 + n);
  std::uniform_int_distribution<int> byte(0, 255), bit(0, 255), pick(0, n - 1);
  std::uniform_real_distribution<float> x(0.f, 639.f), y(0.f, 479.f), unit(0.f, 1.f);
  std::bernoulli_distribution keep(0.8);
  auto rows = [&](bool mask) {
    cv::Mat m(n, 32, CV_8UC1);
    for (int r = 0; r < n; ++r)
      for (int c = 0; c < 32; ++c) {
        int v = mask ? 0 : byte(rng);
        for (int b = 0; mask && b < 8; ++b) v |= keep(rng) << b;
        m.at<uint8_t>(r, c) = static_cast<uint8_t>(v);
      }
    return m;
  };
  g.train = rows(false);
  g.trainMasks = rows(true);
  g.queryMasks = rows(true);
  g.query.create(n, 32, CV_8UC1);
  for (int t = 0; t < n; ++t) g.trainKeypoints.emplace_back(x(rng), y(rng), 7.f);
  for (int q = 0; q < n; ++q) {
    const int t = pick(rng);
    g.train.row(t).copyTo(g.query.row(q));
    for (int f = 0; f < 8; ++f) {
      const int d = bit(rng);
      g.query.at<uint8_t>(q, d / 8) ^= static_cast<uint8_t>(1u << (d % 8));
    }
    const float r = 10.f * unit(rng), a = 6.2831853f * unit(rng);
    g.predicted.emplace_back(g.trainKeypoints[t].pt.x + r * std::cos(a), g.trainKeypoints[t].pt.y + r * std::sin(a));
  }
  return g;
}

// Masked matching with the library's defaults (ratio test, mutual check) both ways; the
// iteration time is the guided call's, counters give both in ms and their ratio.
void BM_MatchGuidedVsBruteForce(benchmark::State& state) {
  const GuidedData g = guidedData(static_cast<int>(state.range(0)));
  const Threads threads(true);
  mdbrief::GuidedMatchOptions options;
  options.radius = 15.f;
  options.matching.parallel = false;
  using Clock = std::chrono::steady_clock;
  double guidedSeconds = 0, bruteSeconds = 0;
  size_t guidedMatches = 0, bruteMatches = 0;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    const auto guided = mdbrief::matchGuidedMasked(g.query, g.queryMasks, {}, g.predicted, g.train, g.trainMasks,
                                                   g.trainKeypoints, kGuidedImage, options);
    const auto t1 = Clock::now();
    const auto brute = mdbrief::matchBruteForceMasked(g.query, g.queryMasks, g.train, g.trainMasks, options.matching);
    const auto t2 = Clock::now();
    const double guidedIteration = std::chrono::duration<double>(t1 - t0).count();
    guidedSeconds += guidedIteration;
    bruteSeconds += std::chrono::duration<double>(t2 - t1).count();
    guidedMatches = guided.size();
    bruteMatches = brute.size();
    state.SetIterationTime(guidedIteration);
  }
  const double iterations = static_cast<double>(state.iterations());
  state.counters["guided_ms"] = 1e3 * guidedSeconds / iterations;
  state.counters["bf_ms"] = 1e3 * bruteSeconds / iterations;
  state.counters["guided_over_bf"] = guidedSeconds / bruteSeconds;
  state.counters["guided_matches"] = static_cast<double>(guidedMatches);
  state.counters["bf_matches"] = static_cast<double>(bruteMatches);
}

BENCHMARK(BM_MatchGuidedVsBruteForce)->ArgName("keypoints")->Arg(1000)->Arg(5000)->UseManualTime()->Unit(
    benchmark::kMicrosecond);

BENCHMARK(BM_MatchPlain)->Apply(matchArgs);
BENCHMARK(BM_MatchMasked)->Apply(matchArgs);
BENCHMARK(BM_MatchOpenCvBF)->Apply(matchArgs);

}  // namespace

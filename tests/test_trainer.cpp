// Trainer core: candidates, bit-packed responses, streamed counts, variance sort, greedy
// selection, and the streamed trainer against the tests the full-matrix trainer learned.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "trainer/candidate_comparisons.hpp"
#include "trainer/comparison_responses.hpp"
#include "trainer/greedy_selection.hpp"
#include "trainer/trainer.hpp"

using namespace mdbrief;
using namespace mdbrief::train;

namespace {

std::vector<uint8_t> randomPatches(size_t count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<uint8_t> px(count * 1024);
  for (auto& v : px) v = static_cast<uint8_t>(rng() & 0xff);
  return px;
}

// Smooth random patches (sums of a few gradients): tests have structured, unequal variances.
std::vector<uint8_t> structuredPatches(size_t count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<uint8_t> px(count * 1024);
  for (size_t p = 0; p < count; ++p) {
    const double gx = u(rng), gy = u(rng), c = u(rng), bias = u(rng) * 0.5;
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 32; ++x) {
        const double v = 128 + 60 * (gx * (x - 16) / 16 + gy * (y - 16) / 16) +
                         40 * c * std::cos((x + y) / 5.0 + bias) + 8 * u(rng);
        px[p * 1024 + y * 32 + x] = static_cast<uint8_t>(std::clamp(v, 0.0, 255.0));
      }
  }
  return px;
}

ResponseCounts countsOf(const PatchMatrix& patches, const std::vector<ComparisonPair>& tests) {
  ResponseCounts counts;
  counts.patches = patches.count;
  counts.ones = countResponses(patches, tests);
  return counts;
}

}  // namespace

TEST(Candidates, Exactly377650InRangeWithinDistanceLimits) {
  const auto c = candidateComparisons();
  ASSERT_EQ(c.size(), kCandidateCount);
  std::set<std::tuple<int, int, int, int>> seen;
  for (const ComparisonPair& t : c) {
    for (int v : {t.x1, t.y1, t.x2, t.y2}) {
      ASSERT_GE(v, -15);
      ASSERT_LE(v, 14);
    }
    const double d = std::hypot(t.x2 - t.x1, t.y2 - t.y1);
    ASSERT_GT(d, 3.0);
    ASSERT_LT(d, 29.0);
    ASSERT_TRUE(seen.insert({t.x1, t.y1, t.x2, t.y2}).second);
    ASSERT_FALSE(seen.count({t.x2, t.y2, t.x1, t.y1}));
  }
}

TEST(Responses, MatchAScalarEvaluationIncludingPadding) {
  const size_t P = 137;  // not a multiple of 64: the last word has padding
  const auto px = randomPatches(P, 7);
  const auto all = candidateComparisons();
  std::vector<ComparisonPair> tests(all.begin(), all.begin() + 500);
  tests.push_back({-16, -16, 15, 15});  // extreme offsets
  const ComparisonResponses r = evaluateComparisons({px.data(), P}, tests);
  ASSERT_EQ(r.words(), 3u);
  for (size_t d = 0; d < tests.size(); ++d) {
    const ComparisonPair& t = tests[d];
    size_t ones = 0;
    for (size_t p = 0; p < P; ++p) {
      const uint8_t a = px[p * 1024 + (t.y1 + 16) * 32 + t.x1 + 16];
      const uint8_t b = px[p * 1024 + (t.y2 + 16) * 32 + t.x2 + 16];
      const bool bit = (r.column(d)[p / 64] >> (p % 64)) & 1;
      ASSERT_EQ(bit, a < b) << d << " " << p;
      ones += a < b;
    }
    EXPECT_EQ(r.ones(d), ones);
    EXPECT_EQ(r.column(d)[2] >> (P - 128), 0u) << "padding bits must stay 0";
  }
  EXPECT_THROW(evaluateComparisons({px.data(), 0}, tests), std::invalid_argument);
  EXPECT_THROW(evaluateComparisons({px.data(), P}, {{0, 0, 16, 0}}), std::invalid_argument);
  EXPECT_THROW(countResponses({px.data(), P}, {{0, 0, 16, 0}}), std::invalid_argument);

  // The streamed counts and the columns recomputed from kept lanes agree with the columns,
  // whatever the chunk size (1 word: every chunk boundary, 2: a partial last chunk).
  for (size_t chunkWords : {1, 2, 8}) {
    StreamingOptions streaming;
    streaming.chunkWords = chunkWords;
    const std::vector<uint32_t> ones = countResponses({px.data(), P}, tests, {}, streaming);
    const PatchLanes lanes(PatchRows::of({px.data(), P}), chunkWords);
    const std::vector<PixelPair> pixels = pixelPairsOf(tests);
    std::vector<uint64_t> columns(tests.size() * lanes.words());
    evaluateColumns(lanes, pixels.data(), tests.size(), columns.data());
    for (size_t d = 0; d < tests.size(); ++d) {
      ASSERT_EQ(ones[d], r.ones(d)) << chunkWords << " " << d;
      for (size_t w = 0; w < r.words(); ++w) ASSERT_EQ(columns[d * r.words() + w], r.column(d)[w]) << chunkWords;
    }
  }
}

TEST(Greedy, SortIsByVarianceThenIndex) {
  const size_t P = 300;
  const auto px = structuredPatches(P, 3);
  const auto all = candidateComparisons();
  const std::vector<ComparisonPair> tests(all.begin(), all.begin() + 3000);
  const ComparisonResponses r = evaluateComparisons({px.data(), P}, tests);
  const auto order = sortByVariance(countsOf({px.data(), P}, tests));
  ASSERT_EQ(order.size(), tests.size());
  for (size_t i = 1; i < order.size(); ++i) {
    const double a = r.ones(order[i - 1]) * double(P - r.ones(order[i - 1]));
    const double b = r.ones(order[i]) * double(P - r.ones(order[i]));
    ASSERT_GE(a, b);
    if (a == b) {
      ASSERT_LT(order[i - 1], order[i]);
    }
  }
}

TEST(Greedy, KeptTestsAreBelowTheFinalThresholdAndMatchASequentialWalk) {
  const size_t P = 256;
  const auto px = structuredPatches(P, 11);
  const auto all = candidateComparisons();
  std::vector<ComparisonPair> tests;
  for (size_t i = 0; i < all.size(); i += 97) tests.push_back(all[i]);
  const ComparisonResponses r = evaluateComparisons({px.data(), P}, tests);
  const auto order = sortByVariance(countsOf({px.data(), P}, tests));
  GreedyOptions opt;
  opt.tests = 128;
  const PatchLanes lanes(PatchRows::of({px.data(), P}), StreamingOptions{}.chunkWords);
  const GreedyResult g = selectUncorrelated(lanes, tests, order, opt);
  ASSERT_EQ(g.kept.size(), 128u);
  EXPECT_GE(g.passes, 1);
  EXPECT_NEAR(g.finalThreshold, 0.2 + 0.1 * (g.passes - 1), 1e-9);
  for (size_t i = 0; i < g.kept.size(); ++i)
    for (size_t j = i + 1; j < g.kept.size(); ++j)
      ASSERT_LT(correlation(r, g.kept[i], g.kept[j]), g.finalThreshold + 1e-12);
  EXPECT_EQ(g.kept.front(), order.front()) << "the highest-variance test is always kept";

  // The plain sequential algorithm of the paper gives the same list.
  std::vector<size_t> kept;
  std::vector<char> taken(r.tests(), 0);
  for (int pass = 0; kept.size() < opt.tests; ++pass) {
    const double tc = 0.2 + 0.1 * pass;
    for (size_t d : order) {
      if (kept.size() == opt.tests) break;
      if (taken[d]) continue;
      bool ok = true;
      for (size_t k : kept) ok = ok && correlation(r, d, k) < tc - 1e-12;
      if (ok) {
        kept.push_back(d);
        taken[d] = 1;
      }
    }
  }
  EXPECT_EQ(kept, g.kept);

  // Screening batches of 5 candidates and 1-word chunks decide the same.
  StreamingOptions tiny;
  tiny.chunkWords = 1;
  tiny.candidateBatch = 5;
  EXPECT_EQ(selectUncorrelated(PatchLanes(PatchRows::of({px.data(), P}), 1), tests, order, opt, {}, tiny).kept, kept);
}

TEST(Greedy, TooFewCandidatesThrow) {
  const auto px = randomPatches(64, 1);
  const std::vector<ComparisonPair> tests{{0, 0, 5, 5}, {1, 1, -5, -5}};
  const PatchLanes lanes(PatchRows::of({px.data(), 64}), 8);
  GreedyOptions opt;
  opt.tests = 3;
  EXPECT_THROW(selectUncorrelated(lanes, tests, {0, 1}, opt), std::invalid_argument);
  opt.tests = 1;
  EXPECT_THROW(selectUncorrelated(lanes, tests, {2, 0}, opt), std::invalid_argument);
}

TEST(Trainer, IsDeterministicWithCorrelationsBelowTheFinalThreshold) {
  const size_t P = 200;
  const auto px = structuredPatches(P, 5);
  GreedyOptions opt;
  opt.tests = 64;
  const LearnedComparisons a = learnComparisons({px.data(), P}, opt);
  const LearnedComparisons b = learnComparisons({px.data(), P}, opt);
  ASSERT_EQ(a.tests.size(), 64u);
  EXPECT_EQ(a.candidates, kCandidateCount);
  for (size_t i = 0; i < a.tests.size(); ++i) {
    EXPECT_EQ(a.tests[i].x1, b.tests[i].x1);
    EXPECT_EQ(a.tests[i].y2, b.tests[i].y2);
    EXPECT_LE(a.maxCorrelation[i], a.finalThreshold);
  }
}

// The header's data digest, against values computed apart from the project (Python, FNV-1a 64
// from the project's offset basis 1469598103934665603 with prime 1099511628211, as hex): the
// learned headers in patterns/ record such digests, which must not change.
TEST(Trainer, PatchDigestIsTheRecordedFnv1a) {
  std::vector<uint8_t> px(2 * kPatchSize * kPatchSize);
  for (size_t i = 0; i < px.size(); ++i) px[i] = static_cast<uint8_t>(i % 251);
  EXPECT_EQ(patchDigest({px.data(), 2}), "4926e4824eef064b");
  EXPECT_EQ(patchDigest({px.data(), 0}), "14650fb0739d0383");  // the offset basis itself
  px[1500] ^= 1;
  EXPECT_NE(patchDigest({px.data(), 2}), "4926e4824eef064b");
}

TEST(Pairs, DisagreementCountsAndBitsMatchAScalarEvaluation) {
  const size_t P = 70, Q = 90;
  const auto ref = randomPatches(P, 11), cp = randomPatches(Q, 12);
  std::vector<int32_t> of(Q);
  for (size_t j = 0; j < Q; ++j) of[j] = static_cast<int32_t>(j * P / Q);
  const std::vector<ComparisonPair> tests{{-3, 2, 5, -7}, {0, 0, 1, 1}, {-15, -15, 14, 14}, {4, -2, -9, 8}};
  const Counterparts pairs{{cp.data(), Q}, of.data()};
  StreamingOptions oneWord;
  oneWord.chunkWords = 1;
  const auto flips = countDisagreements({ref.data(), P}, pairs, tests);
  EXPECT_EQ(countDisagreements({ref.data(), P}, pairs, tests, {}, oneWord), flips);
  const PatchLanes references(PatchRows::pairedReferences({ref.data(), P}, pairs), 1);
  const PatchLanes views(PatchRows::of(pairs.patches), 1);
  const std::vector<PixelPair> pixels = pixelPairsOf(tests);
  ComparisonResponses bits(tests.size(), Q);
  evaluateFlipColumns(references, views, pixels.data(), tests.size(), bits.column(0));
  const auto at = [](const std::vector<uint8_t>& px, size_t p, int x, int y) { return px[p * 1024 + (y + 16) * 32 + x + 16]; };
  for (size_t d = 0; d < tests.size(); ++d) {
    const ComparisonPair& t = tests[d];
    uint32_t expected = 0;
    for (size_t j = 0; j < Q; ++j) {
      const bool a = at(ref, of[j], t.x1, t.y1) < at(ref, of[j], t.x2, t.y2);
      const bool b = at(cp, j, t.x1, t.y1) < at(cp, j, t.x2, t.y2);
      expected += a != b;
      EXPECT_EQ((bits.column(d)[j / 64] >> (j % 64)) & 1u, uint64_t(a != b)) << d << " " << j;
    }
    EXPECT_EQ(flips[d], expected) << d;
  }
  const std::vector<int32_t> outOfRange(Q, int32_t(P));
  EXPECT_THROW(countDisagreements({ref.data(), P}, {{cp.data(), Q}, outOfRange.data()}, tests), std::invalid_argument);
}

TEST(Criteria, ParseNamesAndRankByMargin) {
  EXPECT_EQ(parseSelectionCriterion("paper"), SelectionCriterion::Paper);
  EXPECT_EQ(parseSelectionCriterion("separation"), SelectionCriterion::Separation);
  try {
    parseSelectionCriterion("boost");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("is not one of: paper, stability, separation"), std::string::npos);
  }
  // Three tests over 4 patches: 2 alpha (1 - alpha) = 0.5, 0.5, 0.375; flips 3, 0, 0 of 4 pairs.
  ResponseCounts counts;
  counts.patches = 4;
  counts.ones = {2, 2, 1};
  counts.pairs = 4;
  counts.flips = {3, 0, 0};
  const auto order = sortByCriterion(counts, SelectionCriterion::Stability);
  EXPECT_EQ(order, (std::vector<size_t>{1, 2, 0}));  // margins 0.5, 0.375, -0.25
  EXPECT_EQ(sortByCriterion(counts, SelectionCriterion::Paper), sortByVariance(counts));
  counts.pairs = 0;
  counts.flips.clear();
  EXPECT_THROW(sortByCriterion(counts, SelectionCriterion::Stability), std::invalid_argument);
}

TEST(Criteria, StabilityAndSeparationPreferTestsThatSurviveTheViewChange) {
  // Counterparts: the same structured patches with noise added only to the right half, so tests
  // on the left half are the stable ones.
  const size_t P = 512;
  const auto px = structuredPatches(P, 9);
  auto cp = px;
  std::mt19937 rng(3);
  for (size_t p = 0; p < P; ++p)
    for (int y = 0; y < 32; ++y)
      for (int x = 16; x < 32; ++x) {
        uint8_t& v = cp[p * 1024 + y * 32 + x];
        v = static_cast<uint8_t>(std::clamp(int(v) + int(rng() % 81) - 40, 0, 255));
      }
  std::vector<int32_t> of(P);
  for (size_t p = 0; p < P; ++p) of[p] = static_cast<int32_t>(p);
  GreedyOptions opt;
  opt.tests = 64;
  int paperLeftHalf = 0;
  for (auto c : {SelectionCriterion::Paper, SelectionCriterion::Stability, SelectionCriterion::Separation}) {
    const LearnedComparisons a = learnComparisons({px.data(), P}, opt, c, {{cp.data(), P}, of.data()});
    const LearnedComparisons b = learnComparisons({px.data(), P}, opt, c, {{cp.data(), P}, of.data()});
    ASSERT_EQ(a.tests.size(), 64u);
    double flip = 0;
    int leftHalf = 0;
    for (size_t i = 0; i < a.tests.size(); ++i) {
      EXPECT_EQ(a.tests[i].x1, b.tests[i].x1);
      EXPECT_EQ(a.tests[i].y2, b.tests[i].y2);
      flip += a.flipRate[i] / a.tests.size();
      leftHalf += a.tests[i].x1 < 0 && a.tests[i].x2 < 0;
    }
    RecordProperty("flip_" + selectionCriterionName(c), std::to_string(flip));
    RecordProperty("left_half_" + selectionCriterionName(c), leftHalf);
    if (c == SelectionCriterion::Paper) {
      paperLeftHalf = leftHalf;
      EXPECT_LT(leftHalf, 40) << "the paper's criterion cannot see the noise";
    } else {
      EXPECT_GE(leftHalf, paperLeftHalf + 16) << selectionCriterionName(c) << " keeps the stable half";
    }
  }
  EXPECT_THROW(learnComparisons({px.data(), P}, opt, SelectionCriterion::Separation), std::invalid_argument);
}

// The streamed trainer learns what the full-matrix trainer (every candidate's column held,
// separation scoring every pool candidate at every step; main at 5907e2e) learned on the same
// set, to the bit: tests, means, highest correlations and flip rates. 700 patches and 650 pairs
// leave partial last words, the pairs' references are not the patches in order, and 4 of 11
// covariance words make the separation sample the patches. Tiny blocks must not change a bit.
TEST(Trainer, StreamedSelectionEqualsTheFullMatrixTrainersOutput) {
  const size_t P = 700, Q = 650;
  const auto px = structuredPatches(P, 9);
  std::vector<int32_t> of(Q);
  std::vector<uint8_t> cp(Q * 1024);
  std::mt19937 rng(3);
  for (size_t j = 0; j < Q; ++j) {
    of[j] = static_cast<int32_t>(j * P / Q);
    std::memcpy(cp.data() + j * 1024, px.data() + of[j] * 1024, 1024);
    for (int y = 0; y < 32; ++y)
      for (int x = 16; x < 32; ++x) {
        uint8_t& v = cp[j * 1024 + y * 32 + x];
        v = static_cast<uint8_t>(std::clamp(int(v) + int(rng() % 81) - 40, 0, 255));
      }
  }
  GreedyOptions opt;
  opt.tests = 64;
  SeparationOptions separation;
  separation.covarianceWords = 4;
  separation.pool = 20000;
  StreamingOptions tiny;
  tiny.chunkWords = 1;
  tiny.candidateBatch = 7;
  const std::vector<std::pair<SelectionCriterion, uint64_t>> expected{
      {SelectionCriterion::Paper, 0xdc165b07abb986ccull},
      {SelectionCriterion::Stability, 0xe519ff2b3fd4cba6ull},
      {SelectionCriterion::Separation, 0x17a78ddfc4ea235eull}};
  for (const auto& [criterion, digest] : expected)
    for (const StreamingOptions& streaming : {StreamingOptions{}, tiny}) {
      const LearnedComparisons t =
          learnComparisons({px.data(), P}, opt, criterion, {{cp.data(), Q}, of.data()}, {}, separation, streaming);
      ASSERT_EQ(t.tests.size(), opt.tests);
      // FNV-1a over each test's offsets and the bytes of its three statistics.
      uint64_t h = 1469598103934665603ull;
      const auto add = [&h](const void* data, size_t n) {
        for (size_t i = 0; i < n; ++i) h = (h ^ static_cast<const uint8_t*>(data)[i]) * 1099511628211ull;
      };
      for (size_t i = 0; i < t.tests.size(); ++i) {
        const int8_t xy[4] = {static_cast<int8_t>(t.tests[i].x1), static_cast<int8_t>(t.tests[i].y1),
                              static_cast<int8_t>(t.tests[i].x2), static_cast<int8_t>(t.tests[i].y2)};
        add(xy, sizeof xy);
        add(&t.mean[i], sizeof(double));
        add(&t.maxCorrelation[i], sizeof(double));
        add(&t.flipRate[i], sizeof(double));
      }
      EXPECT_EQ(h, digest) << selectionCriterionName(criterion) << " with chunks of " << streaming.chunkWords
                           << " words, batches of " << streaming.candidateBatch;
    }
}

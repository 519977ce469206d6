// The trainer's test responses, response counts and disagreement counts are identical at every
// SIMD level (mdbrief/base/simd_level.hpp), so a training run gives the same pattern on every CPU.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "mdbrief/base/simd_level.hpp"
#include "trainer/candidate_comparisons.hpp"
#include "trainer/comparison_response_kernels.hpp"
#include "trainer/comparison_responses.hpp"

namespace {

using mdbrief::SimdLevel;
using namespace mdbrief::train;

TEST(TrainerSimdLevel, ResponsesAndDisagreementsAreIdenticalAtEveryLevel) {
  // 200 patches: three full 64-patch words and a partial one.
  std::mt19937 rng(3);
  std::vector<uint8_t> a(200 * 1024), b(200 * 1024);
  for (size_t i = 0; i < a.size(); ++i) {
    a[i] = static_cast<uint8_t>(rng() % 7 * 40);  // repeated values: equal pixels give 0 bits
    b[i] = static_cast<uint8_t>(rng() % 2 ? a[i] : rng());
  }
  std::vector<int32_t> counterpartOf(200);
  for (size_t i = 0; i < counterpartOf.size(); ++i) counterpartOf[i] = static_cast<int32_t>((i * 7) % 200);
  const std::vector<mdbrief::ComparisonPair> tests = candidateComparisons();
  const std::vector<mdbrief::ComparisonPair> some(tests.begin(), tests.begin() + 5000);

  std::vector<uint64_t> refBits;
  std::vector<size_t> refOnes;
  std::vector<uint32_t> refFlips, refCounts;
  for (const SimdLevel level : mdbrief::supportedSimdLevels()) {
    mdbrief::limitSimdLevel(level);
    const ComparisonResponses r = evaluateComparisons({a.data(), 200}, some);
    const kernels::ResponseKernels k = kernels::activeResponseKernels();
    std::vector<uint64_t> bits;
    std::vector<size_t> ones;  // counts of ones, differences and coincidences of the columns
    for (size_t d = 0; d < r.tests(); ++d) {
      bits.insert(bits.end(), r.column(d), r.column(d) + r.words());
      const size_t next = (d + 1) % r.tests();
      ones.push_back(r.ones(d) + 1000 * r.differences(d, next) +
                     1000000 * k.popcountAnd(r.column(d), r.column(next), r.words()));
    }
    const std::vector<uint32_t> flips = countDisagreements({a.data(), 200}, {{b.data(), 200}, counterpartOf.data()}, some);
    const std::vector<uint32_t> counts = countResponses({a.data(), 200}, some);
    if (level == SimdLevel::Portable) {
      refBits = bits, refOnes = ones, refFlips = flips, refCounts = counts;
      continue;
    }
    EXPECT_EQ(bits, refBits) << mdbrief::toString(level);
    EXPECT_EQ(ones, refOnes) << mdbrief::toString(level);
    EXPECT_EQ(flips, refFlips) << mdbrief::toString(level);
    EXPECT_EQ(counts, refCounts) << mdbrief::toString(level);
  }
  mdbrief::limitSimdLevel(SimdLevel::Avx512);
  ASSERT_FALSE(refBits.empty());
}

}  // namespace

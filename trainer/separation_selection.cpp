#include "trainer/separation_selection.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "trainer/comparison_response_kernels.hpp"

namespace mdbrief::train {

namespace {

// Slack per missed covariance term in the upper bound, far above the rounding of sums of at
// most a few thousand terms below 1 (about 1e-12): it can only make a few more candidates be
// scored exactly, never change the choice.
constexpr double kBoundSlack = 1e-9;

// The covariance sample: whole 64-patch words, evenly spread (so the rows of one image stay
// together and every image contributes).
std::vector<size_t> sampleWords(size_t words, size_t maxWords) {
  const size_t n = std::min(maxWords, words);
  std::vector<size_t> chosen(n);
  for (size_t k = 0; k < n; ++k) chosen[k] = k * words / n;
  return chosen;
}

// The pool's sample columns, recomputed a group at a time: on the patch sample (responses) and
// on the pair sample (flips), each candidate's words contiguous.
class SampleColumns {
 public:
  SampleColumns(const PatchMatrix& patches, const Counterparts& counterparts, size_t maxWords, size_t chunkWords)
      : SampleColumns(PatchRows::of(patches), PatchRows::pairedReferences(patches, counterparts),
                      PatchRows::of(counterparts.patches), maxWords, chunkWords) {}

  size_t patchWords() const { return patches_.words(); }
  size_t pairWords() const { return views_.words(); }
  double patchRows() const { return static_cast<double>(patches_.rows()); }
  double pairRows() const { return static_cast<double>(views_.rows()); }

  // Columns of tests[0, count) into responses (count x patchWords()) and flips (count x pairWords()).
  void compute(const PixelPair* tests, size_t count, uint64_t* responses, uint64_t* flips) const {
    evaluateColumns(patches_, tests, count, responses);
    if (references_) {
      evaluateFlipColumns(*references_, views_, tests, count, flips);
      return;
    }
    evaluateColumns(views_, tests, count, flips);
    const size_t words = views_.words();
    tbb::parallel_for(size_t(0), count, [&](size_t n) {
      for (size_t w = n * words; w < (n + 1) * words; ++w) flips[w] ^= responses[w];
    });
  }

 private:
  SampleColumns(const PatchRows& patches, const PatchRows& references, const PatchRows& views, size_t maxWords,
                size_t chunkWords)
      : SampleColumns(patches.words(sampleWords(patches.wordCount(), maxWords)),
                      references.words(sampleWords(views.wordCount(), maxWords)),
                      views.words(sampleWords(views.wordCount(), maxWords)), chunkWords) {}
  // With one counterpart per patch, in order, the pairs' references are the patch sample itself.
  SampleColumns(const PatchRows& patches, const PatchRows& references, const PatchRows& views, size_t chunkWords)
      : patches_(patches, chunkWords),
        references_(references == patches ? nullptr : std::make_unique<PatchLanes>(references, chunkWords)),
        views_(views, chunkWords) {}

  PatchLanes patches_;
  std::unique_ptr<PatchLanes> references_;  // null: the patch sample
  PatchLanes views_;
};

}  // namespace

SeparationResult selectBySeparation(const PatchMatrix& patches, const Counterparts& counterparts,
                                    const std::vector<ComparisonPair>& candidates, const ResponseCounts& counts,
                                    const std::vector<size_t>& order, const SeparationOptions& options,
                                    const std::function<void(size_t)>& progress,
                                    const StreamingOptions& streaming) {
  const size_t pool = std::min(options.pool, order.size());
  if (pool < options.tests || options.tests == 0)
    throw std::invalid_argument("separation selection: " + std::to_string(options.tests) +
                                " tests requested from a pool of " + std::to_string(pool));
  if (!(options.nonMatchingSigmas >= 0) || !(options.matchingSigmas >= 0) || options.covarianceWords == 0)
    throw std::invalid_argument("separation selection: the sigma weights must be >= 0 and covarianceWords > 0");
  if (streaming.candidateBatch == 0) throw std::invalid_argument("separation selection: candidateBatch must be positive");
  if (counts.patches != patches.count || counts.ones.size() != candidates.size())
    throw std::invalid_argument("separation selection: the response counts do not match the patches and candidates");
  if (counts.pairs == 0 || counts.pairs != counterparts.patches.count || counts.flips.size() != candidates.size())
    throw std::invalid_argument("separation selection: the flip counts of the matching pairs are missing");
  const double p = static_cast<double>(counts.patches), q = static_cast<double>(counts.pairs);

  // Per pool candidate: v = 2 alpha (1 - alpha), f, its test, and on the sample: alpha (sa) and
  // the flip rate (sf).
  std::vector<double> v(pool), f(pool), sa(pool), sf(pool);
  std::vector<ComparisonPair> poolTests(pool);
  for (size_t i = 0; i < pool; ++i) {
    if (order[i] >= candidates.size())
      throw std::invalid_argument("separation selection: candidate " + std::to_string(order[i]) + " does not exist");
    const double alpha = counts.ones[order[i]] / p;
    v[i] = 2 * alpha * (1 - alpha);
    f[i] = counts.flips[order[i]] / q;
    poolTests[i] = candidates[order[i]];
  }
  const std::vector<PixelPair> pixels = pixelPairsOf(poolTests);
  const SampleColumns sample(patches, counterparts, options.covarianceWords, streaming.chunkWords);
  const size_t wn = sample.patchWords(), wm = sample.pairWords(), batch = streaming.candidateBatch;
  const double rowsN = sample.patchRows(), rowsM = sample.pairRows();
  const kernels::ResponseKernels kernel = kernels::activeResponseKernels();

  // A group of candidates' sample columns.
  std::vector<PixelPair> groupPixels(batch);
  std::vector<uint64_t> groupN(batch * wn), groupM(batch * wm);
  const auto recompute = [&](const size_t* group, size_t n) {
    for (size_t z = 0; z < n; ++z) groupPixels[z] = pixels[group[z]];
    sample.compute(groupPixels.data(), n, groupN.data(), groupM.data());
  };
  for (size_t i0 = 0; i0 < pool; i0 += batch) {
    std::vector<size_t> group(std::min(batch, pool - i0));
    std::iota(group.begin(), group.end(), i0);
    recompute(group.data(), group.size());
    tbb::parallel_for(size_t(0), group.size(), [&](size_t z) {
      sa[i0 + z] = kernel.popcount(groupN.data() + z * wn, wn) / rowsN;
      sf[i0 + z] = kernel.popcount(groupM.data() + z * wm, wm) / rowsM;
    });
  }

  // Covariance sums with the kept tests [0, updatedTo[i]), and the kept tests' sample columns.
  std::vector<double> sumN(pool, 0.0), sumM(pool, 0.0);
  std::vector<uint32_t> updatedTo(pool, 0);
  std::vector<uint64_t> keptN, keptM;
  keptN.reserve(options.tests * wn);
  keptM.reserve(options.tests * wm);
  std::vector<size_t> keptPool;  // pool indices of the kept tests
  // Prefix sums over the kept tests of (2 sa - 1)^2 and of sf: the bounds of the missed terms.
  std::vector<double> missedN{0.0}, missedM{0.0};
  std::vector<size_t> remaining(pool);  // pool indices not kept, ascending
  std::iota(remaining.begin(), remaining.end(), size_t(0));
  std::vector<std::pair<double, size_t>> bounds(pool);
  std::vector<double> exact(batch);
  double muN = 0, muM = 0, varN = 0, varM = 0;
  const auto score = [&](size_t i, double sN, double sM) {
    const double vn = varN + v[i] * (1 - v[i]) + 2 * sN, vm = varM + f[i] * (1 - f[i]) + 2 * sM;
    return (muN + v[i] - muM - f[i]) - options.nonMatchingSigmas * std::sqrt(std::max(vn, 0.0)) -
           options.matchingSigmas * std::sqrt(std::max(vm, 0.0));
  };
  // Best bound first, ties to the earlier candidate.
  const auto higher = [](const std::pair<double, size_t>& a, const std::pair<double, size_t>& b) {
    return a.first != b.first ? a.first > b.first : a.second < b.second;
  };

  SeparationResult result;
  while (result.kept.size() < options.tests) {
    const size_t t = result.kept.size();
    tbb::parallel_for(size_t(0), remaining.size(), [&](size_t z) {
      const size_t i = remaining[z], s = updatedTo[i];
      if (s == t) {
        bounds[z] = {score(i, sumN[i], sumM[i]), i};
        return;
      }
      const double di = 2 * sa[i] - 1, slack = kBoundSlack * static_cast<double>(t - s);
      bounds[z] = {score(i, sumN[i] - (di * di / 4 * (missedN[t] - missedN[s]) + slack),
                         sumM[i] - (sf[i] * (missedM[t] - missedM[s]) + slack)),
                   i};
    });
    // Score exactly, best bound first and a group at a time, every candidate whose bound
    // reaches the best exact score found so far.
    std::vector<std::pair<double, size_t>> open(bounds.begin(), bounds.begin() + remaining.size());
    size_t best = pool;
    double bestJ = -1e300;
    std::vector<size_t> group, stale;
    while (!open.empty()) {
      const size_t n = std::min(batch, open.size());
      if (n < open.size()) std::nth_element(open.begin(), open.begin() + (n - 1), open.end(), higher);
      group.clear();
      stale.clear();
      for (size_t z = 0; z < n; ++z) {
        group.push_back(open[z].second);
        if (updatedTo[open[z].second] < t) stale.push_back(open[z].second);
      }
      open.erase(open.begin(), open.begin() + n);
      // Candidates sharing a pixel next to each other: its rows stay in the L1 cache.
      std::sort(stale.begin(), stale.end(), [&](size_t a, size_t b) {
        return pixels[a].a != pixels[b].a ? pixels[a].a < pixels[b].a : pixels[a].b < pixels[b].b;
      });
      recompute(stale.data(), stale.size());
      tbb::parallel_for(tbb::blocked_range<size_t>(0, stale.size()), [&](const tbb::blocked_range<size_t>& r) {
        std::vector<size_t> bothN, bothM;
        for (size_t z = r.begin(); z != r.end(); ++z) {
          const size_t i = stale[z], s0 = updatedTo[i];
          bothN.resize(t - s0);
          bothM.resize(t - s0);
          for (size_t s = s0; s < t; ++s) {
            bothN[s - s0] = kernel.popcountAnd(groupN.data() + z * wn, keptN.data() + s * wn, wn);
            bothM[s - s0] = kernel.popcountAnd(groupM.data() + z * wm, keptM.data() + s * wm, wm);
          }
          // The full scan's terms, added in the order the tests were kept.
          double sN = sumN[i], sM = sumM[i];
          for (size_t s = s0; s < t; ++s) {
            const size_t k = keptPool[s];
            const double ai = sa[i], ak = sa[k], p11 = bothN[s - s0] / rowsN;
            const double p10 = ai - p11, p01 = ak - p11, p00 = 1 - ai - ak + p11;
            sN += 2 * (p00 * p11 + p01 * p10) - 4 * ai * (1 - ai) * ak * (1 - ak);
            sM += bothM[s - s0] / rowsM - sf[i] * sf[k];
          }
          sumN[i] = sN;
          sumM[i] = sM;
          updatedTo[i] = static_cast<uint32_t>(t);
        }
      });
      for (size_t i : group) {
        const double j = score(i, sumN[i], sumM[i]);
        if (j > bestJ || (j == bestJ && i < best)) bestJ = j, best = i;
      }
      open.erase(std::remove_if(open.begin(), open.end(), [&](const auto& b) { return b.first < bestJ; }),
                 open.end());
    }
    const size_t k = best;
    remaining.erase(std::lower_bound(remaining.begin(), remaining.end(), k));
    muN += v[k];
    muM += f[k];
    varN += v[k] * (1 - v[k]) + 2 * sumN[k];
    varM += f[k] * (1 - f[k]) + 2 * sumM[k];
    recompute(&k, 1);
    keptN.insert(keptN.end(), groupN.begin(), groupN.begin() + wn);
    keptM.insert(keptM.end(), groupM.begin(), groupM.begin() + wm);
    keptPool.push_back(k);
    missedN.push_back(missedN.back() + (2 * sa[k] - 1) * (2 * sa[k] - 1));
    missedM.push_back(missedM.back() + sf[k]);
    result.kept.push_back(order[k]);
    result.separation.push_back(bestJ);
    if (progress) progress(result.kept.size());
  }
  return result;
}

}  // namespace mdbrief::train

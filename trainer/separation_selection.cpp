#include "trainer/separation_selection.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include <tbb/parallel_for.h>

#include "trainer/test_response_kernels.hpp"

namespace mdbrief::train {

namespace {

// Columns of the pool on an evenly spread subset of whole words (64 patches each, so the rows
// of one image stay together and every image contributes), contiguous per candidate.
struct Sample {
  std::vector<uint64_t> bits;  // pool x words
  size_t words = 0;
  double rows = 0;             // patches (or pairs) in the chosen words
  std::vector<double> alpha;   // per candidate: fraction of ones in the sample
  kernels::ResponseKernels kernel = kernels::activeResponseKernels();

  Sample(const TestResponses& m, const std::vector<size_t>& columns, size_t maxWords) {
    words = std::min(maxWords, m.words());
    std::vector<size_t> chosen(words);
    for (size_t k = 0; k < words; ++k) {
      chosen[k] = k * m.words() / words;
      rows += static_cast<double>(std::min<size_t>(64, m.patches() - 64 * chosen[k]));
    }
    bits.resize(columns.size() * words);
    alpha.resize(columns.size());
    tbb::parallel_for(size_t(0), columns.size(), [&](size_t i) {
      const uint64_t* c = m.column(columns[i]);
      for (size_t w = 0; w < words; ++w) bits[i * words + w] = c[chosen[w]];
      alpha[i] = kernel.popcount(bits.data() + i * words, words) / rows;
    });
  }
  const uint64_t* column(size_t i) const { return bits.data() + i * words; }
  double both(size_t i, size_t j) const { return kernel.popcountAnd(column(i), column(j), words) / rows; }
};

}  // namespace

SeparationResult selectBySeparation(const TestResponses& responses, const std::vector<size_t>& order,
                                    const TestResponses& poolFlips, const SeparationOptions& options,
                                    const std::function<void(size_t)>& progress) {
  const size_t pool = std::min(options.pool, order.size());
  if (pool < options.tests || options.tests == 0)
    throw std::invalid_argument("separation selection: " + std::to_string(options.tests) +
                                " tests requested from a pool of " + std::to_string(pool));
  if (!(options.nonMatchingSigmas >= 0) || !(options.matchingSigmas >= 0) || options.covarianceWords == 0)
    throw std::invalid_argument("separation selection: the sigma weights must be >= 0 and covarianceWords > 0");
  if (poolFlips.tests() < pool || poolFlips.patches() == 0)
    throw std::invalid_argument("separation selection: the flip bits of the pool are missing");
  const double p = static_cast<double>(responses.patches()), q = static_cast<double>(poolFlips.patches());

  // Per pool candidate: alpha, v = 2 alpha (1 - alpha), f, and the covariance sums with the kept.
  std::vector<double> alpha(pool), v(pool), f(pool), sumN(pool, 0.0), sumM(pool, 0.0);
  for (size_t i = 0; i < pool; ++i) {
    alpha[i] = responses.ones(order[i]) / p;
    v[i] = 2 * alpha[i] * (1 - alpha[i]);
    f[i] = poolFlips.ones(i) / q;
  }
  std::vector<size_t> poolColumns(order.begin(), order.begin() + pool), identity(pool);
  for (size_t i = 0; i < pool; ++i) identity[i] = i;
  const Sample ref(responses, poolColumns, options.covarianceWords);
  const Sample flip(poolFlips, identity, options.covarianceWords);
  std::vector<char> taken(pool, 0);
  SeparationResult result;
  double muN = 0, muM = 0, varN = 0, varM = 0;
  while (result.kept.size() < options.tests) {
    size_t best = pool;
    double bestJ = -1e300;
    for (size_t i = 0; i < pool; ++i) {
      if (taken[i]) continue;
      const double vn = varN + v[i] * (1 - v[i]) + 2 * sumN[i], vm = varM + f[i] * (1 - f[i]) + 2 * sumM[i];
      const double j = (muN + v[i] - muM - f[i]) - options.nonMatchingSigmas * std::sqrt(std::max(vn, 0.0)) -
                       options.matchingSigmas * std::sqrt(std::max(vm, 0.0));
      if (j > bestJ) bestJ = j, best = i;
    }
    const size_t k = best;
    taken[k] = 1;
    muN += v[k];
    muM += f[k];
    varN += v[k] * (1 - v[k]) + 2 * sumN[k];
    varM += f[k] * (1 - f[k]) + 2 * sumM[k];
    result.kept.push_back(order[k]);
    result.separation.push_back(bestJ);
    // The new test's covariance with every remaining candidate, on both distributions.
    tbb::parallel_for(size_t(0), pool, [&](size_t i) {
      if (taken[i]) return;
      const double ai = ref.alpha[i], ak = ref.alpha[k], p11 = ref.both(i, k);
      const double p10 = ai - p11, p01 = ak - p11, p00 = 1 - ai - ak + p11;
      sumN[i] += 2 * (p00 * p11 + p01 * p10) - 4 * ai * (1 - ai) * ak * (1 - ak);
      sumM[i] += flip.both(i, k) - flip.alpha[i] * flip.alpha[k];
    });
    if (progress) progress(result.kept.size());
  }
  return result;
}

}  // namespace mdbrief::train

#include "mdbrief/match/matcher.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "match/match_inputs.hpp"
#include "match/matcher_kernels.hpp"
#include "mdbrief/match/hamming.hpp"
#include "mdbrief/match/masked_hamming.hpp"
#include "match/query_row.hpp"

namespace mdbrief {

namespace {

using namespace matcher_kernels;

// The train side packed once per call (contiguous 32-bit words, effective masks, weights) in
// the layout of the kernel (matcher_kernels.hpp).
struct TrainSet {
  std::vector<uint32_t> desc, mask, weight;  // mask/weight only when masked
  TrainView view;
};

TrainSet pack(const cv::Mat& desc, const cv::Mat* masks, int lanes) {
  TrainSet t;
  const int count = desc.rows, nwords = desc.cols / 4;
  const size_t padded = static_cast<size_t>((count + lanes - 1) / lanes) * lanes;
  // Word k of descriptor j.
  auto slot = [&](int j, int k) {
    return (static_cast<size_t>(j / lanes) * nwords + k) * lanes + j % lanes;
  };
  t.desc.assign(padded * nwords, 0);
  if (masks) {
    t.mask.assign(padded * nwords, 0);
    t.weight.assign(padded, 0);
  }
  uint32_t l[kMaxWords];
  for (int j = 0; j < count; ++j) {
    const uint8_t* p = desc.ptr<uint8_t>(j);
    for (int k = 0; k < nwords; ++k) t.desc[slot(j, k)] = rowWord(p, k);
    if (masks) {
      t.weight[j] = effectiveMaskWords(masks->ptr<uint8_t>(j), nwords, l);
      for (int k = 0; k < nwords; ++k) t.mask[slot(j, k)] = l[k];
    }
  }
  t.view = {t.desc.data(), masks ? t.mask.data() : nullptr, masks ? t.weight.data() : nullptr,
            count, nwords, lanes};
  return t;
}

// For every row of `rows`, its two nearest in `set`.
std::vector<Nearest> nearestAll(const cv::Mat& rows, const cv::Mat* rowMasks, const TrainSet& set,
                                const MatcherKernels& kernel, bool parallel) {
  std::vector<Nearest> out(rows.rows);
  const int nwords = rows.cols / 4;
  auto run = [&](int begin, int end) {
    for (int i = begin; i < end; ++i) out[i] = kernel.nearestTwo(loadQueryRow(rows, rowMasks, i, nwords), set.view);
  };
  if (parallel) {
    // Each query is computed by exactly one task, so the split does not affect the results.
    tbb::parallel_for(tbb::blocked_range<int>(0, rows.rows, 16),
                      [&](const tbb::blocked_range<int>& r) { run(r.begin(), r.end()); });
  } else {
    run(0, rows.rows);
  }
  return out;
}

std::vector<cv::DMatch> match(const cv::Mat& query, const cv::Mat* queryMasks,
                              const cv::Mat& train, const cv::Mat* trainMasks,
                              const MatchOptions& options) {
  validate(options);
  checkDescriptorPair(query, train);
  if (queryMasks) checkMasks(*queryMasks, query, "queryMasks", "query");
  if (trainMasks) checkMasks(*trainMasks, train, "trainMasks", "train");
  if (query.empty() || train.empty()) return {};

  const MatcherKernels kernel = activeMatcherKernels();  // resolved once per call
  const std::vector<Nearest> forward =
      nearestAll(query, queryMasks, pack(train, trainMasks, kernel.lanes), kernel, options.parallel);
  std::vector<Nearest> backward;
  if (options.crossCheck) {
    backward = nearestAll(train, trainMasks, pack(query, queryMasks, kernel.lanes), kernel, options.parallel);
  }

  const bool masked = queryMasks != nullptr;
  std::vector<cv::DMatch> matches;
  matches.reserve(forward.size());
  for (int i = 0; i < query.rows; ++i) {
    const Nearest& n = forward[i];
    const float distance = masked ? maskedFixedToBits(n.best) : static_cast<float>(n.best);
    // Ratio on the exact integers (their scale cancels); kNone = no second neighbour: passes.
    if (options.ratio && n.second != kNone &&
        !(static_cast<double>(n.best) < static_cast<double>(*options.ratio) * n.second)) {
      continue;
    }
    if (options.maxDistance && !(distance <= *options.maxDistance)) continue;
    if (options.crossCheck && backward[n.index].index != i) continue;
    matches.emplace_back(i, n.index, 0, distance);
  }
  return matches;
}

}  // namespace

std::vector<cv::DMatch> matchBruteForce(cv::InputArray query, cv::InputArray train, const MatchOptions& options) {
  return match(query.getMat(), nullptr, train.getMat(), nullptr, options);
}

std::vector<cv::DMatch> matchBruteForceMasked(cv::InputArray query, cv::InputArray queryMasks, cv::InputArray train,
                                              cv::InputArray trainMasks, const MatchOptions& options) {
  const cv::Mat queryMaskRows = queryMasks.getMat(), trainMaskRows = trainMasks.getMat();
  return match(query.getMat(), &queryMaskRows, train.getMat(), &trainMaskRows, options);
}

}  // namespace mdbrief

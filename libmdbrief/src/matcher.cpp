#include "mdbrief/matcher.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#if defined(__AVX512F__) && defined(__AVX512VPOPCNTDQ__)
#define MDBRIEF_MATCH_AVX512 1
#include <immintrin.h>
#endif

#include "mdbrief/hamming.hpp"
#include "mdbrief/masked_hamming.hpp"

namespace mdbrief {

void validate(const MatchOptions& options) {
  if (options.ratio && !(*options.ratio > 0.f && *options.ratio <= 1.f)) {
    throw std::invalid_argument("MatchOptions::ratio must be in (0, 1], got " +
                                std::to_string(*options.ratio));
  }
  if (options.maxDistance && !(*options.maxDistance >= 0.f)) {
    throw std::invalid_argument("MatchOptions::maxDistance must be >= 0, got " +
                                std::to_string(*options.maxDistance));
  }
}

namespace {

constexpr int kLanes = 16;  // train descriptors compared per step (one 512-bit register)
constexpr int kMaxWords = kMaxDescriptorBytes / 4;
constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();  // above any distance

// The two nearest train descriptors of one query; distances are plain Hamming or the masked
// fixed-point form (masked_hamming.hpp), both exact integers.
struct Nearest {
  uint32_t best = kNone;
  uint32_t second = kNone;
  int index = -1;
};

// Reads 32-bit word k of a row (rows need not be aligned).
inline uint32_t word(const uint8_t* row, int k) {
  uint32_t w;
  std::memcpy(&w, row + 4 * k, 4);
  return w;
}

// Effective mask words of one row (an all-zero mask acts as all ones) and its weight w(o).
uint32_t maskWords(const uint8_t* mask, int nwords, uint32_t* out) {
  int ones = 0;
  for (int k = 0; k < nwords; ++k) {
    out[k] = word(mask, k);
    ones += popcount64(out[k]);
  }
  if (ones == 0) std::fill(out, out + nwords, ~uint32_t{0});
  return maskWeight(ones, nwords * 32);
}

// One query row with its effective mask and weight, ready for the kernels.
struct QueryRow {
  uint32_t d[kMaxWords];
  uint32_t l[kMaxWords];
  uint32_t w = 0;
};

QueryRow loadRow(const cv::Mat& desc, const cv::Mat* masks, int row, int nwords) {
  QueryRow q;
  const uint8_t* p = desc.ptr<uint8_t>(row);
  for (int k = 0; k < nwords; ++k) q.d[k] = word(p, k);
  if (masks) q.w = maskWords(masks->ptr<uint8_t>(row), nwords, q.l);
  return q;
}

// The train side packed once per call (contiguous 32-bit words, effective masks, weights) in
// the layout of the compiled kernel; slot() gives the index of word k of descriptor j.
// AVX-512: one load gives word k of 16 consecutive descriptors, element (block b, word k,
// lane l) at [(b * nwords + k) * kLanes + l]; padding lanes of the last block hold zeros and
// are excluded by `count`. Portable: row-major, so a row is read as 64-bit words.
struct TrainSet {
  int count = 0;
  int nwords = 0;
  int blocks = 0;
  std::vector<uint32_t> desc, mask, weight;  // mask/weight only when masked

  size_t slot(int j, int k) const {
#ifdef MDBRIEF_MATCH_AVX512
    return (static_cast<size_t>(j / kLanes) * nwords + k) * kLanes + j % kLanes;
#else
    return static_cast<size_t>(j) * nwords + k;
#endif
  }
};

TrainSet pack(const cv::Mat& desc, const cv::Mat* masks) {
  TrainSet t;
  t.count = desc.rows;
  t.nwords = desc.cols / 4;
  t.blocks = (t.count + kLanes - 1) / kLanes;
  const size_t padded = static_cast<size_t>(t.blocks) * kLanes;
  t.desc.assign(padded * t.nwords, 0);
  if (masks) {
    t.mask.assign(padded * t.nwords, 0);
    t.weight.assign(padded, 0);
  }
  uint32_t l[kMaxWords];
  for (int j = 0; j < t.count; ++j) {
    const uint8_t* p = desc.ptr<uint8_t>(j);
    for (int k = 0; k < t.nwords; ++k) t.desc[t.slot(j, k)] = word(p, k);
    if (masks) {
      t.weight[j] = maskWords(masks->ptr<uint8_t>(j), t.nwords, l);
      for (int k = 0; k < t.nwords; ++k) t.mask[t.slot(j, k)] = l[k];
    }
  }
  return t;
}

#ifdef MDBRIEF_MATCH_AVX512

// Lane l of the kernels sees trains l, l + 16, l + 32, ... in increasing order and keeps its
// own two nearest (strict < keeps the lowest index among ties). Merging the lanes afterwards
// gives the same result as one scan in index order.
Nearest mergeLanes(const uint32_t* best1, const uint32_t* best2, const int32_t* index1) {
  int win = -1;
  for (int l = 0; l < kLanes; ++l) {
    if (index1[l] < 0) continue;
    if (win < 0 || best1[l] < best1[win] || (best1[l] == best1[win] && index1[l] < index1[win])) {
      win = l;
    }
  }
  Nearest r;
  if (win < 0) return r;
  r.best = best1[win];
  r.index = index1[win];
  r.second = best2[win];
  for (int l = 0; l < kLanes; ++l) {
    if (l != win) r.second = std::min(r.second, best1[l]);
  }
  return r;
}

// AVX-512 VPOPCNTDQ: 16 train descriptors per step, query words broadcast, the per-lane two
// nearest kept in registers.
template <bool Masked>
Nearest nearestTwo(const QueryRow& q, const TrainSet& t) {
  const int nwords = t.nwords;
  __m512i best1 = _mm512_set1_epi32(-1);
  __m512i best2 = _mm512_set1_epi32(-1);
  __m512i index1 = _mm512_set1_epi32(-1);
  __m512i lane = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const __m512i step = _mm512_set1_epi32(kLanes);
  const __m512i none = _mm512_set1_epi32(-1);
  const __m512i qw = _mm512_set1_epi32(static_cast<int>(q.w));
  const int tail = t.count - (t.blocks - 1) * kLanes;
  const __mmask16 tailValid = static_cast<__mmask16>((1u << tail) - 1);
  const uint32_t* D = t.desc.data();
  const uint32_t* L = t.mask.data();
  for (int b = 0; b < t.blocks; ++b) {
    __m512i d;
    if constexpr (!Masked) {
      __m512i acc = _mm512_setzero_si512();
      for (int k = 0; k < nwords; ++k) {
        const __m512i x = _mm512_xor_si512(_mm512_loadu_si512(D + k * kLanes),
                                           _mm512_set1_epi32(static_cast<int>(q.d[k])));
        acc = _mm512_add_epi32(acc, _mm512_popcnt_epi32(x));
      }
      d = acc;
    } else {
      __m512i a = _mm512_setzero_si512();
      __m512i c = _mm512_setzero_si512();
      for (int k = 0; k < nwords; ++k) {
        const __m512i x = _mm512_xor_si512(_mm512_loadu_si512(D + k * kLanes),
                                           _mm512_set1_epi32(static_cast<int>(q.d[k])));
        a = _mm512_add_epi32(a, _mm512_popcnt_epi32(
                                    _mm512_and_si512(x, _mm512_set1_epi32(static_cast<int>(q.l[k])))));
        c = _mm512_add_epi32(c, _mm512_popcnt_epi32(
                                    _mm512_and_si512(x, _mm512_loadu_si512(L + k * kLanes))));
      }
      const __m512i tw = _mm512_loadu_si512(t.weight.data() + static_cast<size_t>(b) * kLanes);
      d = _mm512_add_epi32(_mm512_mullo_epi32(a, qw), _mm512_mullo_epi32(c, tw));
      L += nwords * kLanes;
    }
    D += nwords * kLanes;
    if (b == t.blocks - 1) d = _mm512_mask_mov_epi32(none, tailValid, d);
    // Masked moves rather than _mm512_min_epu32, which trips GCC 12's -Wmaybe-uninitialized.
    const __mmask16 closer = _mm512_cmplt_epu32_mask(d, best1);
    const __mmask16 closerThanSecond = _mm512_cmplt_epu32_mask(d, best2);
    best2 = _mm512_mask_mov_epi32(_mm512_mask_mov_epi32(best2, closerThanSecond, d), closer, best1);
    best1 = _mm512_mask_mov_epi32(best1, closer, d);
    index1 = _mm512_mask_mov_epi32(index1, closer, lane);
    lane = _mm512_add_epi32(lane, step);
  }
  alignas(64) uint32_t b1[kLanes], b2[kLanes];
  alignas(64) int32_t i1[kLanes];
  _mm512_store_si512(b1, best1);
  _mm512_store_si512(b2, best2);
  _mm512_store_si512(i1, index1);
  return mergeLanes(b1, b2, i1);
}

#else

// Portable kernel: one train row at a time in index order, 64-bit popcounts plus a 32-bit
// tail word for odd word counts.
template <bool Masked>
Nearest nearestTwo(const QueryRow& q, const TrainSet& t) {
  const int nwords = t.nwords;
  const int nlong = nwords / 2;
  uint64_t qd[kMaxWords / 2], ql[kMaxWords / 2];
  std::memcpy(qd, q.d, sizeof(uint64_t) * nlong);
  if constexpr (Masked) std::memcpy(ql, q.l, sizeof(uint64_t) * nlong);
  auto long_ = [](const uint32_t* p, int k) {
    uint64_t v;
    std::memcpy(&v, p + 2 * k, 8);
    return v;
  };
  Nearest n;
  for (int j = 0; j < t.count; ++j) {
    const uint32_t* row = t.desc.data() + t.slot(j, 0);
    uint32_t d;
    if constexpr (!Masked) {
      d = 0;
      for (int k = 0; k < nlong; ++k) d += popcount64(long_(row, k) ^ qd[k]);
      if (nwords & 1) d += popcount64(row[nwords - 1] ^ q.d[nwords - 1]);
    } else {
      const uint32_t* mask = t.mask.data() + t.slot(j, 0);
      uint32_t a = 0, c = 0;
      for (int k = 0; k < nlong; ++k) {
        const uint64_t x = long_(row, k) ^ qd[k];
        a += popcount64(x & ql[k]);
        c += popcount64(x & long_(mask, k));
      }
      if (nwords & 1) {
        const uint32_t x = row[nwords - 1] ^ q.d[nwords - 1];
        a += popcount64(x & q.l[nwords - 1]);
        c += popcount64(x & mask[nwords - 1]);
      }
      d = a * q.w + c * t.weight[j];
    }
    if (d < n.best) {  // strict: ties keep the lowest index
      n.second = n.best;
      n.best = d;
      n.index = j;
    } else {
      n.second = std::min(n.second, d);
    }
  }
  return n;
}

#endif

// For every row of `rows`, its two nearest in `set`.
std::vector<Nearest> nearestAll(const cv::Mat& rows, const cv::Mat* rowMasks, const TrainSet& set,
                                bool parallel) {
  std::vector<Nearest> out(rows.rows);
  const int nwords = rows.cols / 4;
  auto run = [&](int begin, int end) {
    for (int i = begin; i < end; ++i) {
      const QueryRow q = loadRow(rows, rowMasks, i, nwords);
      out[i] = rowMasks ? nearestTwo<true>(q, set) : nearestTwo<false>(q, set);
    }
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

void checkMasks(const cv::Mat& masks, const cv::Mat& desc, const char* name, const char* descName) {
  if (masks.empty() && desc.empty()) return;  // 0x0 and 0 x bytes both mean "no descriptors"
  if (masks.size() != desc.size()) {
    throw std::invalid_argument(std::string(name) + ": size " + std::to_string(masks.rows) + "x" +
                                std::to_string(masks.cols) + " differs from " + descName + "'s " +
                                std::to_string(desc.rows) + "x" + std::to_string(desc.cols));
  }
  if (!masks.empty() && masks.type() != CV_8UC1) {
    throw std::invalid_argument(std::string(name) + ": masks must be CV_8UC1, got " +
                                cv::typeToString(masks.type()));
  }
}

std::vector<cv::DMatch> match(const cv::Mat& query, const cv::Mat* queryMasks,
                              const cv::Mat& train, const cv::Mat* trainMasks,
                              const MatchOptions& options) {
  validate(options);
  validateDescriptorMatrix(query, "query");
  validateDescriptorMatrix(train, "train");
  if (!query.empty() && !train.empty() && query.cols != train.cols) {
    throw std::invalid_argument("train: width " + std::to_string(train.cols) +
                                " bytes differs from query's " + std::to_string(query.cols));
  }
  if (queryMasks) checkMasks(*queryMasks, query, "queryMasks", "query");
  if (trainMasks) checkMasks(*trainMasks, train, "trainMasks", "train");
  if (query.empty() || train.empty()) return {};

  const std::vector<Nearest> forward =
      nearestAll(query, queryMasks, pack(train, trainMasks), options.parallel);
  std::vector<Nearest> backward;
  if (options.crossCheck) {
    backward = nearestAll(train, trainMasks, pack(query, queryMasks), options.parallel);
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

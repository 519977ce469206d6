#include "vocabulary/kmajority.hpp"

#include <algorithm>
#include <array>
#include <random>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include "mdbrief/match/hamming.hpp"
#include "mdbrief/match/matcher.hpp"

namespace mdbrief::vocab {

namespace {

// Nearest centroid of every member (ties to the lowest centroid), with its distance: the
// library's exhaustive matcher without any test.
std::vector<cv::DMatch> nearest(const cv::Mat& desc, const cv::Mat& masks, const cv::Mat& centroids,
                                const cv::Mat& centroidMasks) {
  MatchOptions o;
  o.ratio.reset();
  o.crossCheck = false;
  return masks.empty() ? matchBruteForce(desc, centroids, o) : matchBruteForceMasked(desc, masks, centroids, centroidMasks, o);
}

// Byte t of spread[v] is bit t of v: eight vote counters side by side in one 64-bit word.
const std::array<uint64_t, 256>& spreadTable() {
  static const std::array<uint64_t, 256> table = [] {
    std::array<uint64_t, 256> t{};
    for (int v = 0; v < 256; ++v)
      for (int b = 0; b < 8; ++b)
        if (v >> b & 1) t[v] |= uint64_t{1} << (8 * b);
    return t;
  }();
  return table;
}

// Per cluster and bit: the members that trust the bit and the trusting members whose bit is 1.
struct Votes {
  int clusters = 0, bits = 0;
  std::vector<int32_t> trusted, ones, members;
  Votes(int k, int nbits) : clusters(k), bits(nbits), trusted(k * nbits, 0), ones(k * nbits, 0), members(k, 0) {}
  void add(const Votes& o) {
    for (size_t i = 0; i < trusted.size(); ++i) {
      trusted[i] += o.trusted[i];
      ones[i] += o.ones[i];
    }
    for (int c = 0; c < clusters; ++c) members[c] += o.members[c];
  }
};

Votes countVotes(const cv::Mat& desc, const cv::Mat& masks, const std::vector<int>& assignment, int k) {
  const int bytes = desc.cols, bits = 8 * bytes;
  const auto& spread = spreadTable();
  return tbb::parallel_reduce(
      tbb::blocked_range<int>(0, desc.rows, 2048), Votes(k, bits),
      [&](const tbb::blocked_range<int>& range, Votes votes) {
        // Byte counters overflow after 255 members: each cluster's are emptied before that.
        std::vector<uint64_t> accTrusted(static_cast<size_t>(k) * bytes, 0), accOnes(accTrusted.size(), 0);
        std::vector<int> pending(k, 0);
        const auto flush = [&](int c) {
          for (int b = 0; b < bytes; ++b) {
            uint64_t& t = accTrusted[static_cast<size_t>(c) * bytes + b];
            uint64_t& o = accOnes[static_cast<size_t>(c) * bytes + b];
            for (int bit = 0; bit < 8; ++bit) {
              votes.trusted[c * bits + 8 * b + bit] += static_cast<int32_t>(t >> (8 * bit) & 0xFF);
              votes.ones[c * bits + 8 * b + bit] += static_cast<int32_t>(o >> (8 * bit) & 0xFF);
            }
            t = o = 0;
          }
          pending[c] = 0;
        };
        for (int i = range.begin(); i < range.end(); ++i) {
          const int c = assignment[i];
          const uint8_t* d = desc.ptr<uint8_t>(i);
          const uint8_t* m = masks.empty() ? nullptr : masks.ptr<uint8_t>(i);
          // An all-zero mask trusts every bit, as in the masked distance (masked_hamming.hpp).
          const bool trustAll = !m || std::all_of(m, m + bytes, [](uint8_t v) { return v == 0; });
          for (int b = 0; b < bytes; ++b) {
            const uint8_t mb = trustAll ? 0xFF : m[b];
            accTrusted[static_cast<size_t>(c) * bytes + b] += spread[mb];
            accOnes[static_cast<size_t>(c) * bytes + b] += spread[d[b] & mb];
          }
          ++votes.members[c];
          if (++pending[c] == 255) flush(c);
        }
        for (int c = 0; c < k; ++c)
          if (pending[c]) flush(c);
        return votes;
      },
      [](Votes a, const Votes& b) {
        a.add(b);
        return a;
      });
}

// New centroids (and masks) of the clusters with members; empty clusters keep theirs.
void updateCentroids(const Votes& v, bool masked, double agreement, cv::Mat& centroids, cv::Mat& centroidMasks) {
  const int bytes = centroids.cols;
  for (int c = 0; c < v.clusters; ++c) {
    const int n = v.members[c];
    if (n == 0) continue;
    uint8_t* row = centroids.ptr<uint8_t>(c);
    uint8_t* mrow = masked ? centroidMasks.ptr<uint8_t>(c) : nullptr;
    bool anyTrusted = false;
    for (int b = 0; b < bytes; ++b) {
      uint8_t value = 0, trust = 0;
      for (int bit = 0; bit < 8; ++bit) {
        const int i = c * v.bits + 8 * b + bit;
        const int ones = v.ones[i], trusted = v.trusted[i];
        if (2 * ones > trusted) value |= static_cast<uint8_t>(1 << bit);  // ties: 0
        const int agree = std::max(ones, trusted - ones);
        if (agree > 0 && static_cast<double>(agree) >= agreement * n) trust |= static_cast<uint8_t>(1 << bit);
      }
      row[b] = value;
      if (mrow) mrow[b] = trust;
      anyTrusted = anyTrusted || trust;
    }
    if (mrow && !anyTrusted) std::fill(mrow, mrow + bytes, uint8_t{0xFF});
  }
}

std::vector<int> trainIndices(const std::vector<cv::DMatch>& matches) {
  std::vector<int> out(matches.size());
  for (size_t i = 0; i < matches.size(); ++i) out[i] = matches[i].trainIdx;
  return out;
}

}  // namespace

KMajorityResult kMajority(const cv::Mat& desc, const cv::Mat& masks, const KMajorityOptions& o, uint64_t seed) {
  validateDescriptorMatrix(desc, "descriptors");
  if (desc.rows < 1) throw std::invalid_argument("kMajority: no descriptors");
  if (!masks.empty() && (masks.size() != desc.size() || masks.type() != CV_8UC1))
    throw std::invalid_argument("kMajority: masks differ in size or type from the descriptors");
  if (o.clusters < 1 || o.maxRounds < 1 || !(o.maskAgreement >= 0 && o.maskAgreement <= 1))
    throw std::invalid_argument("kMajority: clusters and maxRounds must be >= 1, maskAgreement in [0, 1]");
  const bool masked = !masks.empty();
  const int n = desc.rows;

  // k-means++ seeding: each next seed drawn with probability proportional to the squared
  // distance to the nearest seed so far; stops early when every member equals a seed.
  std::mt19937_64 rng(seed);
  std::vector<int> seeds{static_cast<int>(rng() % static_cast<uint64_t>(n))};
  std::vector<double> nearestDistance(n);
  {
    const auto m = nearest(desc, masks, desc.row(seeds[0]), masked ? masks.row(seeds[0]) : cv::Mat());
    for (int i = 0; i < n; ++i) nearestDistance[i] = m[i].distance;
  }
  while (static_cast<int>(seeds.size()) < o.clusters) {
    double total = 0;
    for (const double d : nearestDistance) total += d * d;
    if (total <= 0) break;
    // A uniform draw in [0, total) from the engine's raw bits (portable across libraries).
    const double target = static_cast<double>(rng() >> 11) * 0x1.0p-53 * total;
    double cumulative = 0;
    int pick = -1;
    for (int i = 0; i < n; ++i) {
      if (nearestDistance[i] <= 0) continue;
      pick = i;
      cumulative += nearestDistance[i] * nearestDistance[i];
      if (cumulative > target) break;
    }
    seeds.push_back(pick);
    const auto m = nearest(desc, masks, desc.row(pick), masked ? masks.row(pick) : cv::Mat());
    for (int i = 0; i < n; ++i) nearestDistance[i] = std::min<double>(nearestDistance[i], m[i].distance);
  }
  const int k = static_cast<int>(seeds.size());
  cv::Mat centroids(k, desc.cols, CV_8UC1), centroidMasks;
  if (masked) centroidMasks.create(k, desc.cols, CV_8UC1);
  for (int c = 0; c < k; ++c) {
    desc.row(seeds[c]).copyTo(centroids.row(c));
    if (masked) masks.row(seeds[c]).copyTo(centroidMasks.row(c));
  }

  KMajorityResult r;
  std::vector<int> assignment = trainIndices(nearest(desc, masks, centroids, centroidMasks));
  for (r.rounds = 1;; ++r.rounds) {
    updateCentroids(countVotes(desc, masks, assignment, k), masked, o.maskAgreement, centroids, centroidMasks);
    std::vector<int> next = trainIndices(nearest(desc, masks, centroids, centroidMasks));
    const bool stable = next == assignment;
    assignment = std::move(next);
    if (stable) break;
    if (r.rounds == o.maxRounds) {
      // Out of rounds: the centroids still summarise their members.
      updateCentroids(countVotes(desc, masks, assignment, k), masked, o.maskAgreement, centroids, centroidMasks);
      break;
    }
  }

  // Only clusters with members, in their order.
  std::vector<int> members(k, 0), renumber(k, -1);
  for (const int c : assignment) ++members[c];
  int kept = 0;
  for (int c = 0; c < k; ++c)
    if (members[c]) renumber[c] = kept++;
  r.centroids.create(kept, desc.cols, CV_8UC1);
  if (masked) r.masks.create(kept, desc.cols, CV_8UC1);
  for (int c = 0; c < k; ++c) {
    if (renumber[c] < 0) continue;
    centroids.row(c).copyTo(r.centroids.row(renumber[c]));
    if (masked) centroidMasks.row(c).copyTo(r.masks.row(renumber[c]));
  }
  r.assignment.resize(n);
  for (int i = 0; i < n; ++i) r.assignment[i] = renumber[assignment[i]];
  return r;
}

}  // namespace mdbrief::vocab

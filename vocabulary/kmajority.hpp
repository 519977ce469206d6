#pragma once
// k-majority clustering of binary descriptors (Grana et al. 2013; the clustering of DBoW2's
// vocabularies), one node of the vocabulary tree at a time: k-means++ seeding, then rounds of
// assigning every descriptor to its nearest centroid and recomputing each centroid bit by
// majority vote, until no assignment changes.
//
// Masked (mdBRIEF): distances are the masked distance of masked_hamming.hpp (the descriptor's
// mask and the centroid's), a bit's vote counts only where the member's own mask trusts it, and
// every centroid keeps the mask of the bits its members agree on: bit b is trusted when the
// members that trust b and hold the majority value of b are at least `maskAgreement` of all the
// members. A centroid with no such bit trusts every bit (as an all-zero mask does in the
// masked distance). Plain: Hamming distances, every member votes on every bit.
//
// Deterministic for a seed: the random draws depend only on the seed, and the parallel steps
// (assignment per descriptor, integer vote counts) do not depend on the threads.
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

namespace mdbrief::vocab {

struct KMajorityOptions {
  int clusters = 10;           // k: at most this many clusters (fewer when fewer distinct members)
  int maxRounds = 10;          // assignment/vote rounds at most (each round after the seeding)
  // Masked only: see above. Default: the value of docs/RESULTS.md "Place recognition (issue 20)".
  double maskAgreement = 0.5;
};

struct KMajorityResult {
  cv::Mat centroids;             // clusters x bytes, CV_8UC1, every cluster non-empty
  cv::Mat masks;                 // masked: clusters x bytes, no row all zero; plain: empty
  std::vector<int> assignment;   // per member, its cluster
  int rounds = 0;                // rounds run
};

// descriptors: members x bytes CV_8UC1 (at least one row); masks: the same size (masked) or
// empty (plain). Throws std::invalid_argument on bad shapes or options.
KMajorityResult kMajority(const cv::Mat& descriptors, const cv::Mat& masks, const KMajorityOptions& options,
                          uint64_t seed);

}  // namespace mdbrief::vocab

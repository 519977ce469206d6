#pragma once
// Brute-force nearest-neighbour matching of binary descriptors, plain and masked
// (hamming.hpp, masked_hamming.hpp). Exhaustive: every query is compared with every train
// descriptor, keeping only the two nearest on the fly (no distance matrix).
//
// Results are deterministic and independent of threading: each query is processed by one
// task, trains are visited in index order and ties go to the lowest train index.
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "mdbrief/base/option_fields.hpp"

namespace mdbrief {

struct MatchOptions {
  // Lowe's ratio test: keep a match only if best < ratio * secondBest (the second nearest
  // train descriptor; with a single train descriptor the test passes). Must be in (0, 1];
  // unset = off. The default keeps matches as precise as AKAZE's and the most right two-view
  // fits with the default features (docs/RESULTS.md "Real images: what a tracker keeps" and
  // "Coarse blobs first").
  std::optional<float> ratio = 0.55f;
  // Keep a match only if the query and its nearest train descriptor are mutual nearest
  // neighbours (the train's nearest query, ties to the lowest query index, is this query).
  // Costs a second pass; on by default for the same measurement as the ratio.
  bool crossCheck = true;
  // Keep a match only if distance <= maxDistance (bits; for masked matching the scaled masked
  // distance of masked_hamming.hpp). Must be in [0, 512] (no distance exceeds the longest
  // descriptor). Unset (default) = off.
  std::optional<float> maxDistance;
  // Spread queries over TBB workers; results are identical either way. Default on.
  bool parallel = true;
};

// The fields of MatchOptions (option_fields.hpp).
const OptionTable<MatchOptions>& matchOptionFields();
// Throws OptionError naming the first option out of its field's range.
void validate(const MatchOptions& options);

// Every query's nearest neighbour, as cv::BFMatcher::match gives it: no ratio test, no mutual
// check (for precision-recall curves and speed comparisons).
inline MatchOptions nearestNeighbourOptions() {
  MatchOptions o;
  o.ratio.reset();
  o.crossCheck = false;
  return o;
}

// One match per query that passes the enabled tests, in query order: queryIdx = query row,
// trainIdx = train row, distance = Hamming distance in bits, imgIdx = 0.
// query and train: N x bytes CV_8UC1, the same width, a multiple of 4 in [4, 64] (read once per
// call). A query or train without rows gives no matches; rows of no bytes (N x 0) are refused.
// Throws std::invalid_argument naming the argument otherwise.
std::vector<cv::DMatch> matchBruteForce(cv::InputArray query, cv::InputArray train, const MatchOptions& options = {});

// The same with the masked Hamming distance: queryMasks and trainMasks have the sizes of query
// and train (CV_8UC1). distance = masked distance in bits (masked_hamming.hpp).
std::vector<cv::DMatch> matchBruteForceMasked(cv::InputArray query, cv::InputArray queryMasks, cv::InputArray train,
                                              cv::InputArray trainMasks, const MatchOptions& options = {});

}  // namespace mdbrief

#pragma once
// Small vocabularies for the tests: trees given by their nodes' parents, and random trees whose
// words are known only through a reference descent.
#include <cstdint>
#include <random>
#include <vector>

#include <opencv2/core.hpp>

#include "mdbrief/match/masked_hamming.hpp"
#include "mdbrief/recognition/vocabulary.hpp"

namespace mdbrief::testing {

// parents[i] is the parent of node i + 1 (node 0 is the root); each node's children must follow
// one another. centroids/masks: one row per node including the root (zero), or empty masks.
inline VocabularyTree treeFromParents(const std::vector<uint32_t>& parents, const cv::Mat& centroids,
                                      const cv::Mat& masks = {}, int branching = 10, int depth = 6) {
  VocabularyTree t;
  t.bits = centroids.cols * 8;
  t.branching = branching;
  t.depth = depth;
  t.masked = !masks.empty();
  const size_t nodes = parents.size() + 1;
  t.childBegin.assign(nodes, 0);
  t.childCount.assign(nodes, 0);
  for (size_t i = 0; i < parents.size(); ++i) {
    const uint32_t p = parents[i];
    if (t.childCount[p] == 0) t.childBegin[p] = static_cast<uint32_t>(i + 1);
    ++t.childCount[p];
  }
  t.centroids = centroids.clone();
  t.masks = masks.clone();
  for (size_t n = 0; n < nodes; ++n)
    if (t.childCount[n] == 0) t.wordWeights.push_back(1.0f);
  return t;
}

// A complete tree of `branching`^`depth` words with random centroids (and random masks with
// about three bits in four set, never empty), nodes in breadth-first order.
inline VocabularyTree randomTree(int branching, int depth, int bits, bool masked, uint32_t seed) {
  std::vector<uint32_t> parents;
  std::vector<uint32_t> level{0};
  uint32_t next = 1;
  for (int d = 0; d < depth; ++d) {
    std::vector<uint32_t> children;
    for (const uint32_t p : level)
      for (int c = 0; c < branching; ++c) {
        parents.push_back(p);
        children.push_back(next++);
      }
    level = children;
  }
  std::mt19937 rng(seed);
  const int nodes = static_cast<int>(parents.size()) + 1;
  cv::Mat centroids(nodes, bits / 8, CV_8UC1), masks;
  cv::randu(centroids, 0, 256);
  centroids.row(0).setTo(0);
  if (masked) {
    masks.create(nodes, bits / 8, CV_8UC1);
    for (int r = 1; r < nodes; ++r)
      for (int b = 0; b < bits / 8; ++b) masks.at<uint8_t>(r, b) = static_cast<uint8_t>(rng() | rng());
    masks.row(0).setTo(0);
    for (int r = 1; r < nodes; ++r) masks.at<uint8_t>(r, 0) |= 1;
  }
  VocabularyTree t = treeFromParents(parents, centroids, masks, branching, depth);
  for (size_t w = 0; w < t.wordWeights.size(); ++w) t.wordWeights[w] = 0.5f + static_cast<float>(rng() % 100) / 50.0f;
  return t;
}

// The word a descriptor reaches, by the definition: at every level the child of least
// distance (masked, or plain Hamming), ties to the first.
inline uint32_t referenceWord(const VocabularyTree& t, const uint8_t* d, const uint8_t* l) {
  const int bytes = t.bits / 8;
  std::vector<uint8_t> ones(bytes, 0xFF);
  if (!l) l = ones.data();
  uint32_t node = 0;
  while (t.childCount[node] > 0) {
    uint64_t best = UINT64_MAX;
    uint32_t bestNode = 0;
    for (uint32_t c = t.childBegin[node]; c < t.childBegin[node] + t.childCount[node]; ++c) {
      const uint8_t* centroid = t.centroids.ptr<uint8_t>(static_cast<int>(c));
      uint64_t dist = 0;
      if (t.masked) {
        dist = maskedHammingFixed(d, l, centroid, t.masks.ptr<uint8_t>(static_cast<int>(c)), bytes);
      } else {
        for (int b = 0; b < bytes; ++b) dist += static_cast<uint64_t>(__builtin_popcount(d[b] ^ centroid[b]));
      }
      if (dist < best) {
        best = dist;
        bestNode = c;
      }
    }
    node = bestNode;
  }
  uint32_t word = 0;
  for (uint32_t n = 0; n < node; ++n) word += t.childCount[n] == 0;
  return word;
}

}  // namespace mdbrief::testing

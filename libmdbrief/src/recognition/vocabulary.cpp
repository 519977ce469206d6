#include "mdbrief/recognition/vocabulary.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "match/matcher_kernels.hpp"
#include "mdbrief/match/hamming.hpp"
#include "match/query_row.hpp"
#include "recognition/vocabulary_data.hpp"

namespace mdbrief {

namespace {

using namespace matcher_kernels;

// The children of a node are few (the branching), so the row kernel serves every level; the
// block kernel wants its lanes packed per call and would not pay here.
using NearestTwo = Nearest (*)(const QueryRow&, const TrainView&);
NearestTwo activeNearestTwo() { return activeMatcherKernels().nearestTwoRows; }

void checkInput(const Vocabulary::Data& d, const cv::Mat& desc, const cv::Mat& masks) {
  validateDescriptorMatrix(desc, "descriptors");
  if (!desc.empty() && desc.cols != d.bits / 8)
    throw std::invalid_argument("descriptors: width " + std::to_string(desc.cols) + " bytes (" +
                                std::to_string(desc.cols * 8) + " bits) differs from the vocabulary's " +
                                std::to_string(d.bits / 8) + " bytes (" + std::to_string(d.bits) + " bits)");
  if (masks.empty()) return;
  if (masks.size() != desc.size() || masks.type() != CV_8UC1)
    throw std::invalid_argument("masks: " + std::to_string(masks.rows) + "x" + std::to_string(masks.cols) + " " +
                                cv::typeToString(masks.type()) + " differs from the descriptors' " +
                                std::to_string(desc.rows) + "x" + std::to_string(desc.cols) + " CV_8UC1");
}

// The leaf every row reaches, and the node it passed at `directDepth` (or its leaf, when that is
// shallower).
void descend(const Vocabulary::Data& d, const cv::Mat& desc, const cv::Mat& masks, int directDepth,
             std::vector<uint32_t>& leaves, std::vector<uint32_t>* directNodes) {
  const NearestTwo nearest = activeNearestTwo();
  const int nwords = d.nwords;
  const bool useMasks = d.masked && !masks.empty();
  QueryRow allTrusted;
  if (d.masked && !useMasks) {
    std::fill(allTrusted.l, allTrusted.l + nwords, ~uint32_t{0});
    allTrusted.w = maskWeight(d.bits, d.bits);
  }
  leaves.resize(desc.rows);
  if (directNodes) directNodes->resize(desc.rows);
  for (int r = 0; r < desc.rows; ++r) {
    QueryRow q = loadQueryRow(desc, useMasks ? &masks : nullptr, r, nwords);
    if (d.masked && !useMasks) {
      std::copy(allTrusted.l, allTrusted.l + nwords, q.l);
      q.w = allTrusted.w;
    }
    uint32_t node = 0, passed = 0;
    int level = 0;
    while (d.childCount[node] > 0) {
      const uint32_t begin = d.childBegin[node];
      TrainView children;
      children.desc = d.centroids + static_cast<size_t>(begin) * nwords;
      if (d.masked) {
        children.mask = d.masks + static_cast<size_t>(begin) * nwords;
        children.weight = d.maskWeights.data() + begin;
      }
      children.count = static_cast<int>(d.childCount[node]);
      children.nwords = nwords;
      node = begin + static_cast<uint32_t>(nearest(q, children).index);
      if (++level == directDepth) passed = node;
    }
    leaves[r] = node;
    if (directNodes) (*directNodes)[r] = level < directDepth ? node : passed;
  }
}

}  // namespace

int Vocabulary::bits() const { return data_->bits; }
int Vocabulary::branching() const { return data_->branching; }
int Vocabulary::depth() const { return data_->depth; }
Weighting Vocabulary::weighting() const { return data_->weighting; }
bool Vocabulary::masked() const { return data_->masked; }
size_t Vocabulary::nodeCount() const { return data_->nodeCount; }
size_t Vocabulary::wordCount() const { return data_->wordCount; }
float Vocabulary::wordWeight(uint32_t word) const { return data_->wordWeights[word]; }
uint32_t Vocabulary::wordNode(uint32_t word) const { return data_->nodeOfWord[word]; }
std::vector<uint64_t> Vocabulary::trainingImages() const {
  return {data_->trainingImages, data_->trainingImages + data_->trainingCount};
}

uint64_t Vocabulary::fingerprint() const {
  uint64_t v;
  std::memcpy(&v, data_->file.bytes() + 24, 8);  // the frame's checksum (framed_file.hpp)
  return v;
}

VocabularyTree Vocabulary::tree() const {
  const Data& d = *data_;
  VocabularyTree t;
  t.bits = d.bits;
  t.branching = d.branching;
  t.depth = d.depth;
  t.weighting = d.weighting;
  t.masked = d.masked;
  t.childBegin.assign(d.childBegin, d.childBegin + d.nodeCount);
  t.childCount.assign(d.childCount, d.childCount + d.nodeCount);
  const int bytes = d.bits / 8;
  t.centroids = cv::Mat(static_cast<int>(d.nodeCount), bytes, CV_8UC1,
                        const_cast<uint32_t*>(d.centroids)).clone();
  if (d.masked)
    t.masks = cv::Mat(static_cast<int>(d.nodeCount), bytes, CV_8UC1, const_cast<uint32_t*>(d.masks)).clone();
  t.wordWeights.assign(d.wordWeights, d.wordWeights + d.wordCount);
  t.trainingImages = trainingImages();
  return t;
}

std::vector<uint32_t> Vocabulary::words(cv::InputArray descriptors, cv::InputArray masks) const {
  const cv::Mat desc = descriptors.getMat(), m = masks.getMat();
  checkInput(*data_, desc, m);
  std::vector<uint32_t> leaves;
  if (desc.empty()) return leaves;
  descend(*data_, desc, m, 0, leaves, nullptr);
  for (uint32_t& leaf : leaves) leaf = data_->wordOfNode[leaf];
  return leaves;
}

BowVector Vocabulary::bowVector(const std::vector<uint32_t>& words) const {
  const Data& d = *data_;
  std::vector<uint32_t> sorted = words;
  std::sort(sorted.begin(), sorted.end());
  BowVector bow;
  double sum = 0;
  for (size_t i = 0; i < sorted.size();) {
    const uint32_t w = sorted[i];
    if (w >= d.wordCount)
      throw std::invalid_argument("words: word " + std::to_string(w) + " is not below the vocabulary's " +
                                  std::to_string(d.wordCount) + " words");
    size_t j = i;
    while (j < sorted.size() && sorted[j] == w) ++j;
    const double count = static_cast<double>(j - i), idf = d.wordWeights[w];
    i = j;
    if (idf <= 0) continue;  // a word every training image holds tells nothing (DBoW2 drops it too)
    double value = 1;
    switch (d.weighting) {
      case Weighting::TfIdf: value = count * idf; break;
      case Weighting::Tf: value = count; break;
      case Weighting::Idf: value = idf; break;
      case Weighting::Binary: value = 1; break;
    }
    bow.push_back({w, static_cast<float>(value)});
    sum += value;
  }
  for (BowEntry& e : bow) e.value = static_cast<float>(e.value / sum);
  return bow;
}

BowTransform Vocabulary::transform(cv::InputArray descriptors, cv::InputArray masks,
                                   const TransformOptions& options) const {
  if (options.directIndexDepth < 1)
    throw std::invalid_argument("TransformOptions::directIndexDepth must be >= 1, got " +
                                std::to_string(options.directIndexDepth));
  const cv::Mat desc = descriptors.getMat(), m = masks.getMat();
  checkInput(*data_, desc, m);
  BowTransform out;
  if (desc.empty()) return out;
  std::vector<uint32_t> leaves, direct;
  descend(*data_, desc, m, options.directIndexDepth, leaves, &direct);
  out.words.resize(leaves.size());
  for (size_t i = 0; i < leaves.size(); ++i) out.words[i] = data_->wordOfNode[leaves[i]];
  out.bow = bowVector(out.words);
  // Rows grouped by node: sorting (node, row) pairs keeps rows ascending within a node.
  std::vector<std::pair<uint32_t, int>> byNode(direct.size());
  for (size_t i = 0; i < direct.size(); ++i) byNode[i] = {direct[i], static_cast<int>(i)};
  std::sort(byNode.begin(), byNode.end());
  for (const auto& [node, row] : byNode) {
    if (out.direct.empty() || out.direct.back().node != node) out.direct.push_back({node, {}});
    out.direct.back().features.push_back(row);
  }
  return out;
}

}  // namespace mdbrief

// The vocabulary's binary file (vocabulary_data.hpp): writing the body, checking it on load.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "mdbrief/base/file_format_error.hpp"
#include "mdbrief/internal/base/io/atomic_file.hpp"
#include "describe/mask_weight_kernels.hpp"
#include "mdbrief/match/masked_hamming.hpp"
#include "recognition/vocabulary_data.hpp"

namespace mdbrief {

namespace {

constexpr uint64_t kHeaderEnd = 64;
// A million 512-bit masked words take about 150 MB; far larger files are refused unread.
constexpr uint64_t kMaxVocabularyFileBytes = uint64_t{4} << 30;

inline uint64_t pad8(uint64_t x) { return (x + 7) & ~uint64_t{7}; }

struct Layout {
  uint64_t childBegin = 0, childCount = 0, wordWeights = 0, trainingImages = 0, centroids = 0, masks = 0, end = 0;
};

Layout layoutOf(uint64_t nodes, uint64_t words, uint64_t training, uint64_t rowBytes, bool masked) {
  Layout l;
  uint64_t at = kHeaderEnd;
  l.childBegin = at;
  at = pad8(at + 4 * nodes);
  l.childCount = at;
  at = pad8(at + 4 * nodes);
  l.wordWeights = at;
  at = pad8(at + 4 * words);
  l.trainingImages = at;
  at += 8 * training;
  l.centroids = at;
  at = pad8(at + rowBytes * nodes);
  l.masks = at;
  if (masked) at = pad8(at + rowBytes * nodes);
  l.end = at;
  return l;
}

template <typename T>
void put(std::string& out, uint64_t at, const T* values, size_t count) {
  if (count) std::memcpy(&out[at - internal::kFrameBytes], values, count * sizeof(T));
}
template <typename T>
void putValue(std::string& out, uint64_t at, T value) {
  put(out, at, &value, 1);
}
uint32_t headerField(const uint8_t* file, int index) {
  uint32_t v;
  std::memcpy(&v, file + internal::kFrameBytes + 4 * index, 4);
  return v;
}

void putRows(std::string& out, uint64_t at, const cv::Mat& rows) {
  for (int r = 0; r < rows.rows; ++r) put(out, at + static_cast<uint64_t>(r) * rows.cols, rows.ptr<uint8_t>(r), rows.cols);
}

void requireRows(const cv::Mat& m, const char* name, size_t nodes, int bytes) {
  if (m.type() != CV_8UC1 || static_cast<size_t>(m.rows) != nodes || m.cols != bytes)
    throw std::invalid_argument(std::string("VocabularyTree::") + name + ": expected " + std::to_string(nodes) + " x " +
                                std::to_string(bytes) + " CV_8UC1 (nodes x bits/8), got " + std::to_string(m.rows) +
                                " x " + std::to_string(m.cols) + " " + cv::typeToString(m.type()));
}

[[noreturn]] void broken(const std::string& problem) { throw VocabularyContentError(problem); }

bool rowIsZero(const uint32_t* row, int nwords) {
  for (int k = 0; k < nwords; ++k)
    if (row[k]) return false;
  return true;
}

}  // namespace

std::string vocabularyBody(const VocabularyTree& t) {
  if (t.bits < 32 || t.bits > 512 || t.bits % 32)
    throw std::invalid_argument("VocabularyTree::bits must be 32..512 in steps of 32, got " + std::to_string(t.bits));
  const size_t nodes = t.childBegin.size();
  if (t.childCount.size() != nodes)
    throw std::invalid_argument("VocabularyTree: childBegin has " + std::to_string(nodes) + " nodes, childCount " +
                                std::to_string(t.childCount.size()));
  if (nodes > 0xFFFFFFF0u) throw std::invalid_argument("VocabularyTree: more than 2^32 nodes");
  const int bytes = t.bits / 8;
  requireRows(t.centroids, "centroids", nodes, bytes);
  if (t.masked) requireRows(t.masks, "masks", nodes, bytes);
  if (!t.masked && !t.masks.empty())
    throw std::invalid_argument("VocabularyTree::masks: must be empty for a plain (masked = false) vocabulary");
  const size_t words = static_cast<size_t>(std::count(t.childCount.begin(), t.childCount.end(), 0u));
  if (t.wordWeights.size() != words)
    throw std::invalid_argument("VocabularyTree::wordWeights: " + std::to_string(t.wordWeights.size()) +
                                " weights for " + std::to_string(words) + " words (leaves)");
  std::vector<uint64_t> training = t.trainingImages;
  std::sort(training.begin(), training.end());
  training.erase(std::unique(training.begin(), training.end()), training.end());

  const Layout l = layoutOf(nodes, words, training.size(), bytes, t.masked);
  std::string body(l.end - internal::kFrameBytes, '\0');
  const uint32_t header[8] = {static_cast<uint32_t>(t.bits),      t.masked ? 1u : 0u,
                              static_cast<uint32_t>(t.branching), static_cast<uint32_t>(t.depth),
                              static_cast<uint32_t>(t.weighting), static_cast<uint32_t>(nodes),
                              static_cast<uint32_t>(words),       static_cast<uint32_t>(training.size())};
  put(body, internal::kFrameBytes, header, 8);
  put(body, l.childBegin, t.childBegin.data(), nodes);
  put(body, l.childCount, t.childCount.data(), nodes);
  put(body, l.wordWeights, t.wordWeights.data(), words);
  put(body, l.trainingImages, training.data(), training.size());
  putRows(body, l.centroids, t.centroids);
  if (t.masked) putRows(body, l.masks, t.masks);
  return body;
}

std::shared_ptr<const Vocabulary::Data> vocabularyData(internal::FramedFile file) {
  auto d = std::make_shared<Vocabulary::Data>();
  d->file = std::move(file);
  const uint8_t* base = d->file.bytes();
  if (d->file.size < kHeaderEnd) broken("truncated: no room for the vocabulary header");
  const uint32_t bits = headerField(base, 0), flags = headerField(base, 1), branching = headerField(base, 2),
                 depth = headerField(base, 3), weighting = headerField(base, 4);
  d->nodeCount = headerField(base, 5);
  d->wordCount = headerField(base, 6);
  d->trainingCount = headerField(base, 7);
  if (bits < 32 || bits > 512 || bits % 32) broken("bits " + std::to_string(bits) + " is not 32..512 in steps of 32");
  if (flags > 1) broken("unknown flags " + std::to_string(flags));
  if (branching < 2 || branching > kMaxVocabularyBranching)
    broken("branching " + std::to_string(branching) + " is not in [2, " + std::to_string(kMaxVocabularyBranching) + "]");
  if (depth < 1 || depth > kMaxVocabularyDepth)
    broken("depth " + std::to_string(depth) + " is not in [1, " + std::to_string(kMaxVocabularyDepth) + "]");
  if (weighting > 3) broken("weighting " + std::to_string(weighting) + " is not one of 0..3 (tf-idf, tf, idf, binary)");
  if (d->nodeCount < 2) broken(std::to_string(d->nodeCount) + " nodes: a vocabulary has a root and at least one word");
  if (d->wordCount < 1 || d->wordCount >= d->nodeCount)
    broken(std::to_string(d->wordCount) + " words for " + std::to_string(d->nodeCount) + " nodes");
  d->bits = static_cast<int>(bits);
  d->nwords = d->bits / 32;
  d->branching = static_cast<int>(branching);
  d->depth = static_cast<int>(depth);
  d->weighting = static_cast<Weighting>(weighting);
  d->masked = flags & 1;
  const uint64_t rowBytes = bits / 8;
  const Layout l = layoutOf(d->nodeCount, d->wordCount, d->trainingCount, rowBytes, d->masked);
  if (l.end != d->file.size)
    broken("the header's sizes (" + std::to_string(d->nodeCount) + " nodes, " + std::to_string(d->wordCount) +
           " words, " + std::to_string(d->trainingCount) + " training images, " + std::to_string(bits) + " bits" +
           (d->masked ? ", masked" : "") + ") need " + std::to_string(l.end) + " bytes, the file has " +
           std::to_string(d->file.size));
  d->childBegin = reinterpret_cast<const uint32_t*>(base + l.childBegin);
  d->childCount = reinterpret_cast<const uint32_t*>(base + l.childCount);
  d->wordWeights = reinterpret_cast<const float*>(base + l.wordWeights);
  d->trainingImages = reinterpret_cast<const uint64_t*>(base + l.trainingImages);
  d->centroids = reinterpret_cast<const uint32_t*>(base + l.centroids);
  if (d->masked) d->masks = reinterpret_cast<const uint32_t*>(base + l.masks);

  // The tree: parents before children (so no cycle), every node but the root the child of
  // exactly one node, no leaf deeper than `depth`. Local pointers, so that the stores into the
  // tables do not make the compiler reload them per node.
  const uint32_t n = d->nodeCount, wordCount = d->wordCount;
  const uint32_t* childBegin = d->childBegin;
  const uint32_t* childCount = d->childCount;
  // 1 + the node's depth once a parent has claimed it, 0 before (the root: 1).
  std::vector<uint8_t> level(n, 0);
  level[0] = 1;
  d->wordOfNode.resize(n);
  d->nodeOfWord.resize(wordCount);
  uint32_t* wordOfNode = d->wordOfNode.data();
  uint32_t* nodeOfWord = d->nodeOfWord.data();
  uint32_t leaves = 0;
  for (uint32_t i = 0; i < n; ++i) {
    if (level[i] == 0) broken("node " + std::to_string(i) + " is no node's child");
    const uint32_t count = childCount[i], begin = childBegin[i];
    if (count == 0) {
      if (i == 0) broken("the root has no children");
      if (begin != 0) broken("node " + std::to_string(i) + " is a leaf but its childBegin is " + std::to_string(begin));
      if (leaves == wordCount) broken("more leaves than the header's " + std::to_string(wordCount) + " words");
      wordOfNode[i] = leaves;
      nodeOfWord[leaves++] = i;
      continue;
    }
    wordOfNode[i] = kNoWord;
    if (count > branching)
      broken("node " + std::to_string(i) + " has " + std::to_string(count) + " children, more than the branching " +
             std::to_string(branching));
    if (begin <= i || uint64_t{begin} + count > n)
      broken("node " + std::to_string(i) + ": children " + std::to_string(begin) + ".." +
             std::to_string(uint64_t{begin} + count - 1) + " are not after it and within the " + std::to_string(n) +
             " nodes");
    if (level[i] > depth)
      broken("node " + std::to_string(i) + " at depth " + std::to_string(level[i] - 1) +
             " has children, deeper than the depth " + std::to_string(depth));
    for (uint32_t c = begin; c < begin + count; ++c) {
      if (level[c]) broken("node " + std::to_string(c) + " is the child of two nodes");
      level[c] = static_cast<uint8_t>(level[i] + 1);
    }
  }
  if (leaves != wordCount)
    broken(std::to_string(leaves) + " leaves, but the header says " + std::to_string(wordCount) + " words");
  // Finite and >= 0 (-0 included), tested on the bits in one branch-free pass; the first
  // offender is looked for only when there is one.
  bool badWeight = false;
  for (uint32_t w = 0; w < wordCount; ++w) {
    uint32_t bitsOf;
    std::memcpy(&bitsOf, d->wordWeights + w, 4);
    badWeight |= bitsOf >= 0x7F800000u && bitsOf != 0x80000000u;
  }
  if (badWeight)
    for (uint32_t w = 0; w < wordCount; ++w)
      if (!std::isfinite(d->wordWeights[w]) || d->wordWeights[w] < 0)
        broken("word " + std::to_string(w) + " has weight " + std::to_string(d->wordWeights[w]) +
               " (must be finite and >= 0)");
  for (uint32_t i = 1; i < d->trainingCount; ++i)
    if (d->trainingImages[i] <= d->trainingImages[i - 1]) broken("training image digests are not sorted and unique");
  const int nw = d->nwords;
  if (!rowIsZero(d->centroids, nw)) broken("the root carries a centroid (its row must be zero)");
  if (d->masked) {
    if (!rowIsZero(d->masks, nw)) broken("the root carries a mask (its row must be zero)");
    // w(o) looked up by o, not divided per node: the division cost more than the count.
    std::vector<uint32_t> weightOfOnes(static_cast<size_t>(d->bits) + 1);
    for (int ones = 1; ones <= d->bits; ++ones) weightOfOnes[ones] = maskWeight(ones, d->bits);
    d->maskWeights.resize(n);
    d->maskWeights[0] = 0;
    const size_t empty =
        mask_weight_kernels::activeMaskWeights().weights(d->masks + nw, n - 1, nw, weightOfOnes.data(), d->maskWeights.data() + 1) + 1;
    if (empty < n) broken("node " + std::to_string(empty) + " has an empty mask");
  }
  return d;
}

std::shared_ptr<const Vocabulary::Data> vocabularyData(const VocabularyTree& tree) {
  return vocabularyData(internal::framedFileInMemory(
      internal::framedFileBytes(kVocabularyMagic, kVocabularyVersion, vocabularyBody(tree)), kVocabularyVersion));
}

Vocabulary Vocabulary::create(const VocabularyTree& tree) {
  try {
    return Vocabulary(vocabularyData(tree));
  } catch (const VocabularyContentError& e) {
    throw std::invalid_argument(std::string("VocabularyTree: ") + e.what());
  }
}

Vocabulary Vocabulary::load(const std::string& path) {
  internal::FramedFile file = internal::readFramedFile(
      path, kVocabularyMagic, kVocabularyVersion, kMaxVocabularyFileBytes, "vocabulary",
      "; a DBoW2/DBoW3 text vocabulary is read by importDbow2Text (mdbrief/recognition/vocabulary_text.hpp)");
  try {
    return Vocabulary(vocabularyData(std::move(file)));
  } catch (const VocabularyContentError& e) {
    throw FileFormatError(path, e.what());
  }
}

std::string Vocabulary::fileBytes() const {
  return std::string(reinterpret_cast<const char*>(data_->file.bytes()), data_->file.size);
}

void Vocabulary::save(const std::string& path) const {
  internal::writeFileAtomically(
      path, std::string_view(reinterpret_cast<const char*>(data_->file.bytes()), data_->file.size));
}

}  // namespace mdbrief

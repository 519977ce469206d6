#pragma once
// A vocabulary of binary visual words for place recognition (bags of binary words, as DBoW2):
// a tree whose nodes carry centroids, at most `branching` (k) children per node and leaves at
// depth at most `depth` (L), so at most k^L words. A descriptor is quantised by descending from
// the root to the nearest child at every level; the leaf it reaches is its word.
//
// Masked vocabularies (mdBRIEF): every node keeps, besides its centroid, the mask of the bits
// the training descriptors under it agree on, and wherever a descriptor meets a node the masked
// distance of masked_hamming.hpp is used (the descriptor's mask on one side, the node's on the
// other). Plain vocabularies (ORB, BRIEF, dBRIEF, or mdBRIEF with its masks ignored) use the
// Hamming distance and ignore descriptor masks.
//
// Words are weighted, by default with TF-IDF: idf(w) = log(N / n_w) over the N training images,
// n_w of which contain word w. The toolchain trains vocabularies (mdbrief-train-vocabulary,
// docs/vocabulary.md); the library reads and writes them: save/load here (a checked binary
// file), vocabulary_text.hpp for DBoW2/DBoW3 text files. A Vocabulary is immutable: copies
// share its data, and every const member may be called from several threads at once.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "mdbrief/recognition/bow_vector.hpp"
#include "mdbrief/base/enum_names.hpp"

namespace mdbrief {

// How a word's count in an image becomes its value in the image's BowVector (DBoW2's weighting
// types, in DBoW2's numbering): TF-IDF count * idf, TF count, IDF idf once, Binary 1 once.
enum class Weighting { TfIdf = 0, Tf = 1, Idf = 2, Binary = 3 };
inline constexpr EnumName<Weighting> kWeightingNames[] = {
    {Weighting::TfIdf, "tf-idf"}, {Weighting::Tf, "tf"}, {Weighting::Idf, "idf"}, {Weighting::Binary, "binary"}};
inline std::string toString(Weighting weighting) { return nameOf(weighting, kWeightingNames); }
inline Weighting parseWeighting(const std::string& name) { return parseName(name, kWeightingNames, "weighting"); }

inline constexpr int kMaxVocabularyBranching = 256;
inline constexpr int kMaxVocabularyDepth = 32;

// A vocabulary's content, as a trainer or an importer builds it (Vocabulary::create checks it).
struct VocabularyTree {
  int bits = 256;                         // descriptor length: 32..512 in steps of 32
  int branching = 10;                     // k: at most this many children per node, 2..256
  int depth = 6;                          // L: no leaf deeper (the root has depth 0), 1..32
  Weighting weighting = Weighting::TfIdf;
  bool masked = false;                    // nodes carry masks, descriptors meet them masked
  // Node 0 is the root. The children of node n are the nodes childBegin[n] ..
  // childBegin[n] + childCount[n] - 1, all after n; every other node is the child of exactly
  // one node. A node without children is a leaf, i.e. a word (its childBegin is 0); words are
  // numbered in node order. The root has children.
  std::vector<uint32_t> childBegin, childCount;
  cv::Mat centroids;                      // nodes x bits/8, CV_8UC1; row 0 (the root) zero
  cv::Mat masks;                          // masked: as centroids, no other row all zero; else empty
  std::vector<float> wordWeights;         // per word: finite, >= 0 (0: the word is ignored)
  // Digests (patchextract/image_digest.hpp, as numbers) of the training images, so evaluations
  // can refuse to measure on them; kept sorted, without repeats.
  std::vector<uint64_t> trainingImages;
};

// The features of one image grouped by the node they pass at one depth of the tree, for matching
// only features under the same node (ORB-SLAM's guided matching).
struct DirectIndexEntry {
  uint32_t node = 0;
  std::vector<int> features;  // rows of the descriptors, ascending
};
using DirectIndex = std::vector<DirectIndexEntry>;  // ascending node

struct BowTransform {
  BowVector bow;
  DirectIndex direct;
  std::vector<uint32_t> words;  // the word of every descriptor row
};

struct TransformOptions {
  // Depth of the direct index's nodes (1 = the root's children); a word above that depth is its
  // own entry. Default 2: ORB-SLAM's level (four above the leaves of its six-level vocabulary).
  int directIndexDepth = 2;
};

class Vocabulary {
 public:
  // Checks `tree` (every rule of VocabularyTree) and builds the vocabulary. Throws
  // std::invalid_argument naming the first field or node that breaks a rule.
  static Vocabulary create(const VocabularyTree& tree);

  // The library's binary file (docs/vocabulary.md "File format"): mapped into memory and used in
  // place, checked (magic, version, sizes against the file's size, checksum, then the tree's
  // rules), in milliseconds for a million words. Throws FileFormatError (file_format_error.hpp)
  // naming the file and the problem. While the Vocabulary (or a copy) lives, its file may be
  // replaced by renaming another over it (as save does) or removed, but not truncated or
  // rewritten in place: the mapping would see the change (a truncation kills the process with
  // SIGBUS).
  static Vocabulary load(const std::string& path);
  // Writes that file atomically (the previous file stays until the new one is complete). The
  // bytes depend only on the content. Throws std::runtime_error naming the path on failure.
  void save(const std::string& path) const;
  // The file's bytes.
  std::string fileBytes() const;

  int bits() const;
  int descriptorBytes() const { return bits() / 8; }
  int branching() const;
  int depth() const;
  Weighting weighting() const;
  bool masked() const;
  size_t nodeCount() const;
  size_t wordCount() const;
  float wordWeight(uint32_t word) const;  // unchecked: word < wordCount()
  uint32_t wordNode(uint32_t word) const;  // unchecked
  std::vector<uint64_t> trainingImages() const;
  // The checksum of the file's content: two vocabularies with the same content have the same one
  // (a database records it to refuse another vocabulary).
  uint64_t fingerprint() const;
  // The content, e.g. to change the weights or to export it.
  VocabularyTree tree() const;

  // Quantises descriptors (N x bits/8, CV_8UC1) with their masks (the same size, or empty: all
  // bits trusted; ignored by a plain vocabulary): the BowVector with the vocabulary's weighting,
  // the direct index and every row's word. Single-threaded and deterministic. Throws
  // std::invalid_argument when the width differs from the vocabulary's, or the masks' size or
  // type from the descriptors'.
  BowTransform transform(cv::InputArray descriptors, cv::InputArray masks = cv::noArray(),
                         const TransformOptions& options = {}) const;
  // Only the word of every row (the same checks).
  std::vector<uint32_t> words(cv::InputArray descriptors, cv::InputArray masks = cv::noArray()) const;
  // The BowVector of words (each < wordCount(); repeats count), with the vocabulary's weighting.
  BowVector bowVector(const std::vector<uint32_t>& words) const;

  // The library's own (its readers build a Vocabulary from checked data this way).
  struct Data;
  explicit Vocabulary(std::shared_ptr<const Data> data) : data_(std::move(data)) {}

 private:
  std::shared_ptr<const Data> data_;
};

}  // namespace mdbrief

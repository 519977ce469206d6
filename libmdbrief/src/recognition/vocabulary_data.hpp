#pragma once
// What a Vocabulary holds: its file's bytes (framed_file.hpp, then the body below), read in
// place, plus what is derived from them on load. One path builds it from bytes, whether they
// come from a file or from a VocabularyTree, so both pass the same checks.
//
// Body, little-endian, every section starting at a multiple of 8 bytes (zero padding):
//   bytes 32-63  u32 bits, flags (bit 0: masked), branching, depth, weighting, nodeCount,
//                wordCount, trainingImageCount
//   u32 childBegin[nodeCount], u32 childCount[nodeCount], f32 wordWeights[wordCount],
//   u64 trainingImages[trainingImageCount], u8 centroids[nodeCount][bits/8],
//   u8 masks[nodeCount][bits/8] (masked only)
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "mdbrief/internal/base/io/framed_file.hpp"
#include "mdbrief/recognition/vocabulary.hpp"

namespace mdbrief {

inline constexpr char kVocabularyMagic[] = "MDBVOCAB";
inline constexpr uint32_t kVocabularyVersion = 1;
inline constexpr uint32_t kNoWord = 0xFFFFFFFFu;

// A rule of the content is broken; the message names the field or node (callers add the source).
struct VocabularyContentError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Vocabulary::Data {
  internal::FramedFile file;
  int bits = 0, nwords = 0, branching = 0, depth = 0;
  Weighting weighting = Weighting::TfIdf;
  bool masked = false;
  uint32_t nodeCount = 0, wordCount = 0, trainingCount = 0;
  // Views into file.words.
  const uint32_t* childBegin = nullptr;
  const uint32_t* childCount = nullptr;
  const float* wordWeights = nullptr;
  const uint64_t* trainingImages = nullptr;
  const uint32_t* centroids = nullptr;  // nodeCount x nwords
  const uint32_t* masks = nullptr;      // masked only
  // Derived on load.
  std::vector<uint32_t> maskWeights;  // masked: w(o) of every node's mask (masked_hamming.hpp)
  std::vector<uint32_t> nodeOfWord;
  std::vector<uint32_t> wordOfNode;   // kNoWord for inner nodes
};

// The body of a vocabulary file for `tree`. Throws std::invalid_argument when the arrays'
// sizes disagree (the rules of the content are checked by vocabularyData).
std::string vocabularyBody(const VocabularyTree& tree);

// Checks the content of a framed vocabulary file and derives the rest. Throws
// VocabularyContentError naming the first broken rule.
std::shared_ptr<const Vocabulary::Data> vocabularyData(internal::FramedFile file);

// The same for a tree: std::invalid_argument for arrays of disagreeing sizes,
// VocabularyContentError for a broken rule.
std::shared_ptr<const Vocabulary::Data> vocabularyData(const VocabularyTree& tree);

}  // namespace mdbrief

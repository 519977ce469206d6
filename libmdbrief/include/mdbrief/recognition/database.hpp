#pragma once
// An image database for place recognition: the BowVectors of the images added, an inverted
// index (for every word, the images that hold it), and queries that return the images of
// highest L1 score (bow_vector.hpp) with a vocabulary (vocabulary.hpp). Adding and querying are
// deterministic; const members may be called from several threads at once, add() not.
#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "mdbrief/recognition/bow_vector.hpp"
#include "mdbrief/recognition/vocabulary.hpp"

namespace mdbrief {

struct QueryResult {
  uint32_t entry = 0;  // the image's id: the order in which it was added, from 0
  float score = 0;     // l1Score of the query and the entry, in (0, 1]
};

class Database {
 public:
  explicit Database(Vocabulary vocabulary);

  // Adds one image; returns its entry id. Throws std::invalid_argument when bow is not a
  // BowVector of this vocabulary (words ascending, unique and below wordCount(), values finite
  // and > 0).
  uint32_t add(const BowVector& bow);
  // The same from the image's descriptors and masks (Vocabulary::transform).
  uint32_t addDescriptors(cv::InputArray descriptors, cv::InputArray masks = cv::noArray());

  // The at most maxResults entries of highest score, best first (equal scores: lower entry
  // first); entries without a word in common with the query are not returned. The scores are
  // l1Score's, to the last bit. Throws std::invalid_argument as add() for a bad bow, or when
  // maxResults < 1.
  std::vector<QueryResult> query(const BowVector& bow, int maxResults) const;
  std::vector<QueryResult> queryDescriptors(cv::InputArray descriptors, cv::InputArray masks, int maxResults) const;

  size_t size() const { return entries_.size(); }
  const BowVector& entry(uint32_t id) const;  // throws std::out_of_range
  const Vocabulary& vocabulary() const { return vocabulary_; }

  // A checked binary file (docs/vocabulary.md "File format"): the entries and the fingerprint of
  // the vocabulary; the inverted index is rebuilt on load. Written atomically; throws
  // std::runtime_error naming the path on failure.
  void save(const std::string& path) const;
  std::string fileBytes() const;
  // Reads that file for `vocabulary`. Throws FileFormatError naming the file and the problem,
  // among them a file made with another vocabulary (its fingerprint differs).
  static Database load(const std::string& path, Vocabulary vocabulary);

 private:
  struct Posting {
    uint32_t entry;
    float value;
  };
  Vocabulary vocabulary_;
  std::vector<BowVector> entries_;
  std::vector<std::vector<Posting>> inverted_;  // per word, entries ascending
};

}  // namespace mdbrief

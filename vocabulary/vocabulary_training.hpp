#pragma once
// Training a vocabulary (mdbrief/recognition/vocabulary.hpp) from the descriptors of training images:
// hierarchical k-majority clustering (kmajority.hpp) from the root down, k children per node and
// at most L levels, then the words' weights from the same images (idf = log(N / n_w), N images,
// n_w of which reach word w through the trained tree, exactly as transform() quantises; 1 for tf
// and binary weighting).
//
// The nodes of one level are clustered in parallel (and each node's clustering is parallel
// itself); node i's seed is a function of the training seed and i, nodes are numbered breadth
// first, so the vocabulary is the same for a seed whatever the threads.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "mdbrief/recognition/vocabulary.hpp"
#include "vocabulary/kmajority.hpp"

namespace mdbrief::vocab {

// One training image: its descriptors, their masks (empty for a plain vocabulary or plain
// descriptors) and its digest (patchextract/image_digest.hpp as a number; 0 = unknown, e.g.
// descriptors read from a file).
struct TrainingImage {
  cv::Mat descriptors;
  cv::Mat masks;
  uint64_t digest = 0;
};

struct VocabularyTrainingOptions {
  int branching = 10;   // k, 2..256
  int depth = 4;        // L, 1..32: at most k^L words
  // Masked vocabulary: needs masks on every image; false trains a plain one and ignores masks.
  bool masked = true;
  Weighting weighting = Weighting::TfIdf;
  KMajorityOptions clustering;  // its `clusters` is set to `branching`
  uint64_t seed = 1;
};

// done/total units of a named stage; called from worker threads.
using TrainingProgress = std::function<void(const std::string& stage, size_t done, size_t total)>;

// Throws std::invalid_argument for bad options, no descriptors, widths that differ between
// images, or a masked vocabulary asked for images without masks.
Vocabulary trainVocabulary(const std::vector<TrainingImage>& images, const VocabularyTrainingOptions& options,
                           const TrainingProgress& progress = {});

// The words' weights from the images, returned with the vocabulary: for tf-idf and idf weighting
// idf = log(N / n_w) (a word no image reaches counts as reached by one; the images are quantised
// with the vocabulary's masks rule); for tf and binary 1, as DBoW2 (they have no idf part).
Vocabulary withWordWeights(const Vocabulary& vocabulary, const std::vector<TrainingImage>& images);

}  // namespace mdbrief::vocab

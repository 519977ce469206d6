#include "vocabulary/vocabulary_training.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "mdbrief/internal/base/size_text.hpp"

namespace mdbrief::vocab {

namespace {

uint64_t splitMix(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

struct PendingNode {
  uint32_t node = 0;
  std::vector<uint32_t> members;  // rows of the stacked descriptors
};

cv::Mat gatherRows(const cv::Mat& all, const std::vector<uint32_t>& rows) {
  cv::Mat out(static_cast<int>(rows.size()), all.cols, CV_8UC1);
  for (size_t i = 0; i < rows.size(); ++i) all.row(static_cast<int>(rows[i])).copyTo(out.row(static_cast<int>(i)));
  return out;
}

void validate(const std::vector<TrainingImage>& images, const VocabularyTrainingOptions& o) {
  if (o.branching < 2 || o.branching > kMaxVocabularyBranching)
    throw std::invalid_argument("branching must be in [2, " + std::to_string(kMaxVocabularyBranching) + "], got " +
                                std::to_string(o.branching));
  if (o.depth < 1 || o.depth > kMaxVocabularyDepth)
    throw std::invalid_argument("depth must be in [1, " + std::to_string(kMaxVocabularyDepth) + "], got " +
                                std::to_string(o.depth));
  int width = -1;
  size_t rows = 0;
  for (size_t i = 0; i < images.size(); ++i) {
    const TrainingImage& im = images[i];
    if (im.descriptors.empty()) continue;
    if (im.descriptors.type() != CV_8UC1 || im.descriptors.cols % 4 || im.descriptors.cols < 4 || im.descriptors.cols > 64)
      throw std::invalid_argument("image " + std::to_string(i) +
                                  ": descriptors must be CV_8U, 4..64 bytes wide in steps of 4, got " +
                                  internal::matrixText(im.descriptors));
    if (width >= 0 && im.descriptors.cols != width)
      throw std::invalid_argument("image " + std::to_string(i) + ": descriptors of " + std::to_string(im.descriptors.cols) +
                                  " bytes, the images before have " + std::to_string(width));
    width = im.descriptors.cols;
    if (o.masked && (im.masks.size() != im.descriptors.size() || im.masks.type() != CV_8UC1))
      throw std::invalid_argument("image " + std::to_string(i) + ": no masks of the descriptors' size and type (" +
                                  internal::matrixText(im.descriptors) + "), got " + internal::matrixText(im.masks) +
                                  "; a masked vocabulary needs them (train a plain one)");
    rows += static_cast<size_t>(im.descriptors.rows);
  }
  if (rows == 0) throw std::invalid_argument("no training descriptors");
  if (rows > 0x7FFFFFFFu) throw std::invalid_argument("more than 2^31 training descriptors");
}

}  // namespace

Vocabulary withWordWeights(const Vocabulary& vocabulary, const std::vector<TrainingImage>& images) {
  VocabularyTree t = vocabulary.tree();
  if (t.weighting == Weighting::Tf || t.weighting == Weighting::Binary) {
    std::fill(t.wordWeights.begin(), t.wordWeights.end(), 1.0f);
    return Vocabulary::create(t);
  }
  std::vector<std::vector<uint32_t>> seen(images.size());
  tbb::parallel_for(size_t(0), images.size(), [&](size_t i) {
    if (images[i].descriptors.empty()) return;
    std::vector<uint32_t> w = vocabulary.words(images[i].descriptors, vocabulary.masked() ? images[i].masks : cv::Mat());
    std::sort(w.begin(), w.end());
    w.erase(std::unique(w.begin(), w.end()), w.end());
    seen[i] = std::move(w);
  });
  std::vector<uint32_t> holding(vocabulary.wordCount(), 0);
  for (const auto& w : seen)
    for (const uint32_t word : w) ++holding[word];
  const double n = static_cast<double>(images.size());
  for (size_t w = 0; w < t.wordWeights.size(); ++w)
    t.wordWeights[w] = static_cast<float>(std::log(n / std::max<uint32_t>(holding[w], 1)));
  return Vocabulary::create(t);
}

Vocabulary trainVocabulary(const std::vector<TrainingImage>& images, const VocabularyTrainingOptions& o,
                           const TrainingProgress& progress) {
  validate(images, o);
  std::vector<cv::Mat> descRows, maskRows;
  for (const auto& im : images)
    if (!im.descriptors.empty()) {
      descRows.push_back(im.descriptors);
      if (o.masked) maskRows.push_back(im.masks);
    }
  cv::Mat all, allMasks;
  cv::vconcat(descRows, all);
  if (o.masked) cv::vconcat(maskRows, allMasks);
  const int bytes = all.cols;

  VocabularyTree t;
  t.bits = 8 * bytes;
  t.branching = o.branching;
  t.depth = o.depth;
  t.weighting = o.weighting;
  t.masked = o.masked;
  t.childBegin = {0};
  t.childCount = {0};
  std::vector<uint8_t> centroidBytes(bytes, 0), maskBytes(bytes, 0);  // the root's rows
  KMajorityOptions clustering = o.clustering;
  clustering.clusters = o.branching;

  std::vector<PendingNode> level(1);
  level[0].members.resize(static_cast<size_t>(all.rows));
  for (size_t i = 0; i < level[0].members.size(); ++i) level[0].members[i] = static_cast<uint32_t>(i);
  for (int depth = 0; !level.empty(); ++depth) {
    std::vector<KMajorityResult> results(level.size());
    std::atomic<size_t> done{0};
    const std::string stage = "clustering level " + std::to_string(depth + 1) + " of " + std::to_string(o.depth);
    tbb::parallel_for(size_t(0), level.size(), [&](size_t i) {
      const cv::Mat desc = gatherRows(all, level[i].members);
      const cv::Mat masks = o.masked ? gatherRows(allMasks, level[i].members) : cv::Mat();
      results[i] = kMajority(desc, masks, clustering, splitMix(o.seed ^ splitMix(level[i].node)));
      if (progress) progress(stage, ++done, level.size());
    });
    // Children numbered in the order of their parents: breadth first, whatever the threads did.
    std::vector<PendingNode> next;
    for (size_t i = 0; i < level.size(); ++i) {
      const KMajorityResult& r = results[i];
      const uint32_t parent = level[i].node;
      const int clusters = r.centroids.rows;
      if (clusters == 1 && parent != 0) continue;  // identical members: the node stays a word
      std::vector<std::vector<uint32_t>> buckets(clusters);
      for (size_t m = 0; m < level[i].members.size(); ++m) buckets[r.assignment[m]].push_back(level[i].members[m]);
      t.childBegin[parent] = static_cast<uint32_t>(t.childBegin.size());
      t.childCount[parent] = static_cast<uint32_t>(clusters);
      for (int c = 0; c < clusters; ++c) {
        const uint32_t node = static_cast<uint32_t>(t.childBegin.size());
        t.childBegin.push_back(0);
        t.childCount.push_back(0);
        centroidBytes.insert(centroidBytes.end(), r.centroids.ptr<uint8_t>(c), r.centroids.ptr<uint8_t>(c) + bytes);
        if (o.masked) maskBytes.insert(maskBytes.end(), r.masks.ptr<uint8_t>(c), r.masks.ptr<uint8_t>(c) + bytes);
        if (depth + 1 < o.depth && buckets[c].size() > 1) next.push_back({node, std::move(buckets[c])});
      }
    }
    level = std::move(next);
  }
  const int nodes = static_cast<int>(t.childBegin.size());
  t.centroids = cv::Mat(nodes, bytes, CV_8UC1, centroidBytes.data()).clone();
  if (o.masked) t.masks = cv::Mat(nodes, bytes, CV_8UC1, maskBytes.data()).clone();
  t.wordWeights.assign(static_cast<size_t>(std::count(t.childCount.begin(), t.childCount.end(), 0u)), 1.0f);
  for (const auto& im : images)
    if (im.digest) t.trainingImages.push_back(im.digest);
  if (progress) progress("weighting words", 0, 1);
  Vocabulary weighted = withWordWeights(Vocabulary::create(t), images);
  if (progress) progress("weighting words", 1, 1);
  return weighted;
}

}  // namespace mdbrief::vocab

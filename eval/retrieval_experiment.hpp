#pragma once
// Place recognition with vocabularies (issue 20): retrieval recall of one Database per method.
// The database holds the first image of every sequence plus distractor images; every other image
// of a sequence is a query, right when its sequence's first image is among the top k results.
// The methods share the training images and the tree's shape (k, L, seed), so their word counts
// match: mdBRIEF with masked centroids, mdBRIEF with the masks ignored (trained and queried
// plain), and cv::ORB with a plain vocabulary trained the same way. Besides recall: transform
// time per 1000 features, query time, and the vocabulary's file size and load time against the
// DBoW2 text of the same vocabulary (plain ones; the text has no masks).
#include <string>
#include <vector>

#include "pr_experiment.hpp"
#include "vocabulary/training_features.hpp"

namespace mdbrief::eval {

struct RetrievalOptions {
  vocab::VocabularyTrainingOptions training;  // branching, depth and seed shared by the methods
  int nfeatures = vocab::FeatureOptions{}.nfeatures;  // keypoints per image at most, every method
  std::vector<int> recallAt{1, 5};
  std::string outDir;                         // retrieval.csv, retrieval_speed.csv, the vocabularies
};

// Training images and distractors are image files; the training set must not hold a distractor
// (by digest): throws InputError naming it. Writes outDir/retrieval.csv (deterministic) and
// outDir/retrieval_speed.csv (timings), and prints a summary.
void runRetrieval(const std::vector<EvalGroup>& groups, const std::vector<std::string>& trainingImages,
                  const std::vector<std::string>& distractors, const RetrievalOptions& options);
// Every file runRetrieval writes: the tables and each method's vocabulary (binary, and DBoW2 text
// for the plain ones).
std::vector<std::string> retrievalOutputs(const RetrievalOptions& options);

}  // namespace mdbrief::eval

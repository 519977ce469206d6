#include "retrieval_experiment.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include <tbb/parallel_for.h>

#include "csv_table.hpp"
#include "eval_commands.hpp"
#include "mdbrief/recognition/database.hpp"
#include "mdbrief/recognition/vocabulary_text.hpp"

namespace mdbrief::eval {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

struct Method {
  const char* name;
  vocab::FeatureKind kind;
  bool masked;
};
const Method kMethods[] = {{"mdbrief-masked", vocab::FeatureKind::MdBrief, true},
                           {"mdbrief-blind", vocab::FeatureKind::MdBrief, false},
                           {"orb", vocab::FeatureKind::Orb, false}};

std::string binaryPath(const RetrievalOptions& o, const Method& m) { return o.outDir + "/" + m.name + ".mdbvoc"; }
// Plain vocabularies only: DBoW2's text has no masks.
std::string textPath(const RetrievalOptions& o, const Method& m) { return o.outDir + "/" + m.name + ".dbow2.txt"; }
std::string recallPath(const RetrievalOptions& o) { return o.outDir + "/retrieval.csv"; }
std::string speedPath(const RetrievalOptions& o) { return o.outDir + "/retrieval_speed.csv"; }

// An image to describe: its pixels, the camera mdBRIEF uses (null: the photo camera) and where
// keypoints may be (empty: anywhere).
struct ImageToDescribe {
  const cv::Mat* grey;
  CameraPtr camera;
  cv::Mat region;
};

struct Query {
  size_t group;
  uint32_t expected;  // the database entry of the query's sequence
  ImageToDescribe image;
};

std::vector<vocab::TrainingImage> describeAll(const std::vector<ImageToDescribe>& images,
                                              const vocab::FeatureOptions& features) {
  std::vector<vocab::TrainingImage> out(images.size());
  tbb::parallel_for(size_t(0), images.size(), [&](size_t i) {
    out[i] = vocab::describeImage(*images[i].grey, features, images[i].camera, images[i].region);
  });
  return out;
}

// Load time of a file: the best of `repeats` reads (the file in the page cache, as a program
// that starts again finds it).
template <typename Load>
double bestLoadMs(Load&& load, int repeats) {
  double best = 1e300;
  for (int r = 0; r < repeats; ++r) {
    const auto start = Clock::now();
    load();
    best = std::min(best, msSince(start));
  }
  return best;
}

}  // namespace

void runRetrieval(const std::vector<EvalGroup>& groups, const std::vector<std::string>& trainingImages,
                  const std::vector<std::string>& distractors, const RetrievalOptions& options) {
  if (options.recallAt.empty()) throw InputError("--recall-at: at least one k");
  const int maxK = *std::max_element(options.recallAt.begin(), options.recallAt.end());

  // Database: the first image of every sequence, then the distractors; queries: the others.
  std::vector<ImageToDescribe> database;
  std::vector<Query> queries;
  for (size_t g = 0; g < groups.size(); ++g)
    for (const auto& s : groups[g].sequences) {
      if (s.images.empty()) continue;
      const auto region = [&](size_t i) { return s.regions.empty() ? cv::Mat() : s.regions[i]; };
      const auto entry = static_cast<uint32_t>(database.size());
      database.push_back({&s.images[0], s.camera, region(0)});
      for (size_t i = 1; i < s.images.size(); ++i) queries.push_back({g, entry, {&s.images[i], s.camera, region(i)}});
    }
  const size_t sequenceEntries = database.size();

  // The training images pass the held-out check (no evaluation image); the distractors must not
  // be among them either.
  const train::HeldOutImages& heldOut = train::shippedHeldOutImages();
  std::vector<cv::Mat> trainingGrey(trainingImages.size()), distractorGrey(distractors.size());
  std::vector<uint64_t> trainingDigests(trainingImages.size());
  std::vector<std::pair<uint64_t, std::string>> distractorDigests(distractors.size());
  std::vector<std::string> errors(trainingImages.size() + distractors.size());
  tbb::parallel_for(size_t(0), errors.size(), [&](size_t i) {
    try {
      if (i < trainingImages.size()) {
        trainingGrey[i] = vocab::readTrainingImage(trainingImages[i], heldOut, trainingDigests[i]);
      } else {
        const size_t d = i - trainingImages.size();
        distractorGrey[d] = vocab::readTrainingImage(distractors[d], {}, distractorDigests[d].first);
        distractorDigests[d].second = distractors[d];
      }
    } catch (const std::exception& e) {
      errors[i] = e.what();
    }
  });
  for (const auto& e : errors)
    if (!e.empty()) throw InputError(e);
  std::vector<uint64_t> sortedTraining = trainingDigests;
  std::sort(sortedTraining.begin(), sortedTraining.end());
  for (const auto& [digest, path] : distractorDigests)
    if (std::binary_search(sortedTraining.begin(), sortedTraining.end(), digest))
      throw InputError(path + ": a distractor that is also a training image (by content)");
  for (const auto& grey : distractorGrey) database.push_back({&grey, nullptr, {}});
  std::vector<ImageToDescribe> training;
  for (const auto& grey : trainingGrey) training.push_back({&grey, nullptr, {}});
  std::vector<ImageToDescribe> queryImages;
  for (const auto& q : queries) queryImages.push_back(q.image);
  std::printf("retrieval: %zu training images, database %zu sequences + %zu distractors, %zu queries\n",
              training.size(), sequenceEntries, distractors.size(), queries.size());

  std::vector<std::string> header{"method", "group", "words", "queries"};
  for (int k : options.recallAt) header.push_back("recall_at_" + std::to_string(k));
  CsvTable recall(header);
  CsvTable speed({"method", "words", "bits", "database_entries", "query_features", "transform_ms_per_1000_features",
                  "query_ms", "binary_bytes", "binary_load_ms", "dbow2_text_bytes", "dbow2_text_load_ms"});
  fs::create_directories(options.outDir);

  struct Described {
    std::vector<vocab::TrainingImage> training, database, queries;
  };
  for (const auto kind : {vocab::FeatureKind::MdBrief, vocab::FeatureKind::Orb}) {
    vocab::FeatureOptions features;
    features.kind = kind;
    features.nfeatures = options.nfeatures;
    Described described{describeAll(training, features), describeAll(database, features),
                        describeAll(queryImages, features)};
    // The vocabulary records its training images, so later evaluations can refuse them.
    for (size_t i = 0; i < trainingDigests.size(); ++i) described.training[i].digest = trainingDigests[i];
    for (const Method& m : kMethods) {
      if (m.kind != kind) continue;
      vocab::VocabularyTrainingOptions trainingOptions = options.training;
      trainingOptions.masked = m.masked;
      const auto trainStart = Clock::now();
      const Vocabulary v = vocab::trainVocabulary(described.training, trainingOptions);
      std::printf("retrieval: %s: %zu words trained in %.1f s\n", m.name, v.wordCount(), msSince(trainStart) / 1000);
      const auto masksOf = [&](const vocab::TrainingImage& im) { return m.masked ? im.masks : cv::Mat(); };

      Database db(v);
      for (const auto& im : described.database) db.addDescriptors(im.descriptors, masksOf(im));
      std::vector<std::vector<int>> right(groups.size() + 1, std::vector<int>(options.recallAt.size(), 0));
      std::vector<int> counts(groups.size() + 1, 0);
      double transformMs = 0, queryMs = 0;
      size_t queryFeatures = 0;
      for (size_t q = 0; q < queries.size(); ++q) {
        const auto& im = described.queries[q];
        const auto t0 = Clock::now();
        const BowVector bow = v.transform(im.descriptors, masksOf(im)).bow;
        transformMs += msSince(t0);
        queryFeatures += static_cast<size_t>(im.descriptors.rows);
        const auto t1 = Clock::now();
        const std::vector<QueryResult> results = db.query(bow, maxK);
        queryMs += msSince(t1);
        for (const size_t g : {queries[q].group, groups.size()}) {
          ++counts[g];
          for (size_t k = 0; k < options.recallAt.size(); ++k) {
            const size_t top = std::min(results.size(), static_cast<size_t>(options.recallAt[k]));
            right[g][k] += std::any_of(results.begin(), results.begin() + static_cast<std::ptrdiff_t>(top),
                                       [&](const QueryResult& r) { return r.entry == queries[q].expected; });
          }
        }
      }
      for (size_t g = 0; g <= groups.size(); ++g) {
        if (counts[g] == 0) continue;
        recall.row().add(m.name).add(g < groups.size() ? groups[g].name : "all").add(static_cast<int>(v.wordCount()));
        recall.add(counts[g]);
        for (size_t k = 0; k < options.recallAt.size(); ++k) recall.add(static_cast<double>(right[g][k]) / counts[g]);
      }

      const std::string binary = binaryPath(options, m);
      v.save(binary);
      const double binaryMs = bestLoadMs([&] { Vocabulary::load(binary); }, 5);
      double textMs = -1, textBytes = -1;
      if (!v.masked()) {
        const std::string text = textPath(options, m);
        exportDbow2Text(v, text);
        textMs = bestLoadMs([&] { importDbow2Text(text); }, 1);
        textBytes = static_cast<double>(fs::file_size(text));
      }
      const double perQuery = queries.empty() ? 0 : 1.0 / static_cast<double>(queries.size());
      speed.row().add(m.name).add(static_cast<int>(v.wordCount())).add(v.bits()).add(static_cast<int>(db.size()));
      speed.add(static_cast<double>(queryFeatures) * perQuery);
      speed.add(queryFeatures ? transformMs * 1000.0 / static_cast<double>(queryFeatures) : 0.0);
      speed.add(queryMs * perQuery).add(static_cast<double>(fs::file_size(binary))).add(binaryMs);
      speed.add(textBytes).add(textMs);
      std::printf("retrieval: %s: recall@%d %.3f over %d queries\n", m.name, options.recallAt[0],
                  counts[groups.size()] ? static_cast<double>(right[groups.size()][0]) / counts[groups.size()] : 0.0,
                  counts[groups.size()]);
    }
  }
  recall.write(recallPath(options));
  speed.write(speedPath(options));
}

std::vector<std::string> retrievalOutputs(const RetrievalOptions& options) {
  std::vector<std::string> out{recallPath(options), speedPath(options)};
  for (const Method& m : kMethods) {
    out.push_back(binaryPath(options, m));
    if (!m.masked) out.push_back(textPath(options, m));
  }
  return out;
}

}  // namespace mdbrief::eval

#include "mdbrief/match/guided_matcher.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "match/match_inputs.hpp"
#include "match/matcher_kernels.hpp"
#include "mdbrief/match/masked_hamming.hpp"
#include "match/query_row.hpp"

namespace mdbrief {

namespace {

// The train keypoints by grid cell, in compressed rows: cell c holds entry[start[c] ..
// start[c + 1]), in increasing keypoint order. Entries carry their positions, so a search reads
// one contiguous run per cell instead of following indices into the keypoints.
class Grid {
 public:
  Grid(const std::vector<cv::KeyPoint>& keypoints, cv::Size imageSize, float radius) {
    const double area = static_cast<double>(imageSize.width) * imageSize.height;
    // Cells about the radius wide, but never smaller than one keypoint's share of the image:
    // a tiny radius would otherwise give millions of empty cells to allocate and clear.
    cell_ = std::max({static_cast<double>(radius), std::sqrt(area / std::max<size_t>(keypoints.size(), 1)), 1.0});
    cols_ = static_cast<int>(std::ceil(imageSize.width / cell_));
    rows_ = static_cast<int>(std::ceil(imageSize.height / cell_));
    start_.assign(static_cast<size_t>(cols_) * rows_ + 1, 0);
    std::vector<int> cellOf(keypoints.size());
    for (size_t i = 0; i < keypoints.size(); ++i) {
      cellOf[i] = cellIndex(column(keypoints[i].pt.x), row(keypoints[i].pt.y));
      ++start_[cellOf[i] + 1];
    }
    for (size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    // Counting sort; visiting keypoints in order keeps each cell sorted by index.
    entry_.resize(keypoints.size());
    std::vector<int> next(start_.begin(), start_.end() - 1);
    for (size_t i = 0; i < keypoints.size(); ++i)
      entry_[next[cellOf[i]]++] = {keypoints[i].pt, static_cast<int>(i)};
  }

  // Calls visit(train index) for every keypoint within `radius` of p (border included).
  template <typename Visit>
  void forEachWithin(cv::Point2f p, float radius, Visit visit) const {
    const int c0 = column(p.x - radius), c1 = column(p.x + radius);
    const int r0 = row(p.y - radius), r1 = row(p.y + radius);
    const float r2 = radius * radius;
    for (int r = r0; r <= r1; ++r) {
      // The cells of one grid row are adjacent in entry_: one run per row.
      const Entry* e = entry_.data() + start_[cellIndex(c0, r)];
      const Entry* end = entry_.data() + start_[cellIndex(c1, r) + 1];
      for (; e != end; ++e) {
        const float dx = e->pt.x - p.x, dy = e->pt.y - p.y;
        if (dx * dx + dy * dy <= r2) visit(e->index);
      }
    }
  }

 private:
  struct Entry {
    cv::Point2f pt;
    int index;
  };

  // Positions outside the image (train keypoints may lie there) fall into the border cells.
  int column(float x) const { return clampedCell(x, cols_); }
  int row(float y) const { return clampedCell(y, rows_); }
  int clampedCell(float v, int count) const {
    const double c = std::floor(v / cell_);
    return static_cast<int>(std::clamp(c, 0.0, static_cast<double>(count - 1)));
  }
  int cellIndex(int c, int r) const { return r * cols_ + c; }

  double cell_;
  int cols_, rows_;
  std::vector<int> start_;
  std::vector<Entry> entry_;
};

using namespace matcher_kernels;

// The train rows packed once per call, row-major, for the kernels' distancesRows: words,
// effective masks (all-zero -> all ones) and weights.
struct TrainRows {
  std::vector<uint32_t> desc, mask, weight;  // mask/weight only when masked
  TrainView view;
};

TrainRows packRows(const cv::Mat& desc, const cv::Mat* masks) {
  TrainRows t;
  const int count = desc.rows, nwords = desc.cols / 4;
  t.desc.resize(static_cast<size_t>(count) * nwords);
  if (masks) {
    t.mask.resize(t.desc.size());
    t.weight.resize(count);
  }
  for (int j = 0; j < count; ++j) {
    const uint8_t* p = desc.ptr<uint8_t>(j);
    for (int k = 0; k < nwords; ++k) t.desc[static_cast<size_t>(j) * nwords + k] = rowWord(p, k);
    if (masks) {
      t.weight[j] = effectiveMaskWords(masks->ptr<uint8_t>(j), nwords, &t.mask[static_cast<size_t>(j) * nwords]);
    }
  }
  t.view = {t.desc.data(), masks ? t.mask.data() : nullptr, masks ? t.weight.data() : nullptr, count, nwords, 1};
  return t;
}

// A number as a message prints it: "-1", "nan", "0.5".
std::string text(float v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

// Angle difference on the circle, in degrees: in [0, 180].
float angleDifference(float a, float b) {
  const float d = std::fmod(std::fabs(a - b), 360.f);
  return d > 180.f ? 360.f - d : d;
}

void checkCount(size_t count, int rows, const char* name, const char* descName) {
  if (count != static_cast<size_t>(rows)) {
    throw std::invalid_argument(std::string(name) + ": " + std::to_string(count) + " given for " +
                                std::to_string(rows) + " " + descName + " rows");
  }
}

// The consistency checks need what OpenCV marks as unknown: angle -1, size 0.
void checkKeypointFields(const std::vector<cv::KeyPoint>& keypoints, const char* name, const GuidedMatchOptions& o) {
  for (size_t i = 0; i < keypoints.size(); ++i) {
    const cv::KeyPoint& k = keypoints[i];
    if (o.maxAngleDifference && !(k.angle >= 0 && std::isfinite(k.angle))) {
      throw std::invalid_argument(std::string(name) + "[" + std::to_string(i) + "]: angle " + text(k.angle) +
                                  " is unknown, which maxAngleDifference needs");
    }
    if (o.maxScaleRatio && !(k.size > 0 && std::isfinite(k.size))) {
      throw std::invalid_argument(std::string(name) + "[" + std::to_string(i) + "]: size " + text(k.size) +
                                  " is not positive, which maxScaleRatio needs");
    }
  }
}

std::vector<cv::DMatch> match(const cv::Mat& query, const cv::Mat* queryMasks,
                              const std::vector<cv::KeyPoint>& queryKeypoints,
                              const std::vector<cv::Point2f>& predicted, const cv::Mat& train,
                              const cv::Mat* trainMasks, const std::vector<cv::KeyPoint>& trainKeypoints,
                              cv::Size imageSize, const GuidedMatchOptions& options) {
  validate(options);
  checkDescriptorPair(query, train);
  if (queryMasks) checkMasks(*queryMasks, query, "queryMasks", "query");
  if (trainMasks) checkMasks(*trainMasks, train, "trainMasks", "train");
  checkCount(predicted.size(), query.rows, "predicted", "query");
  checkCount(trainKeypoints.size(), train.rows, "trainKeypoints", "train");
  const bool checksKeypoints = options.maxAngleDifference || options.maxScaleRatio;
  if (checksKeypoints || !queryKeypoints.empty()) {
    checkCount(queryKeypoints.size(), query.rows, "queryKeypoints", "query");
  }
  if (imageSize.width < 1 || imageSize.height < 1) {
    throw std::invalid_argument("imageSize: " + std::to_string(imageSize.width) + "x" +
                                std::to_string(imageSize.height) + " has no pixels");
  }
  for (size_t i = 0; i < trainKeypoints.size(); ++i) {
    const cv::Point2f p = trainKeypoints[i].pt;
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) {
      throw std::invalid_argument("trainKeypoints[" + std::to_string(i) + "]: position (" + text(p.x) + ", " +
                                  text(p.y) + ") is not finite");
    }
  }
  checkKeypointFields(queryKeypoints, "queryKeypoints", options);
  checkKeypointFields(trainKeypoints, "trainKeypoints", options);
  if (query.empty() || train.empty()) return {};

  const Grid grid(trainKeypoints, imageSize, options.radius);
  const MatcherKernels kernel = activeMatcherKernels();  // resolved once per call
  const TrainRows rows = packRows(train, trainMasks);
  const int nwords = query.cols / 4;
  const bool masked = queryMasks != nullptr;
  auto consistent = [&](int q, int t) {
    const cv::KeyPoint &a = queryKeypoints[q], &b = trainKeypoints[t];
    if (options.maxAngleDifference && !(angleDifference(a.angle, b.angle) <= *options.maxAngleDifference)) return false;
    return !options.maxScaleRatio || std::max(a.size, b.size) <= *options.maxScaleRatio * std::min(a.size, b.size);
  };
  // Calls visit(train) for each candidate of query q: in its window and consistent.
  auto forEachCandidate = [&](int q, auto visit) {
    const cv::Point2f p = predicted[q];
    // Also excludes NaN: every comparison with it is false.
    if (!(p.x >= 0 && p.x < imageSize.width && p.y >= 0 && p.y < imageSize.height)) return;
    grid.forEachWithin(p, options.radius, [&](int t) {
      if (!checksKeypoints || consistent(q, t)) visit(t);
    });
  };
  auto forQueries = [&](auto run) {
    if (options.matching.parallel) {
      // Each query is handled by exactly one task, so the split does not change the results.
      tbb::parallel_for(tbb::blocked_range<int>(0, query.rows, 64), [&](const tbb::blocked_range<int>& r) {
        for (int q = r.begin(); q < r.end(); ++q) run(q);
      });
    } else {
      for (int q = 0; q < query.rows; ++q) run(q);
    }
  };

  // Every query's candidates and their distances, in one array (query q's from offset[q]), kept
  // for the mutual check: counted first, so no list per query is allocated.
  std::vector<int> offset(query.rows + 1, 0);
  forQueries([&](int q) { forEachCandidate(q, [&](int) { ++offset[q + 1]; }); });
  for (int q = 0; q < query.rows; ++q) offset[q + 1] += offset[q];
  std::vector<int> candidate(offset.back());
  std::vector<uint32_t> distance(offset.back());  // Hamming bits or the masked fixed point
  forQueries([&](int q) {
    int n = 0;
    forEachCandidate(q, [&](int t) { candidate[offset[q] + n++] = t; });
    if (n > 0) {
      kernel.distancesRows(loadQueryRow(query, queryMasks, q, nwords), rows.view, candidate.data() + offset[q], n,
                           distance.data() + offset[q]);
    }
  });

  // Each train's nearest query: queries in increasing order with a strict <, so the lowest
  // index wins a tie.
  constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();
  std::vector<int> nearestQuery;
  if (options.matching.crossCheck) {
    nearestQuery.assign(train.rows, -1);
    std::vector<uint32_t> nearestDistance(train.rows, kNone);
    for (int q = 0; q < query.rows; ++q)
      for (int i = offset[q]; i < offset[q + 1]; ++i)
        if (distance[i] < nearestDistance[candidate[i]]) {  // every distance is below kNone
          nearestDistance[candidate[i]] = distance[i];
          nearestQuery[candidate[i]] = q;
        }
  }

  const MatchOptions& m = options.matching;
  std::vector<cv::DMatch> matches;
  for (int q = 0; q < query.rows; ++q) {
    // The two nearest, ordered by (distance, train index): the grid visits cells, not indices.
    int best = -1;
    uint32_t bestDistance = kNone, secondDistance = kNone;
    bool hasSecond = false;
    for (int i = offset[q]; i < offset[q + 1]; ++i) {
      const int t = candidate[i];
      const uint32_t d = distance[i];
      if (best < 0 || d < bestDistance || (d == bestDistance && t < best)) {
        if (best >= 0) {
          secondDistance = bestDistance;
          hasSecond = true;
        }
        best = t;
        bestDistance = d;
      } else if (!hasSecond || d < secondDistance) {
        secondDistance = d;
        hasSecond = true;
      }
    }
    if (best < 0) continue;
    const float bits = masked ? maskedFixedToBits(bestDistance) : static_cast<float>(bestDistance);
    // Ratio on the exact integers, as matchBruteForce; a single candidate passes.
    if (m.ratio && hasSecond &&
        !(static_cast<double>(bestDistance) < static_cast<double>(*m.ratio) * secondDistance)) {
      continue;
    }
    if (m.maxDistance && !(bits <= *m.maxDistance)) continue;
    if (m.crossCheck && nearestQuery[best] != q) continue;
    matches.emplace_back(q, best, 0, bits);
  }
  return matches;
}

}  // namespace

std::vector<cv::DMatch> matchGuided(cv::InputArray query, const std::vector<cv::KeyPoint>& queryKeypoints,
                                    const std::vector<cv::Point2f>& predicted, cv::InputArray train,
                                    const std::vector<cv::KeyPoint>& trainKeypoints, cv::Size imageSize,
                                    const GuidedMatchOptions& options) {
  return match(query.getMat(), nullptr, queryKeypoints, predicted, train.getMat(), nullptr, trainKeypoints, imageSize,
               options);
}

std::vector<cv::DMatch> matchGuidedMasked(cv::InputArray query, cv::InputArray queryMasks,
                                          const std::vector<cv::KeyPoint>& queryKeypoints,
                                          const std::vector<cv::Point2f>& predicted, cv::InputArray train,
                                          cv::InputArray trainMasks, const std::vector<cv::KeyPoint>& trainKeypoints,
                                          cv::Size imageSize, const GuidedMatchOptions& options) {
  const cv::Mat queryMaskRows = queryMasks.getMat(), trainMaskRows = trainMasks.getMat();
  return match(query.getMat(), &queryMaskRows, queryKeypoints, predicted, train.getMat(), &trainMaskRows,
               trainKeypoints, imageSize, options);
}

}  // namespace mdbrief

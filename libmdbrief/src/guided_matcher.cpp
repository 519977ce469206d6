#include "mdbrief/guided_matcher.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "mdbrief/hamming.hpp"
#include "mdbrief/masked_hamming.hpp"

namespace mdbrief {

namespace {

// The train keypoints by grid cell, in compressed rows: cell c holds index[start[c] ..
// start[c + 1]), in increasing keypoint order.
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
    index_.resize(keypoints.size());
    std::vector<int> next(start_.begin(), start_.end() - 1);
    for (size_t i = 0; i < keypoints.size(); ++i) index_[next[cellOf[i]]++] = static_cast<int>(i);
  }

  // Calls visit(train index) for every keypoint of the cells that overlap the square around p.
  template <typename Visit>
  void forEachNear(cv::Point2f p, float radius, Visit visit) const {
    const int c0 = column(p.x - radius), c1 = column(p.x + radius);
    const int r0 = row(p.y - radius), r1 = row(p.y + radius);
    for (int r = r0; r <= r1; ++r)
      for (int c = c0; c <= c1; ++c) {
        const int cell = cellIndex(c, r);
        for (int k = start_[cell]; k < start_[cell + 1]; ++k) visit(index_[k]);
      }
  }

 private:
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
  std::vector<int> start_, index_;
};

struct Candidate {
  int train;
  uint32_t distance;  // Hamming bits, or the masked fixed-point distance (masked_hamming.hpp)
};

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

void checkMasks(const cv::Mat& masks, const cv::Mat& desc, const char* name, const char* descName) {
  if (masks.empty() && desc.empty()) return;
  if (masks.size() != desc.size()) {
    throw std::invalid_argument(std::string(name) + ": size " + std::to_string(masks.rows) + "x" +
                                std::to_string(masks.cols) + " differs from " + descName + "'s " +
                                std::to_string(desc.rows) + "x" + std::to_string(desc.cols));
  }
  if (masks.type() != CV_8UC1) {
    throw std::invalid_argument(std::string(name) + ": masks must be CV_8UC1, got " + cv::typeToString(masks.type()));
  }
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
  validateDescriptorMatrix(query, "query");
  validateDescriptorMatrix(train, "train");
  if (!query.empty() && !train.empty() && query.cols != train.cols) {
    throw std::invalid_argument("train: width " + std::to_string(train.cols) + " bytes differs from query's " +
                                std::to_string(query.cols));
  }
  if (queryMasks) checkMasks(*queryMasks, query, "queryMasks", "query");
  if (trainMasks) checkMasks(*trainMasks, train, "trainMasks", "train");
  checkCount(predicted.size(), query.rows, "predicted", "query");
  checkCount(trainKeypoints.size(), train.rows, "trainKeypoints", "train");
  const bool checksKeypoints = options.maxAngleDifference || options.maxScaleRatio;
  if (checksKeypoints || !queryKeypoints.empty()) checkCount(queryKeypoints.size(), query.rows, "queryKeypoints", "query");
  if (imageSize.width < 1 || imageSize.height < 1) {
    throw std::invalid_argument("imageSize: " + std::to_string(imageSize.width) + "x" +
                                std::to_string(imageSize.height) + " has no pixels");
  }
  for (size_t i = 0; i < trainKeypoints.size(); ++i) {
    const cv::Point2f p = trainKeypoints[i].pt;
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) {
      throw std::invalid_argument("trainKeypoints[" + std::to_string(i) + "]: position (" + text(p.x) + ", " + text(p.y) +
                                  ") is not finite");
    }
  }
  checkKeypointFields(queryKeypoints, "queryKeypoints", options);
  checkKeypointFields(trainKeypoints, "trainKeypoints", options);
  if (query.empty() || train.empty()) return {};

  const Grid grid(trainKeypoints, imageSize, options.radius);
  const int bytes = query.cols;
  const bool masked = queryMasks != nullptr;
  const float radius = options.radius;
  auto distance = [&](int q, int t) -> uint32_t {
    if (masked) {
      return maskedHammingFixed(query.ptr<uint8_t>(q), queryMasks->ptr<uint8_t>(q), train.ptr<uint8_t>(t),
                                trainMasks->ptr<uint8_t>(t), bytes);
    }
    return static_cast<uint32_t>(hammingDistance(query.ptr<uint8_t>(q), train.ptr<uint8_t>(t), bytes));
  };
  auto consistent = [&](int q, int t) {
    const cv::KeyPoint &a = queryKeypoints[q], &b = trainKeypoints[t];
    if (options.maxAngleDifference && !(angleDifference(a.angle, b.angle) <= *options.maxAngleDifference)) return false;
    return !options.maxScaleRatio || std::max(a.size, b.size) <= *options.maxScaleRatio * std::min(a.size, b.size);
  };

  // Every query's candidates (window and consistency), kept for the mutual check.
  std::vector<std::vector<Candidate>> candidates(query.rows);
  auto collect = [&](int begin, int end) {
    for (int q = begin; q < end; ++q) {
      const cv::Point2f p = predicted[q];
      // Also excludes NaN: every comparison with it is false.
      if (!(p.x >= 0 && p.x < imageSize.width && p.y >= 0 && p.y < imageSize.height)) continue;
      grid.forEachNear(p, radius, [&](int t) {
        const cv::Point2f d = trainKeypoints[t].pt - p;
        if (d.x * d.x + d.y * d.y > radius * radius) return;
        if (checksKeypoints && !consistent(q, t)) return;
        candidates[q].push_back({t, distance(q, t)});
      });
    }
  };
  if (options.matching.parallel) {
    // Each query is handled by exactly one task, so the split does not change the results.
    tbb::parallel_for(tbb::blocked_range<int>(0, query.rows, 64),
                      [&](const tbb::blocked_range<int>& r) { collect(r.begin(), r.end()); });
  } else {
    collect(0, query.rows);
  }

  // Each train's nearest query: queries in increasing order with a strict <, so the lowest
  // index wins a tie.
  constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();
  std::vector<int> nearestQuery;
  if (options.matching.crossCheck) {
    nearestQuery.assign(train.rows, -1);
    std::vector<uint32_t> nearestDistance(train.rows, kNone);
    for (int q = 0; q < query.rows; ++q)
      for (const Candidate& c : candidates[q])
        if (c.distance < nearestDistance[c.train]) {  // every distance is below kNone
          nearestQuery[c.train] = q;
          nearestDistance[c.train] = c.distance;
        }
  }

  const MatchOptions& m = options.matching;
  std::vector<cv::DMatch> matches;
  for (int q = 0; q < query.rows; ++q) {
    // The two nearest, ordered by (distance, train index): the grid visits cells, not indices.
    int best = -1;
    uint32_t bestDistance = kNone, secondDistance = kNone;
    bool hasSecond = false;
    for (const Candidate& c : candidates[q]) {
      if (best < 0 || c.distance < bestDistance || (c.distance == bestDistance && c.train < best)) {
        if (best >= 0) {
          secondDistance = bestDistance;
          hasSecond = true;
        }
        best = c.train;
        bestDistance = c.distance;
      } else if (!hasSecond || c.distance < secondDistance) {
        secondDistance = c.distance;
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

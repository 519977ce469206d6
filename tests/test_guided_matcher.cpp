// Guided matcher against a slow windowed reference and against brute force.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "mdbrief/match/guided_matcher.hpp"
#include "mdbrief/match/hamming.hpp"
#include "mdbrief/match/masked_hamming.hpp"
#include "mdbrief/match/matcher.hpp"
#include "mdbrief/base/simd_level.hpp"

namespace {

using mdbrief::GuidedMatchOptions;
using mdbrief::matchGuided;
using mdbrief::matchGuidedMasked;

const cv::Size kImage(640, 480);

// A tracker's view: train keypoints spread over the image; every other query is a noisy copy
// of a train descriptor (its true match) with a prediction near the true position, the others
// are unrelated descriptors with random predictions. Masks have mdBRIEF-like densities.
struct Scene {
  cv::Mat query, queryMasks, train, trainMasks;
  std::vector<cv::KeyPoint> queryKeypoints, trainKeypoints;
  std::vector<cv::Point2f> predicted;
  std::vector<int> truth;  // the true train of each query, -1 for none
};

Scene makeScene(int nTrain, int nQuery, int bytes, float predictionError, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> byte(0, 255), bit(0, bytes * 8 - 1), octave(0, 3), pick(0, nTrain - 1);
  std::uniform_real_distribution<float> x(0.f, kImage.width - 1e-3f), y(0.f, kImage.height - 1e-3f),
      angle(0.f, 360.f), unit(0.f, 1.f);
  std::bernoulli_distribution keep(0.8);
  auto randomRows = [&](int rows) {
    cv::Mat m(rows, bytes, CV_8UC1);
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < bytes; ++c) m.at<uint8_t>(r, c) = static_cast<uint8_t>(byte(rng));
    return m;
  };
  auto maskRows = [&](int rows) {
    cv::Mat m(rows, bytes, CV_8UC1, cv::Scalar(0));
    for (int r = 0; r < rows; ++r) {
      if (r % 13 == 0) continue;  // all-zero masks count as all ones
      for (int d = 0; d < bytes * 8; ++d)
        if (keep(rng)) m.at<uint8_t>(r, d / 8) |= static_cast<uint8_t>(1u << (d % 8));
    }
    return m;
  };
  Scene s;
  s.train = randomRows(nTrain);
  s.trainMasks = maskRows(nTrain);
  for (int t = 0; t < nTrain; ++t)
    s.trainKeypoints.emplace_back(cv::Point2f(x(rng), y(rng)), 7.f * std::pow(1.2f, octave(rng)), angle(rng));
  s.query = randomRows(nQuery);
  s.queryMasks = maskRows(nQuery);
  for (int q = 0; q < nQuery; ++q) {
    if (q % 2 == 0) {
      const int t = pick(rng);
      s.truth.push_back(t);
      s.train.row(t).copyTo(s.query.row(q));
      for (int f = q % 11; f > 0; --f) {
        const int d = bit(rng);
        s.query.at<uint8_t>(q, d / 8) ^= static_cast<uint8_t>(1u << (d % 8));
      }
      const cv::KeyPoint& k = s.trainKeypoints[t];
      const float size = k.size * (q % 4 == 0 ? 1.f : 1.2f);
      s.queryKeypoints.emplace_back(k.pt, size, std::fmod(k.angle + 5.f * unit(rng), 360.f));
      const float r = predictionError * unit(rng), a = 6.2831853f * unit(rng);
      s.predicted.emplace_back(k.pt.x + r * std::cos(a), k.pt.y + r * std::sin(a));
    } else {
      s.truth.push_back(-1);
      s.queryKeypoints.emplace_back(cv::Point2f(x(rng), y(rng)), 7.f * std::pow(1.2f, octave(rng)), angle(rng));
      s.predicted.emplace_back(x(rng), y(rng));
    }
  }
  return s;
}

float angleDifference(float a, float b) {
  float d = std::fabs(a - b);
  while (d >= 360.f) d -= 360.f;
  return std::min(d, 360.f - d);
}

// Obviously-correct guided matcher: every pair is tested against the window and the checks;
// nearest by (distance, index); the mutual check over the same pairs, all queries in order.
std::vector<cv::DMatch> referenceGuided(const Scene& s, bool masked, const GuidedMatchOptions& o) {
  const int nq = s.query.rows, nt = s.train.rows, bytes = s.query.cols;
  auto candidate = [&](int q, int t) {
    const cv::Point2f p = s.predicted[q];
    if (!(p.x >= 0 && p.x < kImage.width && p.y >= 0 && p.y < kImage.height)) return false;
    const float dx = s.trainKeypoints[t].pt.x - p.x, dy = s.trainKeypoints[t].pt.y - p.y;
    if (dx * dx + dy * dy > o.radius * o.radius) return false;
    const cv::KeyPoint &a = s.queryKeypoints[q], &b = s.trainKeypoints[t];
    if (o.maxAngleDifference && angleDifference(a.angle, b.angle) > *o.maxAngleDifference) return false;
    return !o.maxScaleRatio || std::max(a.size / b.size, b.size / a.size) <= *o.maxScaleRatio;
  };
  auto distance = [&](int q, int t) -> uint32_t {
    if (masked)
      return mdbrief::maskedHammingFixed(s.query.ptr<uint8_t>(q), s.queryMasks.ptr<uint8_t>(q), s.train.ptr<uint8_t>(t),
                                         s.trainMasks.ptr<uint8_t>(t), bytes);
    int count = 0;
    for (int d = 0; d < bytes * 8; ++d)
      count += ((s.query.at<uint8_t>(q, d / 8) ^ s.train.at<uint8_t>(t, d / 8)) >> (d % 8)) & 1;
    return static_cast<uint32_t>(count);
  };
  std::vector<cv::DMatch> out;
  for (int q = 0; q < nq; ++q) {
    int best = -1;
    uint64_t bestD = UINT64_MAX, secondD = UINT64_MAX;
    for (int t = 0; t < nt; ++t) {
      if (!candidate(q, t)) continue;
      const uint64_t d = distance(q, t);
      if (d < bestD) {
        secondD = bestD;
        bestD = d;
        best = t;
      } else if (d < secondD) {
        secondD = d;
      }
    }
    if (best < 0) continue;
    const float bits = masked ? mdbrief::maskedFixedToBits(static_cast<uint32_t>(bestD)) : static_cast<float>(bestD);
    const auto& ratio = o.matching.ratio;
    if (ratio && secondD != UINT64_MAX && !(bestD < *ratio * static_cast<double>(secondD))) continue;
    if (o.matching.maxDistance && !(bits <= *o.matching.maxDistance)) continue;
    if (o.matching.crossCheck) {
      int back = -1;
      uint64_t backD = UINT64_MAX;
      for (int r = 0; r < nq; ++r)
        if (candidate(r, best) && distance(r, best) < backD) {
          backD = distance(r, best);
          back = r;
        }
      if (back != q) continue;
    }
    out.emplace_back(q, best, 0, bits);
  }
  return out;
}

std::vector<cv::DMatch> guided(const Scene& s, bool masked, const GuidedMatchOptions& o) {
  if (masked)
    return matchGuidedMasked(s.query, s.queryMasks, s.queryKeypoints, s.predicted, s.train, s.trainMasks,
                             s.trainKeypoints, kImage, o);
  return matchGuided(s.query, s.queryKeypoints, s.predicted, s.train, s.trainKeypoints, kImage, o);
}

void expectSameMatches(const std::vector<cv::DMatch>& a, const std::vector<cv::DMatch>& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].queryIdx, b[i].queryIdx) << what << " match " << i;
    EXPECT_EQ(a[i].trainIdx, b[i].trainIdx) << what << " match " << i;
    EXPECT_EQ(a[i].distance, b[i].distance) << what << " match " << i;
  }
}

std::string messageOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no exception";
}

TEST(GuidedMatcher, EqualsWindowedReferenceForEveryOptionCombination) {
  // Dense enough that windows hold several candidates and the checks decide; 36 bytes has a
  // tail word after the 64-bit counts.
  for (int bytes : {32, 36}) {
    const Scene s = makeScene(600, 400, bytes, 12.f, 7 + bytes);
    for (bool masked : {false, true})
      for (int combo = 0; combo < 32; ++combo) {
        GuidedMatchOptions o;
        o.radius = (combo & 1) ? 30.f : 15.f;
        if (combo & 2) o.matching.ratio.reset();
        o.matching.crossCheck = (combo & 4) != 0;
        if (combo & 8) {
          o.maxAngleDifference = 3.f;
          o.maxScaleRatio = 1.1f;
        }
        if (combo & 16) o.matching.maxDistance = 40.f;
        o.matching.parallel = (combo % 3) != 0;
        const std::string what = std::string(masked ? "masked" : "plain") + " bytes " + std::to_string(bytes) +
                                 " combo " + std::to_string(combo);
        const auto matches = guided(s, masked, o);
        expectSameMatches(matches, referenceGuided(s, masked, o), what);
        EXPECT_GT(matches.size(), 20u) << what;  // the comparison is not vacuous
      }
  }
}

TEST(GuidedMatcher, KeepsEveryRightBruteForceMatchWhosePredictionIsWithinTheRadius) {
  for (bool masked : {false, true})
    for (int bytes : {32, 64}) {
      // Prediction errors up to 20 px against a 15 px radius: some true matches fall outside.
      const Scene s = makeScene(1000, 1000, bytes, 20.f, 11 + bytes);
      const GuidedMatchOptions o;  // the library's defaults: ratio test and mutual check
      const auto bf = masked ? mdbrief::matchBruteForceMasked(s.query, s.queryMasks, s.train, s.trainMasks, o.matching)
                             : mdbrief::matchBruteForce(s.query, s.train, o.matching);
      const auto g = guided(s, masked, o);
      std::vector<int> guidedTrain(s.query.rows, -1);
      std::vector<float> guidedDistance(s.query.rows, -1.f);
      for (const cv::DMatch& m : g) {
        guidedTrain[m.queryIdx] = m.trainIdx;
        guidedDistance[m.queryIdx] = m.distance;
      }
      int checked = 0, outside = 0;
      for (const cv::DMatch& m : bf) {
        if (m.trainIdx != s.truth[m.queryIdx]) continue;
        // A prediction outside the image has no candidates, however near its true match.
        const cv::Point2f p = s.predicted[m.queryIdx], d = s.trainKeypoints[m.trainIdx].pt - p;
        if (std::hypot(d.x, d.y) > o.radius || !cv::Rect2f(0.f, 0.f, kImage.width, kImage.height).contains(p)) {
          ++outside;
          continue;
        }
        ++checked;
        EXPECT_EQ(guidedTrain[m.queryIdx], m.trainIdx) << "query " << m.queryIdx << " bytes " << bytes;
        EXPECT_EQ(guidedDistance[m.queryIdx], m.distance) << "query " << m.queryIdx << " bytes " << bytes;
      }
      EXPECT_GT(checked, 200) << bytes;
      EXPECT_GT(outside, 20) << bytes;  // the radius and the border do cut some true matches
    }
}

TEST(GuidedMatcher, PredictionsOutsideTheImageHaveNoCandidates) {
  cv::Mat train(4, 32, CV_8UC1, cv::Scalar(0x5a));
  // Keypoints at the corners and one just outside the image (allowed: it can be matched).
  const std::vector<cv::KeyPoint> trainKeypoints = {cv::KeyPoint(0.f, 0.f, 7.f), cv::KeyPoint(639.9f, 479.9f, 7.f),
                                                    cv::KeyPoint(0.f, 479.9f, 7.f), cv::KeyPoint(-3.f, 200.f, 7.f)};
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<cv::Point2f> outside = {{-0.01f, 0.f}, {640.f, 479.f}, {0.f, 480.f}, {-1e30f, 1e30f},
                                            {nan, 10.f},  {10.f, nan},     {inf, 0.f},  {-inf, -inf}};
  const cv::Mat query = cv::repeat(train.row(0), static_cast<int>(outside.size()), 1);
  GuidedMatchOptions o;
  o.matching.ratio.reset();
  o.matching.crossCheck = false;
  for (float radius : {0.f, 15.f, 10000.f}) {
    o.radius = radius;
    EXPECT_TRUE(matchGuided(query, {}, outside, train, trainKeypoints, kImage, o).empty()) << radius;
  }
  // Inside by a hair, each corner finds its keypoint; the one outside the image is found too.
  o.radius = 5.f;
  const std::vector<cv::Point2f> inside = {{0.f, 0.f}, {639.99f, 479.99f}, {0.f, 479.f}, {1.f, 200.f}};
  const auto matches = matchGuided(query.rowRange(0, 4), {}, inside, train, trainKeypoints, kImage, o);
  ASSERT_EQ(matches.size(), 4u);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(matches[i].trainIdx, i);
}

TEST(GuidedMatcher, RadiusZeroKeepsOnlyKeypointsAtThePrediction) {
  const Scene s = makeScene(300, 200, 32, 0.f, 3);  // predictions exactly at the true positions
  GuidedMatchOptions o;
  o.radius = 0.f;
  const auto exact = guided(s, true, o);
  expectSameMatches(exact, referenceGuided(s, true, o), "radius 0");
  ASSERT_GT(exact.size(), 50u);
  for (const cv::DMatch& m : exact) EXPECT_EQ(m.trainIdx, s.truth[m.queryIdx]);
  Scene shifted = s;
  for (cv::Point2f& p : shifted.predicted) p.x += 0.01f;
  EXPECT_TRUE(guided(shifted, true, o).empty());
}

TEST(GuidedMatcher, TiesGoToTheLowestIndex) {
  // Trains 0..2 identical and in one window, train 1 in a grid cell visited before train 0's;
  // train 3 identical too but outside the window. 2000 distant others (256 bits away) make the
  // cells as small as the radius. Queries 0 and 1 identical, both predicting the same place.
  cv::Mat train(2004, 32, CV_8UC1, cv::Scalar(0xcc));
  train.rowRange(0, 4).setTo(0x33);
  std::vector<cv::KeyPoint> trainKeypoints = {cv::KeyPoint(100.f, 100.f, 7.f), cv::KeyPoint(80.f, 100.f, 7.f),
                                              cv::KeyPoint(120.f, 110.f, 7.f), cv::KeyPoint(300.f, 300.f, 7.f)};
  for (int i = 0; i < 2000; ++i) trainKeypoints.emplace_back(static_cast<float>(i % 640), 400.f + i / 640, 7.f);
  const cv::Mat query = cv::repeat(train.row(0), 2, 1);
  const std::vector<cv::Point2f> predicted = {{100.f, 100.f}, {100.f, 100.f}};
  GuidedMatchOptions o;
  o.radius = 25.f;
  o.matching.ratio.reset();
  for (bool parallel : {false, true}) {
    o.matching.parallel = parallel;
    o.matching.crossCheck = false;
    auto m = matchGuided(query, {}, predicted, train, trainKeypoints, kImage, o);
    ASSERT_EQ(m.size(), 2u);
    EXPECT_EQ(m[0].trainIdx, 0);
    EXPECT_EQ(m[1].trainIdx, 0);
    // Mutual: train 0's nearest query is query 0 (the lower of two equal ones).
    o.matching.crossCheck = true;
    m = matchGuided(query, {}, predicted, train, trainKeypoints, kImage, o);
    ASSERT_EQ(m.size(), 1u);
    EXPECT_EQ(m[0].queryIdx, 0);
    EXPECT_EQ(m[0].trainIdx, 0);
    // A tie also fails the ratio test, as in brute force (best < ratio * second).
    o.matching.ratio = 1.f;
    EXPECT_TRUE(matchGuided(query, {}, predicted, train, trainKeypoints, kImage, o).empty());
    o.matching.ratio.reset();
  }
}

TEST(GuidedMatcher, OrientationAndScaleChecksSkipInconsistentCandidates) {
  // Train 0 is the query's exact copy but turned or scaled; train 1 differs by 8 bits.
  cv::Mat train(2, 32, CV_8UC1, cv::Scalar(0));
  train.at<uint8_t>(1, 0) = 0xff;
  const cv::Mat query = train.row(0).clone();
  const std::vector<cv::Point2f> predicted = {{50.f, 50.f}};
  GuidedMatchOptions o;
  o.matching.ratio.reset();
  auto nearest = [&](const cv::KeyPoint& q, const cv::KeyPoint& t0, const cv::KeyPoint& t1) {
    const auto m = matchGuided(query, {q}, predicted, train, {t0, t1}, kImage, o);
    return m.empty() ? -1 : m[0].trainIdx;
  };
  const cv::KeyPoint q(50.f, 50.f, 10.f, 359.f);
  o.maxAngleDifference = 10.f;
  // 359 and 4 degrees differ by 5 on the circle; 359 and 30 by 31.
  EXPECT_EQ(nearest(q, cv::KeyPoint(50.f, 50.f, 10.f, 4.f), cv::KeyPoint(51.f, 50.f, 10.f, 355.f)), 0);
  EXPECT_EQ(nearest(q, cv::KeyPoint(50.f, 50.f, 10.f, 30.f), cv::KeyPoint(51.f, 50.f, 10.f, 355.f)), 1);
  EXPECT_EQ(nearest(q, cv::KeyPoint(50.f, 50.f, 10.f, 30.f), cv::KeyPoint(51.f, 50.f, 10.f, 180.f)), -1);
  o.maxAngleDifference.reset();
  o.maxScaleRatio = 1.5f;
  EXPECT_EQ(nearest(q, cv::KeyPoint(50.f, 50.f, 15.f, 0.f), cv::KeyPoint(51.f, 50.f, 10.f, 0.f)), 0);  // 1.5: kept
  EXPECT_EQ(nearest(q, cv::KeyPoint(50.f, 50.f, 6.f, 0.f), cv::KeyPoint(51.f, 50.f, 10.f, 0.f)), 1);   // 1.67
  // Off, the nearest descriptor wins whatever its orientation and size.
  o.maxScaleRatio.reset();
  EXPECT_EQ(nearest(q, cv::KeyPoint(50.f, 50.f, 60.f, 180.f), cv::KeyPoint(51.f, 50.f, 10.f, 359.f)), 0);
}

TEST(GuidedMatcher, SameResultWithAndWithoutThreads) {
  const Scene s = makeScene(5000, 5000, 32, 10.f, 5);
  GuidedMatchOptions o;
  o.maxAngleDifference = 20.f;
  for (bool masked : {false, true}) {
    o.matching.parallel = false;
    const auto serial = guided(s, masked, o);
    o.matching.parallel = true;
    expectSameMatches(guided(s, masked, o), serial, masked ? "masked" : "plain");
    EXPECT_GT(serial.size(), 1000u);
  }
}

TEST(GuidedMatcher, SameResultAtEverySimdLevel) {
  // The distances come from the dispatched kernels (matcher_kernels.hpp).
  const Scene s = makeScene(2000, 2000, 36, 10.f, 9);  // 36 bytes: an odd word count's tail
  GuidedMatchOptions o;
  o.matching.ratio.reset();
  o.matching.crossCheck = false;
  for (bool masked : {false, true}) {
    std::vector<cv::DMatch> reference;
    for (const mdbrief::SimdLevel level : mdbrief::supportedSimdLevels()) {
      mdbrief::limitSimdLevel(level);
      const auto matches = guided(s, masked, o);
      if (reference.empty()) {
        reference = matches;
        ASSERT_GT(reference.size(), 1000u);
      } else {
        expectSameMatches(matches, reference, mdbrief::toString(level));
      }
    }
    mdbrief::limitSimdLevel(mdbrief::SimdLevel::Avx512);  // no cap: the widest the CPU runs
  }
}

TEST(GuidedMatcher, EmptyInputsGiveNoMatches) {
  const cv::Mat rows(3, 32, CV_8UC1, cv::Scalar(1));
  const std::vector<cv::KeyPoint> keypoints(3, cv::KeyPoint(10.f, 10.f, 7.f));
  const std::vector<cv::Point2f> predicted(3, cv::Point2f(10.f, 10.f));
  EXPECT_TRUE(matchGuided(cv::Mat(), {}, {}, rows, keypoints, kImage).empty());
  EXPECT_TRUE(matchGuided(rows, {}, predicted, cv::Mat(), {}, kImage).empty());
  EXPECT_TRUE(matchGuided(cv::Mat(0, 32, CV_8UC1), {}, {}, cv::Mat(0, 32, CV_8UC1), {}, kImage).empty());
  EXPECT_TRUE(matchGuidedMasked(cv::Mat(), cv::Mat(), {}, {}, rows, rows, keypoints, kImage).empty());
  EXPECT_TRUE(matchGuidedMasked(rows, rows, {}, predicted, cv::Mat(), cv::Mat(), {}, kImage).empty());
  // The same inputs do match: the emptiness above is what gave no matches.
  EXPECT_EQ(matchGuided(rows.row(0), {}, {predicted[0]}, rows.row(0), {keypoints[0]}, kImage).size(), 1u);
}

TEST(GuidedMatcher, InvalidOptionsAreRefusedNamingTheOption) {
  const cv::Mat rows(1, 32, CV_8UC1, cv::Scalar(1));
  const std::vector<cv::KeyPoint> keypoints = {cv::KeyPoint(10.f, 10.f, 7.f)};
  const std::vector<cv::Point2f> predicted = {{10.f, 10.f}};
  auto run = [&](const GuidedMatchOptions& o) {
    return messageOf([&] { matchGuided(rows, keypoints, predicted, rows, keypoints, kImage, o); });
  };
  GuidedMatchOptions o;
  o.radius = -1.f;
  EXPECT_EQ(run(o), "GuidedMatchOptions::radius must be in [0, 10000], got -1");
  o.radius = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(run(o).rfind("GuidedMatchOptions::radius must be in [0, 10000], got ", 0), 0u) << run(o);
  o = {};
  o.maxAngleDifference = 0.f;
  EXPECT_EQ(run(o), "GuidedMatchOptions::maxAngleDifference must be in (0, 180], got 0");
  o = {};
  o.maxScaleRatio = 0.5f;
  EXPECT_EQ(run(o), "GuidedMatchOptions::maxScaleRatio must be in [1, 1000], got 0.5");
  o = {};
  o.matching.ratio = 0.f;
  EXPECT_EQ(run(o), "GuidedMatchOptions::matching.ratio must be in (0, 1], got 0");
  o = {};
  o.matching.maxDistance = 600.f;
  EXPECT_EQ(run(o), "GuidedMatchOptions::matching.maxDistance must be in [0, 512], got 600");
  // Every default is in its range, and spellings are unique.
  std::set<std::string> keywords;
  for (const auto& f : mdbrief::guidedMatchOptionFields()) {
    EXPECT_FALSE(mdbrief::fieldProblem(f, GuidedMatchOptions{})) << f.member;
    EXPECT_TRUE(keywords.insert(f.keyword).second) << f.keyword;
  }
}

TEST(GuidedMatcher, InvalidInputsAreRefusedNamingTheArgument) {
  const cv::Mat rows(2, 32, CV_8UC1, cv::Scalar(1));
  const std::vector<cv::KeyPoint> keypoints(2, cv::KeyPoint(10.f, 10.f, 7.f, 45.f));
  const std::vector<cv::Point2f> predicted(2, cv::Point2f(10.f, 10.f));
  EXPECT_EQ(messageOf([&] { matchGuided(rows, {}, {predicted[0]}, rows, keypoints, kImage); }),
            "predicted: 1 given for 2 query rows");
  EXPECT_EQ(messageOf([&] { matchGuided(rows, {}, predicted, rows, {keypoints[0]}, kImage); }),
            "trainKeypoints: 1 given for 2 train rows");
  EXPECT_EQ(messageOf([&] { matchGuided(rows, {keypoints[0]}, predicted, rows, keypoints, kImage); }),
            "queryKeypoints: 1 given for 2 query rows");
  GuidedMatchOptions o;
  o.maxScaleRatio = 2.f;
  EXPECT_EQ(messageOf([&] { matchGuided(rows, {}, predicted, rows, keypoints, kImage, o); }),
            "queryKeypoints: 0 given for 2 query rows");
  EXPECT_EQ(messageOf([&] { matchGuided(rows, keypoints, predicted, rows, keypoints, cv::Size(0, 480)); }),
            "imageSize: 0x480 has no pixels");
  EXPECT_EQ(messageOf([&] { matchGuided(rows, keypoints, predicted, rows.colRange(0, 16), keypoints, kImage); }),
            "train: width 16 bytes differs from query's 32");
  std::vector<cv::KeyPoint> bad = keypoints;
  bad[1].pt.x = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(messageOf([&] { matchGuided(rows, keypoints, predicted, rows, bad, kImage); }).rfind(
                "trainKeypoints[1]: position (", 0),
            0u);
  bad = keypoints;
  bad[1].angle = -1.f;  // OpenCV's "no orientation"
  o = {};
  o.maxAngleDifference = 30.f;
  EXPECT_EQ(messageOf([&] { matchGuided(rows, keypoints, predicted, rows, bad, kImage, o); }),
            "trainKeypoints[1]: angle -1 is unknown, which maxAngleDifference needs");
  EXPECT_EQ(messageOf([&] {
              matchGuidedMasked(rows, rows.colRange(0, 16), keypoints, predicted, rows, rows, keypoints, kImage);
            }),
            "queryMasks: size 2x16 differs from query's 2x32");
  EXPECT_EQ(messageOf([&] {
              matchGuidedMasked(rows, rows, keypoints, predicted, rows, cv::Mat(2, 32, CV_16UC1), keypoints, kImage);
            }),
            "trainMasks: masks must be CV_8UC1, got CV_16UC1");
  EXPECT_EQ(messageOf([&] { matchGuided(cv::Mat(2, 30, CV_8UC1), {}, predicted, rows, keypoints, kImage); }).find(
                "query"),
            0u);
}

}  // namespace

// Brute-force matcher against slow reference matchers and cv::BFMatcher.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include <opencv2/features2d.hpp>

#include "mdbrief/match/hamming.hpp"
#include "mdbrief/match/masked_hamming.hpp"
#include "mdbrief/match/matcher.hpp"
#include "test_data.hpp"

namespace {

using mdbrief::MatchOptions;

cv::Mat randomDescriptors(int rows, int bytes, std::mt19937& rng) {
  cv::Mat m(rows, bytes, CV_8UC1);
  std::uniform_int_distribution<int> byte(0, 255);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < bytes; ++c) m.at<uint8_t>(r, c) = static_cast<uint8_t>(byte(rng));
  }
  return m;
}

// Masks with a per-row density, including all-zero and all-one rows.
cv::Mat randomMasks(int rows, int bytes, std::mt19937& rng) {
  cv::Mat m(rows, bytes, CV_8UC1, cv::Scalar(0));
  const double densities[] = {0.0, 1.0, 0.05, 0.5, 0.8, 0.95};
  for (int r = 0; r < rows; ++r) {
    std::bernoulli_distribution coin(densities[r % 6]);
    for (int d = 0; d < bytes * 8; ++d) {
      if (coin(rng)) m.at<uint8_t>(r, d / 8) |= static_cast<uint8_t>(1u << (d % 8));
    }
  }
  return m;
}

// Descriptors close to some of the train rows, so that the tests select real matches and
// produce distance ties (two train rows at the same distance).
cv::Mat perturbedCopies(const cv::Mat& train, int rows, std::mt19937& rng) {
  cv::Mat q = randomDescriptors(rows, train.cols, rng);
  std::uniform_int_distribution<int> pick(0, train.rows - 1), bitPick(0, train.cols * 8 - 1);
  for (int r = 0; r < rows; r += 2) {
    train.row(pick(rng)).copyTo(q.row(r));
    for (int f = r % 7; f > 0; --f) {
      const int d = bitPick(rng);
      q.at<uint8_t>(r, d / 8) ^= static_cast<uint8_t>(1u << (d % 8));
    }
  }
  return q;
}

// Plain nearest neighbours: no ratio test, no cross-check, no distance bound. Set explicitly:
// the defaults have a ratio test and the cross-check.
MatchOptions nearestOnly() {
  MatchOptions o;
  o.ratio.reset();
  o.crossCheck = false;
  o.maxDistance.reset();
  return o;
}

int bitByBitHamming(const uint8_t* a, const uint8_t* b, int bytes) {
  int count = 0;
  for (int d = 0; d < bytes * 8; ++d) count += ((a[d / 8] ^ b[d / 8]) >> (d % 8)) & 1;
  return count;
}

// Obviously-correct matcher over an arbitrary integer distance: scans trains in index order,
// strict < so ties keep the lowest index; then applies the options as documented.
template <typename Dist, typename ToFloat>
std::vector<cv::DMatch> referenceMatch(int nq, int nt, const MatchOptions& o, Dist dist,
                                       ToFloat toFloat) {
  auto nearest = [](int n, auto&& d) {
    int64_t best = std::numeric_limits<int64_t>::max(), second = best;
    int index = -1;
    for (int j = 0; j < n; ++j) {
      const int64_t v = d(j);
      if (v < best) {
        second = best;
        best = v;
        index = j;
      } else if (v < second) {
        second = v;
      }
    }
    return std::make_tuple(best, second, index);
  };
  std::vector<cv::DMatch> out;
  if (nq == 0 || nt == 0) return out;
  for (int i = 0; i < nq; ++i) {
    const auto [best, second, index] = nearest(nt, [&](int j) { return dist(i, j); });
    if (o.ratio && second != std::numeric_limits<int64_t>::max() &&
        !(static_cast<double>(best) < *o.ratio * static_cast<double>(second))) {
      continue;
    }
    if (o.maxDistance && !(toFloat(best) <= *o.maxDistance)) continue;
    if (o.crossCheck) {
      const int back = std::get<2>(nearest(nq, [&](int k) { return dist(k, index); }));
      if (back != i) continue;
    }
    out.emplace_back(i, index, 0, toFloat(best));
  }
  return out;
}

void expectSameMatches(const std::vector<cv::DMatch>& got, const std::vector<cv::DMatch>& want,
                       const std::string& what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  for (size_t k = 0; k < got.size(); ++k) {
    EXPECT_EQ(got[k].queryIdx, want[k].queryIdx) << what << " match " << k;
    EXPECT_EQ(got[k].trainIdx, want[k].trainIdx) << what << " match " << k;
    EXPECT_EQ(got[k].imgIdx, 0) << what;
    EXPECT_EQ(got[k].distance, want[k].distance) << what << " match " << k;
  }
}

std::vector<MatchOptions> optionCombinations(int nbits) {
  std::vector<MatchOptions> all;
  for (int mask = 0; mask < 16; ++mask) {
    MatchOptions o = nearestOnly();
    if (mask & 1) o.ratio = 0.8f;
    if (mask & 2) o.crossCheck = true;
    if (mask & 4) o.maxDistance = nbits * 0.3f;
    o.parallel = (mask & 8) != 0;
    all.push_back(o);
  }
  all.push_back(MatchOptions{});  // the defaults, whatever they are
  return all;
}

std::string describe(const MatchOptions& o, int bytes) {
  return "bytes " + std::to_string(bytes) + " ratio " + (o.ratio ? "on" : "off") + " cross " +
         (o.crossCheck ? "on" : "off") + " maxDistance " + (o.maxDistance ? "on" : "off") +
         " parallel " + (o.parallel ? "on" : "off");
}

TEST(Matcher, PlainEqualsReferenceForAllWidthsAndOptions) {
  std::mt19937 rng(2024);
  for (int bytes = 4; bytes <= 64; bytes += 4) {
    // 53 trains: three full blocks of 16 plus a partial one.
    const cv::Mat train = randomDescriptors(53, bytes, rng);
    const cv::Mat query = perturbedCopies(train, 37, rng);
    auto dist = [&](int i, int j) {
      return bitByBitHamming(query.ptr<uint8_t>(i), train.ptr<uint8_t>(j), bytes);
    };
    auto toFloat = [](int64_t v) { return static_cast<float>(v); };
    for (const MatchOptions& o : optionCombinations(bytes * 8)) {
      expectSameMatches(mdbrief::matchBruteForce(query, train, o),
                        referenceMatch(query.rows, train.rows, o, dist, toFloat), describe(o, bytes));
    }
  }
}

TEST(Matcher, MaskedEqualsFixedPointReferenceForAllWidthsAndOptions) {
  // Selection and options on the fixed-point distance, which test_hamming checks against the
  // paper's formula in double; the nearest neighbour itself is checked in double below.
  std::mt19937 rng(99);
  for (int bytes = 4; bytes <= 64; bytes += 4) {
    const cv::Mat train = randomDescriptors(40, bytes, rng);
    const cv::Mat query = perturbedCopies(train, 29, rng);
    const cv::Mat trainMasks = randomMasks(train.rows, bytes, rng);
    const cv::Mat queryMasks = randomMasks(query.rows, bytes, rng);
    auto dist = [&](int i, int j) {
      return static_cast<int64_t>(mdbrief::maskedHammingFixed(query.ptr<uint8_t>(i), queryMasks.ptr<uint8_t>(i),
                                                              train.ptr<uint8_t>(j), trainMasks.ptr<uint8_t>(j), bytes));
    };
    auto toFloat = [](int64_t v) { return mdbrief::maskedFixedToBits(static_cast<uint32_t>(v)); };
    for (const MatchOptions& o : optionCombinations(bytes * 8)) {
      expectSameMatches(mdbrief::matchBruteForceMasked(query, queryMasks, train, trainMasks, o),
                        referenceMatch(query.rows, train.rows, o, dist, toFloat), describe(o, bytes));
    }
  }
}

// The paper's masked distance in double, scaled to bits; an all-zero mask counts as ones.
double doubleMasked(const uint8_t* di, const uint8_t* li, const uint8_t* dj, const uint8_t* lj, int bytes) {
  const int nbits = bytes * 8;
  auto bit = [](const uint8_t* p, int d) { return (p[d / 8] >> (d % 8)) & 1; };
  int oi = 0, oj = 0, a = 0, b = 0;
  for (int d = 0; d < nbits; ++d) {
    oi += bit(li, d);
    oj += bit(lj, d);
  }
  for (int d = 0; d < nbits; ++d) {
    const bool x = bit(di, d) != bit(dj, d);
    a += x && (oi == 0 || bit(li, d));
    b += x && (oj == 0 || bit(lj, d));
  }
  return nbits / 2.0 * (static_cast<double>(a) / (oi ? oi : nbits) + static_cast<double>(b) / (oj ? oj : nbits));
}

TEST(Matcher, MaskedNearestNeighbourAgreesWithDoubleFormula) {
  std::mt19937 rng(5);
  for (int bytes = 4; bytes <= 64; bytes += 4) {
    const double tol = bytes * 8 / std::ldexp(1.0, 22) + bytes * 8 * std::ldexp(1.0, -24);
    const cv::Mat train = randomDescriptors(70, bytes, rng);
    const cv::Mat query = perturbedCopies(train, 25, rng);
    const cv::Mat trainMasks = randomMasks(train.rows, bytes, rng);
    const cv::Mat queryMasks = randomMasks(query.rows, bytes, rng);
    const auto matches = mdbrief::matchBruteForceMasked(query, queryMasks, train, trainMasks, nearestOnly());
    ASSERT_EQ(matches.size(), static_cast<size_t>(query.rows));
    for (const cv::DMatch& m : matches) {
      std::vector<double> d(train.rows);
      for (int j = 0; j < train.rows; ++j) {
        d[j] = doubleMasked(query.ptr<uint8_t>(m.queryIdx), queryMasks.ptr<uint8_t>(m.queryIdx),
                            train.ptr<uint8_t>(j), trainMasks.ptr<uint8_t>(j), bytes);
      }
      const double best = *std::min_element(d.begin(), d.end());
      int lowestClearWinner = -1, nearBest = 0;
      for (int j = 0; j < train.rows; ++j) {
        if (d[j] <= best + 2 * tol) {
          ++nearBest;
          lowestClearWinner = j;
        }
      }
      EXPECT_NEAR(m.distance, d[m.trainIdx], tol) << "bytes " << bytes;
      EXPECT_LE(d[m.trainIdx], best + 2 * tol) << "bytes " << bytes;
      if (nearBest == 1) {
        EXPECT_EQ(m.trainIdx, lowestClearWinner) << "bytes " << bytes;
      }
    }
  }
}

TEST(Matcher, PlainAgreesWithOpenCvBFMatcher) {
  std::mt19937 rng(77);
  for (int bytes : {4, 8, 16, 32, 36, 64}) {
    const cv::Mat train = randomDescriptors(300, bytes, rng);
    const cv::Mat query = perturbedCopies(train, 200, rng);
    std::vector<cv::DMatch> theirs;
    cv::BFMatcher(cv::NORM_HAMMING).match(query, train, theirs);
    const auto ours = mdbrief::matchBruteForce(query, train, nearestOnly());
    ASSERT_EQ(ours.size(), theirs.size());
    for (size_t k = 0; k < ours.size(); ++k) {
      ASSERT_EQ(ours[k].queryIdx, theirs[k].queryIdx);
      EXPECT_EQ(ours[k].distance, theirs[k].distance) << "bytes " << bytes << " query " << k;
      // Ties: both must pick a train at the minimum; ours is the lowest such index.
      const int q = ours[k].queryIdx;
      int lowest = -1;
      for (int j = 0; j < train.rows; ++j) {
        const float dj = static_cast<float>(bitByBitHamming(query.ptr<uint8_t>(q), train.ptr<uint8_t>(j), bytes));
        if (dj == ours[k].distance && lowest < 0) lowest = j;
      }
      EXPECT_EQ(ours[k].trainIdx, lowest);
      EXPECT_EQ(mdbrief::hammingDistance(query.row(q), train.row(theirs[k].trainIdx)), theirs[k].distance);
    }
  }
}

cv::Mat flipped(const cv::Mat& row, std::initializer_list<int> bits) {
  cv::Mat r = row.clone();
  for (int d : bits) r.at<uint8_t>(0, d / 8) ^= static_cast<uint8_t>(1u << (d % 8));
  return r;
}

TEST(Matcher, RatioTestThresholdAndTies) {
  std::mt19937 rng(3);
  const cv::Mat q = randomDescriptors(1, 32, rng);
  cv::Mat train;
  cv::vconcat(std::vector<cv::Mat>{flipped(q, {1, 2, 3}), flipped(q, {4, 5}), flipped(q, {6, 7})}, train);

  auto one = [&](const MatchOptions& o) { return mdbrief::matchBruteForce(q, train, o); };
  auto m = one(nearestOnly());
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].trainIdx, 1) << "tie at distance 2 goes to the lowest index";
  EXPECT_EQ(m[0].distance, 2.f);

  MatchOptions o = nearestOnly();
  o.ratio = 1.0f;  // best 2, second 2 (the tie): 2 < 2 fails
  EXPECT_TRUE(one(o).empty());
  const cv::Mat noTie = train.rowRange(0, 2);  // best 2, second 3
  o.ratio = 0.7f;  // 2 < 2.1 passes
  EXPECT_EQ(mdbrief::matchBruteForce(q, noTie, o).size(), 1u);
  o.ratio = 0.6f;  // 2 < 1.8 fails
  EXPECT_TRUE(mdbrief::matchBruteForce(q, noTie, o).empty());
  o.ratio = 0.1f;  // a single train descriptor has no second neighbour: passes
  EXPECT_EQ(mdbrief::matchBruteForce(q, train.row(0), o).size(), 1u);

  MatchOptions t = nearestOnly();
  t.maxDistance = 2.f;
  EXPECT_EQ(one(t).size(), 1u);
  t.maxDistance = 1.9f;
  EXPECT_TRUE(one(t).empty());
}

TEST(Matcher, CrossCheckKeepsMutualNearestOnly) {
  std::mt19937 rng(11);
  const cv::Mat base = randomDescriptors(1, 32, rng);
  // Both queries are nearest to train 0, but train 0 is nearest to query 0 only.
  cv::Mat query, train;
  cv::vconcat(std::vector<cv::Mat>{flipped(base, {1}), flipped(base, {1, 2, 3})}, query);
  cv::vconcat(std::vector<cv::Mat>{base, flipped(base, {100, 101, 102, 103, 104, 105, 106, 107})}, train);
  EXPECT_EQ(mdbrief::matchBruteForce(query, train, nearestOnly()).size(), 2u);
  MatchOptions o = nearestOnly();
  o.crossCheck = true;
  const auto m = mdbrief::matchBruteForce(query, train, o);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].queryIdx, 0);
  EXPECT_EQ(m[0].trainIdx, 0);
  const cv::Mat ones(2, 32, CV_8UC1, cv::Scalar(255));
  const auto masked = mdbrief::matchBruteForceMasked(query, ones, train, ones, o);
  ASSERT_EQ(masked.size(), 1u);
  EXPECT_EQ(masked[0].distance, 1.f) << "all-ones masks give the plain distance";
}

TEST(Matcher, MaskedUsesMasks) {
  // Train 0 differs from the query only in bits its and the query's masks exclude, train 1
  // in fewer bits that both masks keep: masked matching prefers train 0, plain train 1.
  cv::Mat query(1, 8, CV_8UC1, cv::Scalar(0));
  cv::Mat train;
  cv::vconcat(std::vector<cv::Mat>{flipped(query, {40, 41, 42, 43, 44}), flipped(query, {0})}, train);
  cv::Mat queryMask = (cv::Mat_<uint8_t>(1, 8) << 255, 255, 255, 255, 0, 0, 0, 0);
  cv::Mat trainMasks;
  cv::vconcat(std::vector<cv::Mat>{queryMask, queryMask}, trainMasks);
  EXPECT_EQ(mdbrief::matchBruteForce(query, train, nearestOnly())[0].trainIdx, 1);
  const auto m = mdbrief::matchBruteForceMasked(query, queryMask, train, trainMasks, nearestOnly());
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].trainIdx, 0);
  EXPECT_EQ(m[0].distance, 0.f);
}

TEST(Matcher, NonContiguousInputs) {
  std::mt19937 rng(8);
  const cv::Mat wideTrain = randomDescriptors(40, 40, rng);
  const cv::Mat wideQuery = randomDescriptors(20, 40, rng);
  const cv::Mat train = wideTrain.colRange(4, 36), query = wideQuery.colRange(4, 36);
  ASSERT_FALSE(train.isContinuous());
  const cv::Mat trainCopy = train.clone(), queryCopy = query.clone();
  expectSameMatches(mdbrief::matchBruteForce(query, train), mdbrief::matchBruteForce(queryCopy, trainCopy), "roi");
  const cv::Mat masks = randomMasks(40, 40, rng);
  expectSameMatches(mdbrief::matchBruteForceMasked(query, masks.rowRange(0, 20).colRange(4, 36), train, masks.colRange(4, 36)),
                    mdbrief::matchBruteForceMasked(queryCopy, masks.rowRange(0, 20).colRange(4, 36).clone(), trainCopy,
                                                   masks.colRange(4, 36).clone()),
                    "roi masked");
}

TEST(Matcher, EmptyInputsGiveNoMatches) {
  const cv::Mat d(5, 32, CV_8UC1, cv::Scalar(1));
  EXPECT_TRUE(mdbrief::matchBruteForce(cv::Mat(), d).empty());
  EXPECT_TRUE(mdbrief::matchBruteForce(d, cv::Mat(0, 32, CV_8UC1)).empty());
  EXPECT_TRUE(mdbrief::matchBruteForceMasked(d, d, cv::Mat(), cv::Mat()).empty());
  MatchOptions o;
  o.crossCheck = true;
  EXPECT_TRUE(mdbrief::matchBruteForce(cv::Mat(), cv::Mat(), o).empty());
}

template <typename F>
void expectInvalid(F&& f, const std::string& expectedInMessage) {
  try {
    f();
    ADD_FAILURE() << "no exception; expected one mentioning '" << expectedInMessage << "'";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(expectedInMessage), std::string::npos) << e.what();
  }
}

// N x 0 is not "no descriptors" but N descriptors of no bits: every pair would match at 0.
TEST(Matcher, RowsOfNoBytesAreRefused) {
  const cv::Mat none(5, 0, CV_8UC1), d32(5, 32, CV_8UC1, cv::Scalar(0));
  expectInvalid([&] { mdbrief::matchBruteForce(none, none); }, "query: descriptor width");
  expectInvalid([&] { mdbrief::matchBruteForce(d32, none); }, "train: descriptor width");
  expectInvalid([&] { mdbrief::matchBruteForceMasked(none, none, none, none); }, "query: descriptor width");
  EXPECT_TRUE(mdbrief::matchBruteForce(cv::Mat(0, 0, CV_8UC1), d32).empty());
}

TEST(Matcher, InvalidInputsThrow) {
  const cv::Mat d32(5, 32, CV_8UC1, cv::Scalar(0));
  const cv::Mat d16(5, 16, CV_8UC1, cv::Scalar(0));
  expectInvalid([&] { mdbrief::matchBruteForce(d32, d16); }, "train: width 16");
  expectInvalid([&] { mdbrief::matchBruteForce(cv::Mat(5, 32, CV_32F), d32); }, "query: descriptors must be CV_8UC1");
  expectInvalid([&] { mdbrief::matchBruteForce(d32, cv::Mat(5, 30, CV_8UC1)); }, "train: descriptor width");
  expectInvalid([&] { mdbrief::matchBruteForce(cv::Mat(5, 72, CV_8UC1), d32); }, "query: descriptor width");
  expectInvalid([&] { mdbrief::matchBruteForceMasked(d32, d16, d32, d32); }, "queryMasks: size");
  expectInvalid([&] { mdbrief::matchBruteForceMasked(d32, d32, d32, cv::Mat(4, 32, CV_8UC1)); }, "trainMasks: size");
  expectInvalid([&] { mdbrief::matchBruteForceMasked(d32, d32, d32, cv::Mat(5, 32, CV_8SC1)); }, "trainMasks: masks must be CV_8UC1");
  expectInvalid([&] { mdbrief::matchBruteForceMasked(d32, cv::Mat(), d32, d32); }, "queryMasks: size");
  MatchOptions o;
  o.ratio = 1.5f;
  expectInvalid([&] { mdbrief::matchBruteForce(d32, d32, o); }, "MatchOptions::ratio");
  o.ratio = 0.f;
  expectInvalid([&] { mdbrief::matchBruteForce(d32, d32, o); }, "MatchOptions::ratio");
  o.ratio.reset();
  o.maxDistance = -1.f;
  expectInvalid([&] { mdbrief::matchBruteForce(d32, d32, o); }, "MatchOptions::maxDistance");
}

}  // namespace

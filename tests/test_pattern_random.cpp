// The random BRIEF set generator (trainer/random_pattern.hpp) and the shipped
// patterns/brief_random_512.{hpp,json}: regenerating them gives byte-identical files; the sets
// are those of an implementation apart from the project's and follow from the definition.
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>

#include "trainer/pattern_writer.hpp"
#include "mdbrief/describe/patterns.hpp"
#include "test_data.hpp"
#include "toolkit/content_digest.hpp"
#include "trainer/random_pattern.hpp"

namespace fs = std::filesystem;
using namespace mdbrief;

using mdbrief::testing::readFile;

TEST(RandomPattern, RegeneratedFilesAreByteIdenticalToTheShippedOnes) {
  const fs::path dir =
      fs::temp_directory_path() / ("mdbrief_test_random_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  writePattern(train::randomPatternDocument({}), dir);
  const fs::path shipped = mdbrief::testing::sourceDir() / "patterns";
  for (const char* file : {"brief_random_512.hpp", "brief_random_512.json"}) {
    const std::string fresh = readFile(dir / file);
    EXPECT_FALSE(fresh.empty()) << file;
    EXPECT_EQ(fresh, readFile(shipped / file)) << file << " differs: run scripts/gen-random-pattern.sh";
  }
  fs::remove_all(dir);
}

TEST(RandomPattern, MatchesTheCompiledSet) {
  const auto tests = train::gaussianRandomComparisons(512, train::RandomPatternOptions{}.seed);
  const ComparisonSet builtin = builtinComparisonSet("brief_random_512");
  ASSERT_EQ(tests.size(), builtin.tests.size());
  for (size_t i = 0; i < tests.size(); ++i) {
    const ComparisonPair &a = tests[i], &b = builtin.tests[i];
    EXPECT_TRUE(a.x1 == b.x1 && a.y1 == b.y1 && a.x2 == b.x2 && a.y2 == b.y2) << i;
  }
}

namespace {

// The content digest (toolkit/content_digest.hpp) of the tests as x1 y1 x2 y2 bytes.
std::string digestOf(const std::vector<ComparisonPair>& tests) {
  static_assert(sizeof(ComparisonPair) == 4);
  return contentDigest(tests.data(), tests.size() * sizeof(ComparisonPair));
}

}  // namespace

// Golden values from an implementation apart from the project's (Python: MT19937 from its
// reference init_genrand and tempering, Box-Muller as random_pattern.hpp describes it, each value
// times 6.4 rounded half away from zero and clipped, the rejection rules), with the content
// digest (FNV-1a 64) of the x1 y1 x2 y2 bytes.
TEST(RandomPattern, GivesTheSetsOfAnIndependentImplementation) {
  const auto shipped = train::gaussianRandomComparisons(512, 20170529);
  const auto field = [](const ComparisonPair& t) { return std::vector<int>{t.x1, t.y1, t.x2, t.y2}; };
  EXPECT_EQ(field(shipped[0]), (std::vector<int>{-2, 11, 7, 12}));
  EXPECT_EQ(field(shipped[1]), (std::vector<int>{0, -3, 2, -5}));
  EXPECT_EQ(field(shipped[2]), (std::vector<int>{-2, 5, -7, 4}));
  EXPECT_EQ(field(shipped[3]), (std::vector<int>{-2, 0, -8, 7}));
  EXPECT_EQ(field(shipped[511]), (std::vector<int>{3, 8, 5, 3}));
  EXPECT_EQ(digestOf(shipped), "1bcc80b02aa1aa68");
  EXPECT_EQ(digestOf(train::gaussianRandomComparisons(4096, 1)), "14bbdaf851f480aa");
}

// What follows from the definition (random_pattern.hpp), on a large set: every field in the
// patch's [-15, 14]; no test compares a pixel with itself or repeats another in either order;
// each field distributed as a Gaussian of sigma S/5 = 6.4 rounded and clipped (a chi-square test
// over the 30 values), the four independent of each other, and another seed another set.
TEST(RandomPattern, FollowsItsDefinition) {
  const auto a = train::gaussianRandomComparisons(4096, 1);
  ASSERT_EQ(a.size(), 4096u);
  std::set<std::array<int, 4>> seen;
  for (const ComparisonPair& t : a) {
    for (const int v : {t.x1, t.y1, t.x2, t.y2}) {
      EXPECT_GE(v, -15);
      EXPECT_LE(v, 14);
    }
    EXPECT_FALSE(t.x1 == t.x2 && t.y1 == t.y2) << "a pixel compared with itself";
    EXPECT_TRUE(seen.insert({t.x1, t.y1, t.x2, t.y2}).second) << "a repeated test";
    EXPECT_EQ(seen.count({t.x2, t.y2, t.x1, t.y1}), 0u) << "a swapped repeat";
  }
  // P(value = k): the Gaussian's mass rounding to k, the tails clipped onto -15 and 14.
  const double sigma = 32 / 5.0;
  const auto cdf = [&](double x) { return 0.5 * std::erfc(-x / (sigma * std::sqrt(2.0))); };
  std::vector<std::vector<double>> values(4);
  for (const ComparisonPair& t : a) {
    const int v[4] = {t.x1, t.y1, t.x2, t.y2};
    for (int f = 0; f < 4; ++f) values[f].push_back(v[f]);
  }
  for (int f = 0; f < 4; ++f) {
    std::vector<int> count(30, 0);
    for (const double v : values[f]) ++count[static_cast<int>(v) + 15];
    double chi2 = 0;
    for (int k = -15; k <= 14; ++k) {
      const double p = (k == 14 ? 1.0 : cdf(k + 0.5)) - (k == -15 ? 0.0 : cdf(k - 0.5));
      const double expected = p * a.size();
      chi2 += (count[k + 15] - expected) * (count[k + 15] - expected) / expected;
    }
    // 29 degrees of freedom: 58.3 is the 0.1 % point (34.1 measured, the largest of the four).
    EXPECT_LT(chi2, 58.3) << "field " << f;
    for (int g = f + 1; g < 4; ++g) {
      double sf = 0, sg = 0, sff = 0, sgg = 0, sfg = 0;
      for (size_t i = 0; i < a.size(); ++i) {
        const double x = values[f][i], y = values[g][i];
        sf += x, sg += y, sff += x * x, sgg += y * y, sfg += x * y;
      }
      const double n = static_cast<double>(a.size());
      const double correlation = (sfg - sf * sg / n) / std::sqrt((sff - sf * sf / n) * (sgg - sg * sg / n));
      EXPECT_LT(std::abs(correlation), 0.05) << "fields " << f << " and " << g;  // 3 standard errors
    }
  }
  const auto b = train::gaussianRandomComparisons(4096, 2);
  int same = 0;
  for (size_t i = 0; i < a.size(); ++i)
    same += a[i].x1 == b[i].x1 && a[i].y1 == b[i].y1 && a[i].x2 == b[i].x2 && a[i].y2 == b[i].y2;
  EXPECT_LT(same, 20);
  EXPECT_THROW(train::gaussianRandomComparisons(0, 1), std::invalid_argument);
}

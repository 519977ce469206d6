// The random BRIEF set generator (trainer/random_pattern.hpp) and the shipped
// patterns/brief_random_512.{hpp,json}: regenerating them gives byte-identical files.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <unistd.h>

#include "trainer/pattern_writer.hpp"
#include "mdbrief/describe/patterns.hpp"
#include "test_data.hpp"
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
  const auto tests = train::gaussianRandomTests(512, train::RandomPatternOptions{}.seed);
  const TestSet builtin = builtinTestSet("brief_random_512");
  ASSERT_EQ(tests.size(), builtin.tests.size());
  for (size_t i = 0; i < tests.size(); ++i)
    EXPECT_TRUE(tests[i].x1 == builtin.tests[i].x1 && tests[i].y2 == builtin.tests[i].y2) << i;
}

TEST(RandomPattern, SeedChangesTheSetAndSpreadIsSOver5) {
  const auto a = train::gaussianRandomTests(4096, 1);
  const auto b = train::gaussianRandomTests(4096, 2);
  int same = 0;
  double sum = 0, sum2 = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    same += a[i].x1 == b[i].x1 && a[i].y1 == b[i].y1 && a[i].x2 == b[i].x2 && a[i].y2 == b[i].y2;
    for (int v : {a[i].x1, a[i].y1, a[i].x2, a[i].y2}) {
      sum += v;
      sum2 += double(v) * v;
    }
  }
  EXPECT_LT(same, 20);
  const double n = 4.0 * a.size();
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 0.3);
  EXPECT_NEAR(sd, 6.4, 0.4);  // slightly less than 6.4 because of the clipping to [-15, 14]
  EXPECT_THROW(train::gaussianRandomTests(0, 1), std::invalid_argument);
}

// Runtime comparison sets: the compiled-in registry, ComparisonSet::first, JSON loading, the
// pattern writer (header, JSON copy, registry) and the deprecated names of 0.2.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <thread>
#include <tuple>
#include <type_traits>

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include "mdbrief/internal/base/io/atomic_file.hpp"
#include "mdbrief/describe/descriptor.hpp"
#include "mdbrief/describe/patterns.hpp"
#include "mdbrief/describe/test_set.hpp"  // the deprecated header still compiles
#include "trainer/pattern_writer.hpp"
#include "test_data.hpp"
#include "write_limits.hpp"

namespace fs = std::filesystem;
using namespace mdbrief;

namespace {

using mdbrief::testing::TempDir;
using mdbrief::testing::readFile;

// A fresh empty folder, removed at the end of the test.
void writeText(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

bool sameComparisons(const std::vector<ComparisonPair>& a, const std::vector<ComparisonPair>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](const ComparisonPair& l, const ComparisonPair& r) {
    return l.x1 == r.x1 && l.y1 == r.y1 && l.x2 == r.x2 && l.y2 == r.y2;
  });
}

PatternDocument smallDocument(const std::string& name, int count = 64) {
  PatternDocument d;
  d.name = name;
  d.description = "test set \"quoted\" \\ backslash";
  d.generator = "test_patterns";
  d.provenance = {"line one", "line two"};
  for (int i = 0; i < count; ++i)
    d.tests.push_back({static_cast<int8_t>(i % 30 - 15), static_cast<int8_t>(i % 7 - 3),
                       static_cast<int8_t>(14 - i % 30), static_cast<int8_t>(-16 + i % 32)});
  return d;
}

// loadComparisonSetJson on a file with `text` must throw a runtime_error naming the file and `what`.
void expectJsonError(const std::string& text, const std::string& what) {
  TempDir dir("bad");
  const fs::path p = dir.path / "bad.json";
  writeText(p, text);
  try {
    loadComparisonSetJson(p.string());
    ADD_FAILURE() << "no exception for: " << text;
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(p.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << msg;
  }
}

}  // namespace

TEST(Registry, ListsTheRandomSetSortedWithAValidDefault) {
  const auto names = builtinComparisonSetNames();
  EXPECT_TRUE(std::is_sorted(names.begin(), names.end()));
  EXPECT_NE(std::find(names.begin(), names.end(), "brief_random_512"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), defaultComparisonSetName()), names.end());
  EXPECT_NO_THROW(builtinComparisonSet(defaultComparisonSetName()));
}

TEST(Registry, EveryBuiltinSetHasInRangeDistinctTests) {
  for (const auto& name : builtinComparisonSetNames()) {
    const ComparisonSet set = builtinComparisonSet(name);
    EXPECT_EQ(set.name, name);
    EXPECT_GE(set.tests.size(), 32u);
    EXPECT_EQ(set.tests.size() % 32, 0u);
    std::set<std::tuple<int, int, int, int>> seen;
    for (const ComparisonPair& t : set.tests) {
      for (int v : {t.x1, t.y1, t.x2, t.y2}) {
        EXPECT_GE(v, -15) << name;  // the trainer's and generator's range: no border pixels
        EXPECT_LE(v, 14) << name;
      }
      EXPECT_FALSE(t.x1 == t.x2 && t.y1 == t.y2) << name << ": self-comparison";
      EXPECT_TRUE(seen.insert({t.x1, t.y1, t.x2, t.y2}).second) << name << ": repeated test";
      EXPECT_FALSE(seen.count({t.x2, t.y2, t.x1, t.y1})) << name << ": swapped repeat";
    }
  }
}

TEST(Registry, RandomSetHas512Tests) {
  EXPECT_EQ(builtinComparisonSet("brief_random_512").tests.size(), 512u);
}

TEST(Registry, UnknownNameThrowsListingKnownNames) {
  try {
    builtinComparisonSet("no_such_set");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("brief_random_512"), std::string::npos);
  }
  EXPECT_THROW(resolveComparisonSet("no_such_set_or_file"), std::invalid_argument);
}

TEST(ComparisonSetFirst, TakesPrefixesInStepsOf32) {
  const ComparisonSet set = builtinComparisonSet("brief_random_512");
  for (int n = 32; n <= 512; n += 32) {
    const ComparisonSet sub = set.first(n);
    ASSERT_EQ(sub.tests.size(), static_cast<size_t>(n));
    EXPECT_EQ(sub.name, set.name);
    EXPECT_TRUE(sameComparisons(sub.tests, {set.tests.begin(), set.tests.begin() + n}));
  }
  for (int n : {-32, 0, 1, 31, 33, 100, 511, 544, 1024})
    EXPECT_THROW(set.first(n), std::invalid_argument) << n;
}

TEST(PatternJson, ShippedCopyMatchesTheCompiledSet) {
  const fs::path json = mdbrief::testing::sourceDir() / "patterns" / "brief_random_512.json";
  const ComparisonSet loaded = loadComparisonSetJson(json.string());
  EXPECT_EQ(loaded.name, "brief_random_512");
  EXPECT_TRUE(sameComparisons(loaded.tests, builtinComparisonSet("brief_random_512").tests));
  EXPECT_TRUE(sameComparisons(resolveComparisonSet(json.string()).tests, loaded.tests));
}

TEST(PatternJson, RoundTrip) {
  TempDir dir("roundtrip");
  PatternDocument doc = smallDocument("round_trip");
  doc.testComments.assign(doc.tests.size(), "mean 0.50 max corr 0.10");
  const fs::path p = dir.path / "round_trip.json";
  internal::writeFileAtomically(p, patternJsonText(doc));
  const ComparisonSet loaded = loadComparisonSetJson(p.string());
  EXPECT_EQ(loaded.name, doc.name);
  EXPECT_TRUE(sameComparisons(loaded.tests, doc.tests));
}

TEST(PatternJson, MalformedFilesThrowNamingFileAndProblem) {
  const std::string tests32 = [] {
    std::string s;
    for (int i = 0; i < 32; ++i) s += std::string(i ? "," : "") + "[1,2,3,4]";
    return s;
  }();
  expectJsonError("{\"name\": \"x\", \"tests\": [", "not valid JSON");
  expectJsonError("[1, 2]", "not a JSON object");
  expectJsonError("{\"tests\": [" + tests32 + "]}", "\"name\"");
  expectJsonError("{\"name\": \"x\"}", "\"tests\"");
  expectJsonError("{\"name\": \"x\", \"tests\": [[1,2,3]]}", "4 offsets");
  expectJsonError("{\"name\": \"x\", \"tests\": [[1,2,3,16]]}", "outside [-16, 15]");
  expectJsonError("{\"name\": \"x\", \"tests\": [[1,2,3,-17]]}", "outside [-16, 15]");
  expectJsonError("{\"name\": \"x\", \"tests\": [[1,2.5,3,4]]}", "non-integer offset 2.5");
  // Issue 45: 2^63 was printed as -9223372036854775808, and whole numbers beyond 64 bits were
  // called non-integers.
  expectJsonError("{\"name\": \"x\", \"tests\": [[9223372036854775808,2,3,4]]}",
                  "offset 9223372036854775808 outside [-16, 15]");
  expectJsonError("{\"name\": \"x\", \"tests\": [[18446744073709551615,2,3,4]]}",
                  "offset 18446744073709551615 outside [-16, 15]");
  expectJsonError("{\"name\": \"x\", \"tests\": [[1,-9223372036854775809,3,4]]}", "outside [-16, 15]");
  expectJsonError("{\"name\": \"x\", \"tests\": [[1,2,1e30,4]]}", "offset 1e+30 outside [-16, 15]");
  // Issue 45: a depth limit with its own message, as every reader of structured text has.
  expectJsonError("{\"name\": \"x\", \"tests\": " + std::string(1000, '[') + std::string(1000, ']') + "}",
                  "nested deeper than 64 levels");
  expectJsonError("{\"name\": \"x\", \"tests\": [[1,2,3,4]]}", "multiple of 32");
  expectJsonError("{\"name\": \"x\", \"tests\": []}", "multiple of 32");
  // Issue 45: the second "tests" silently replaced the first.
  expectJsonError("{\"name\": \"x\", \"tests\": [" + tests32 + "], \"tests\": [" + tests32 + "]}",
                  "key 'tests' appears twice");
  expectJsonError("{\"name\": \"x\", \"info\": {\"a\": 1, \"a\": 2}, \"tests\": [" + tests32 + "]}",
                  "key 'a' appears twice");
  EXPECT_THROW(loadComparisonSetJson("/nonexistent/set.json"), std::runtime_error);
}

TEST(PatternHeader, HasIdentifiersInfoAndPerTestComments) {
  PatternDocument doc = smallDocument("my_set_64");
  doc.testComments.assign(doc.tests.size(), "mean 0.50 max corr 0.10");
  const std::string text = patternHeaderText(doc);
  EXPECT_EQ(patternIdentifier("my_set_64"), "kMySet64");
  EXPECT_EQ(text.rfind("// Generated by test_patterns. Do not edit.\n", 0), 0u);
  EXPECT_NE(text.find("inline constexpr TestRow kMySet64[64] = {"), std::string::npos);
  EXPECT_NE(text.find("inline constexpr PatternInfo kMySet64Info{\"my_set_64\", kMySet64, 64,"),
            std::string::npos);
  EXPECT_NE(text.find("{-15, -3, 14, -16},  // 0: mean 0.50 max corr 0.10\n"), std::string::npos);
  EXPECT_NE(text.find("\"test set \\\"quoted\\\" \\\\ backslash\""), std::string::npos);
}

TEST(PatternHeader, RejectsBadDocuments) {
  PatternDocument doc = smallDocument("ok");
  doc.name = "Bad-Name";
  EXPECT_THROW(patternHeaderText(doc), std::invalid_argument);
  doc.name = "registry";
  EXPECT_THROW(patternHeaderText(doc), std::invalid_argument);
  doc = smallDocument("ok");
  doc.tests[3].x2 = 16;
  EXPECT_THROW(patternHeaderText(doc), std::invalid_argument);
  doc = smallDocument("ok");
  doc.testComments = {"one"};
  EXPECT_THROW(patternHeaderText(doc), std::invalid_argument);
  doc = smallDocument("ok");
  doc.provenance.push_back("two\nlines");
  EXPECT_THROW(patternHeaderText(doc), std::invalid_argument);
}

TEST(PatternWriter, RegeneratesRegistryAndKeepsDefault) {
  TempDir dir("writer");
  writePattern(smallDocument("zeta_set"), dir.path);
  EXPECT_EQ(registryDefaultName(dir.path), "zeta_set");  // first set becomes the default
  writePattern(smallDocument("alpha_set"), dir.path);
  EXPECT_EQ(registryDefaultName(dir.path), "zeta_set");
  EXPECT_EQ(patternHeaderNames(dir.path), (std::vector<std::string>{"alpha_set", "zeta_set"}));
  const std::string registry = readFile(dir.path / "registry.hpp");
  EXPECT_LT(registry.find("patterns/alpha_set.hpp"), registry.find("patterns/zeta_set.hpp"));
  EXPECT_LT(registry.find("&kAlphaSetInfo"), registry.find("&kZetaSetInfo"));
  writePattern(smallDocument("alpha_set"), dir.path, {true, true});
  EXPECT_EQ(registryDefaultName(dir.path), "alpha_set");
  EXPECT_TRUE(fs::exists(dir.path / "alpha_set.json"));
  for (const auto& e : fs::directory_iterator(dir.path))  // no temporary files left behind
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
}

TEST(PatternWriter, InvalidDocumentOrMissingFolderWritesNothing) {
  TempDir dir("invalid");
  writePattern(smallDocument("kept"), dir.path);
  const std::string before = readFile(dir.path / "kept.hpp");
  PatternDocument bad = smallDocument("kept");
  bad.tests[0].y1 = -20;
  EXPECT_THROW(writePattern(bad, dir.path), std::invalid_argument);
  EXPECT_EQ(readFile(dir.path / "kept.hpp"), before);
  EXPECT_THROW(writePattern(smallDocument("x"), dir.path / "missing"), std::runtime_error);
}

// The header, its JSON copy and the registry are one set: a write that fails part way (here the
// header, beyond the file size limit, after the JSON) leaves all three as they were.
TEST(PatternWriter, AFailedWriteKeepsTheWholePreviousSet) {
  TempDir dir("writer_fsize");
  writePattern(smallDocument("kept", 32), dir.path);
  std::map<std::string, std::string> before;
  for (const char* file : {"kept.json", "kept.hpp", "registry.hpp"}) before[file] = readFile(dir.path / file);
  PatternDocument larger = smallDocument("kept", 512);
  const size_t jsonBytes = patternJsonText(larger).size(), headerBytes = patternHeaderText(larger).size();
  ASSERT_LT(jsonBytes + 4096, headerBytes);
  {
    const mdbrief::testing::FileSizeLimit limit(jsonBytes + 1);
    EXPECT_THROW(writePattern(larger, dir.path), std::runtime_error);
  }
  for (const auto& [file, content] : before) EXPECT_EQ(readFile(dir.path / file), content) << file << " changed";
  EXPECT_EQ(mdbrief::testing::temporaryFiles(dir.path), std::vector<std::string>{});
}

// Writers running at once into one folder (parallel mdbrief-train or mdbrief-pattern-random
// runs) each add their set; none drops another's from the registry.
TEST(PatternWriter, ParallelWritersKeepEveryRegistryEntry) {
  TempDir dir("writer_parallel");
  constexpr int kWriters = 8, kRounds = 3;
  for (int round = 0; round < kRounds; ++round) {
    std::atomic<int> ready{0};
    std::vector<std::thread> writers;
    for (int w = 0; w < kWriters; ++w)
      writers.emplace_back([&, w] {
        const PatternDocument document = smallDocument("set_" + std::to_string(round) + "_" + std::to_string(w), 32);
        // All start together, so their writes overlap.
        for (++ready; ready < kWriters;) std::this_thread::yield();
        writePattern(document, dir.path);
      });
    for (auto& t : writers) t.join();
  }
  const std::string registry = readFile(dir.path / "registry.hpp");
  EXPECT_EQ(patternHeaderNames(dir.path).size(), static_cast<size_t>(kWriters * kRounds));
  for (int round = 0; round < kRounds; ++round)
    for (int w = 0; w < kWriters; ++w) {
      const std::string name = "set_" + std::to_string(round) + "_" + std::to_string(w);
      EXPECT_NE(registry.find("patterns/" + name + ".hpp"), std::string::npos) << name << " lost";
    }
}

// The turns are taken with an flock on the folder (pattern_writer.hpp): while another writer
// holds it, a writer waits instead of listing the headers and replacing the registry.
TEST(PatternWriter, AWriterWaitsWhileAnotherHoldsTheFolder) {
  TempDir dir("writer_turns");
  const int folder = ::open(dir.path.c_str(), O_RDONLY | O_DIRECTORY);
  ASSERT_GE(folder, 0);
  ASSERT_EQ(::flock(folder, LOCK_EX), 0);
  std::atomic<bool> done{false};
  std::thread writer([&] {
    writePattern(smallDocument("waiting", 32), dir.path);
    done = true;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_FALSE(done) << "wrote while another writer held the folder";
  writeText(dir.path / "other.hpp", "// the other writer's header\n");
  ::flock(folder, LOCK_UN);
  ::close(folder);
  writer.join();
  EXPECT_TRUE(done);
  EXPECT_EQ(patternHeaderNames(dir.path), (std::vector<std::string>{"other", "waiting"}));
  EXPECT_NE(readFile(dir.path / "registry.hpp").find("patterns/other.hpp"), std::string::npos);
}

TEST(PatternWriter, OutputsThatCannotBeWrittenAreReportedBeforeTheWork) {
  TempDir dir("writer_check");
  checkPatternOutputs("fresh", dir.path);
  EXPECT_TRUE(fs::is_empty(dir.path));
  fs::create_directory(dir.path / "taken.hpp");
  EXPECT_THROW(checkPatternOutputs("taken", dir.path), std::runtime_error);
  EXPECT_THROW(checkPatternOutputs("fresh", dir.path / "missing"), std::runtime_error);
  EXPECT_THROW(checkPatternOutputs("Bad-Name", dir.path), std::invalid_argument);
}

// Issue 29: `--pattern /dev/zero` said the file did not exist. Whatever is at the path is named.
TEST(ResolveComparisonSet, ADeviceOrAFolderIsNamedForWhatItIs) {
  const auto messageOf = [](const std::string& path) {
    try {
      resolveComparisonSet(path);
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(messageOf("/dev/zero"), "/dev/zero: test set file: is a character device, not a regular file");
  EXPECT_NE(messageOf("/tmp").find("/tmp: test set file: is a folder"), std::string::npos);
  EXPECT_NE(messageOf("no_such_set").find("neither a built-in set"), std::string::npos);
}

// Issue 46: TestSet, TestPair and the functions named after them were renamed; the old names
// still compile (with a deprecation warning, silenced here) and are the same types and results.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
TEST(DeprecatedNames, AreTheComparisonSetsTypesAndFunctions) {
  static_assert(std::is_same_v<TestSet, ComparisonSet>);
  static_assert(std::is_same_v<TestPair, ComparisonPair>);
  static_assert(std::is_same_v<decltype(&DescriptorExtractor::testSet), decltype(&DescriptorExtractor::comparisonSet)>);
  EXPECT_EQ(builtinTestSetNames(), builtinComparisonSetNames());
  EXPECT_EQ(defaultTestSetName(), defaultComparisonSetName());
  const TestSet old = resolveTestSet("brief_random_512");
  EXPECT_TRUE(sameComparisons(old.tests, builtinComparisonSet("brief_random_512").tests));
  EXPECT_TRUE(sameComparisons(builtinTestSet("brief_random_512").tests, old.tests));
  EXPECT_THROW(loadTestSetJson("/nonexistent/set.json"), std::runtime_error);
}
#pragma GCC diagnostic pop

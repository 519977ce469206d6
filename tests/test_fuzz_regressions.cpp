// Every seed and every kept fuzzing finding (fuzz/seeds/<target>, fuzz/regressions/<target>)
// goes through its parser again in every build, the sanitizer build included: a finding that
// comes back crashes this test. And scripts/fuzz.sh's modes fuzz every parser.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "fuzz_targets.hpp"
#include "test_data.hpp"

namespace fs = std::filesystem;

TEST(FuzzRegressions, EverySeedAndFindingParsesOrFailsCleanly) {
  size_t replayed = 0;
  for (const auto& target : mdbrief::fuzz::targets())
    for (const char* kind : {"seeds", "regressions"}) {
      const fs::path dir = mdbrief::testing::sourceDir() / "fuzz" / kind / target.name;
      if (!fs::is_directory(dir)) continue;
      for (const auto& entry : fs::directory_iterator(dir)) {
        std::ifstream f(entry.path(), std::ios::binary);
        const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
        SCOPED_TRACE(entry.path().string());
        target.run(bytes.data(), bytes.size());
        ++replayed;
      }
    }
  RecordProperty("replayed", static_cast<int>(replayed));
  EXPECT_GT(replayed, 5u) << "the seed corpora are missing";
}

namespace {

// The lines scripts/fuzz.sh prints for `mode` in a dry run (nothing is built or run).
std::set<std::string> fuzzPlan(const std::string& mode) {
  const std::string command = "env -u FUZZ_TARGETS -u FUZZ_SEED FUZZ_DRY_RUN=1 bash " +
                              (mdbrief::testing::sourceDir() / "scripts" / "fuzz.sh").string() + " " + mode;
  std::set<std::string> lines;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return lines;
  char buffer[256];
  while (std::fgets(buffer, sizeof buffer, pipe)) lines.insert(std::string(buffer));
  EXPECT_EQ(::pclose(pipe), 0) << command;
  return lines;
}

}  // namespace

TEST(FuzzScript, LongModeFuzzesEveryParserForTenMinutesAndCiModeForAMinuteWithAFixedSeed) {
  std::set<std::string> longPlan, ciPlan;
  for (const auto& target : mdbrief::fuzz::targets()) {
    longPlan.insert("fuzz plan: " + std::string(target.name) + " 600 s\n");
    ciPlan.insert("fuzz plan: " + std::string(target.name) + " 60 s, seed 1\n");
  }
  EXPECT_EQ(fuzzPlan("long"), longPlan);
  EXPECT_EQ(fuzzPlan(""), longPlan) << "long is the default";
  EXPECT_EQ(fuzzPlan("ci"), ciPlan);
}

// Every seed and every kept fuzzing finding (fuzz/seeds/<target>, fuzz/regressions/<target>)
// goes through its parser again in every build, the sanitizer build included: a finding that
// comes back crashes this test.
#include <filesystem>
#include <fstream>
#include <iterator>
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

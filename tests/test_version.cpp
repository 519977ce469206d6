// mdbrief/base/version.hpp: the headers' version and the linked library's agree and read as
// MAJOR.MINOR.PATCH.
#include <gtest/gtest.h>

#include <string>

#include "mdbrief/base/version.hpp"

TEST(Version, HeaderAndLibraryAgree) {
  const std::string fromMacros = std::to_string(MDBRIEF_VERSION_MAJOR) + "." + std::to_string(MDBRIEF_VERSION_MINOR) +
                                 "." + std::to_string(MDBRIEF_VERSION_PATCH);
  EXPECT_EQ(fromMacros, MDBRIEF_VERSION_STRING);
  EXPECT_STREQ(mdbrief::version(), MDBRIEF_VERSION_STRING);
}

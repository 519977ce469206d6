// The field tables (mdbrief/base/option_fields.hpp) drive every surface: for each numeric field, a
// value just outside its range gets the same message, "<option> must be <range>, got <value>",
// from the struct's validate(), FileStorage (MdBrief::read), the command line (mdbrief extract,
// mdbrief-train) and Python (tests/python/test_option_fields.py), each naming the option as
// that surface spells it.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <gtest/gtest.h>

#include "cli/commands.hpp"
#include "mdbrief/api/feature2d.hpp"
#include "mdbrief/match/guided_matcher.hpp"
#include "mdbrief/match/matcher.hpp"
#include "test_data.hpp"
#include "trainer/train_cli.hpp"
#include "trainer/training.hpp"

using namespace mdbrief;
namespace fs = std::filesystem;

namespace {

// A value just outside a numeric field's range (evaluated on `defaults`), below or above it.
struct OutOfRange {
  std::size_t field;
  FieldValue value;
  std::string problem;  // the message every surface gives after the option's name
};

template <typename Options>
std::vector<OutOfRange> valuesJustOutside(const OptionTable<Options>& table, const Options& defaults = {}) {
  std::vector<OutOfRange> out;
  for (std::size_t i = 0; i < table.size(); ++i) {
    const OptionField<Options>& f = table[i];
    if (f.type != FieldType::Integer && f.type != FieldType::Real) continue;
    const FieldRange r = f.range(defaults);
    const bool integer = f.type == FieldType::Integer;
    for (const bool above : {false, true}) {
      FieldValue v;
      if (integer) {
        v = static_cast<long long>(above ? r.high + 1 : r.low - 1);
      } else {
        const double bound = above ? r.high : r.low;
        const bool open = above ? r.highOpen : r.lowOpen;
        v = open ? bound : std::nextafter(bound, above ? HUGE_VAL : -HUGE_VAL);
      }
      out.push_back({i, v, "must be " + r.text(integer) + ", got " + fieldValueText(v)});
    }
  }
  return out;
}

// The value as a command line or a YAML file spells it (reals read back exactly).
std::string valueArgument(const FieldValue& v) {
  if (const auto* i = std::get_if<long long>(&v)) return std::to_string(*i);
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", std::get<double>(v));
  return buf;
}

std::string messageOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "no exception";
}

}  // namespace

TEST(OptionFields, EveryRuntimeTableHasUniqueSpellingsAndDefaultsInRange) {
  const auto check = [](const auto& table, const auto& defaults, const char* name) {
    std::set<std::string> keywords, flags, members;
    for (const auto& f : table) {
      EXPECT_TRUE(keywords.insert(f.keyword).second) << name << ": keyword " << f.keyword;
      if (f.flag) {
        EXPECT_TRUE(flags.insert(f.flag).second) << name << ": flag " << f.flag;
      }
      EXPECT_TRUE(members.insert(f.member).second) << name << ": member " << f.member;
      EXPECT_FALSE(fieldProblem(f, defaults)) << name << "." << f.member << " default out of its range";
    }
  };
  check(mdBriefOptionFields(), MdBriefOptions{}, "MdBriefOptions");
  check(matchOptionFields(), MatchOptions{}, "MatchOptions");
  check(train::trainOptionFields(), train::TrainOptions{}, "TrainOptions");
}

// appendNested built each outer field from the inner one's parts and left `unsettable` out, so
// GuidedMatchOptions' matching.ratio and max_distance could not be turned off through the outer
// table; the Python binding patched it (issue 45). A nested field is its inner field under a
// longer name: every property but the spelling of the member carries over.
TEST(OptionFields, NestedFieldsKeepEveryPropertyOfTheirInnerField) {
  const auto expectCarried = [](const auto& outer, const auto& inner, const std::string& prefix) {
    for (const auto& f : inner) {
      const auto g = std::find_if(outer.begin(), outer.end(),
                                  [&](const auto& o) { return o.member == prefix + "." + f.member; });
      ASSERT_NE(g, outer.end()) << prefix << "." << f.member;
      EXPECT_STREQ(g->keyword, f.keyword) << g->member;
      EXPECT_EQ(g->flag == nullptr, f.flag == nullptr) << g->member;
      if (f.flag && g->flag) {
        EXPECT_STREQ(g->flag, f.flag) << g->member;
      }
      EXPECT_EQ(g->type, f.type) << g->member;
      EXPECT_EQ(g->choices, f.choices) << g->member;
      EXPECT_EQ(g->unsettable, f.unsettable) << g->member;
    }
  };
  expectCarried(guidedMatchOptionFields(), matchOptionFields(), "matching");
  expectCarried(mdBriefOptionFields(), detectorOptionFields(), "detector");
  expectCarried(mdBriefOptionFields(), descriptorOptionFields(), "descriptor");
  expectCarried(detectorOptionFields(), pyramidOptionFields(), "pyramid");
  expectCarried(train::trainOptionFields(), train::extractionOptionFields(), "extraction");

  // Through the outer table, an unset value turns the nested option off.
  const OptionTable<GuidedMatchOptions>& guided = guidedMatchOptionFields();
  for (const char* keyword : {"ratio", "max_distance"}) {
    const OptionField<GuidedMatchOptions>& f = guided.at(findField(guided, keyword, &OptionField<GuidedMatchOptions>::keyword));
    EXPECT_TRUE(f.unsettable) << keyword;
    GuidedMatchOptions options;
    options.matching.ratio = 0.8;
    options.matching.maxDistance = 64;
    ASSERT_TRUE(f.set(options, std::monostate{})) << keyword;
    EXPECT_TRUE(std::holds_alternative<std::monostate>(f.get(options))) << keyword;
  }
}

TEST(OptionFields, StructValidateNamesTheMemberRangeAndValue) {
  const auto& table = mdBriefOptionFields();
  const auto cases = valuesJustOutside(table);
  ASSERT_GE(cases.size(), 2u * 20);
  for (const OutOfRange& c : cases) {
    MdBriefOptions o;
    ASSERT_TRUE(table[c.field].set(o, c.value)) << table[c.field].member;
    const std::string expected = "MdBriefOptions::" + table[c.field].member + " " + c.problem;
    try {
      validate(o);
      ADD_FAILURE() << expected << ": accepted";
    } catch (const OptionError& e) {
      EXPECT_EQ(e.what(), expected);
      EXPECT_EQ(e.field(), c.field);
    }
    EXPECT_EQ(messageOf([&] { MdBrief::create(nullptr, o); }), expected);
  }
  // Before: a 99999-pixel smoothing kernel was accepted and blurred for minutes.
  MdBriefOptions wide;
  wide.detector.pyramid.smoothingKernel = 99999;
  EXPECT_EQ(messageOf([&] { validate(wide); }),
            "MdBriefOptions::detector.pyramid.smoothingKernel must be an odd number in [1, 31], got 99999");
  // Before: border_margin=-100 was reported as harris_block_size.
  MdBriefOptions margin;
  margin.detector.borderMargin = -100;
  EXPECT_EQ(messageOf([&] { validate(margin); }),
            "MdBriefOptions::detector.borderMargin must be in [15, 1024], got -100");
  // The integers a member cannot hold are refused by setField with the same message, the range
  // the method's (the Hessian's maxima need inner levels).
  MdBriefOptions o;
  const std::size_t levels = findField(table, "levels", &OptionField<MdBriefOptions>::keyword);
  o.detector.method = DetectorMethod::ModOrb;
  EXPECT_EQ(messageOf([&] { setField(table, levels, o, FieldValue(1LL << 40), "levels"); }),
            "levels must be in [1, 32], got 1099511627776");
  o.detector.method = DetectorMethod::Hessian;
  EXPECT_EQ(messageOf([&] { setField(table, levels, o, FieldValue(1LL << 40), "levels"); }),
            "levels must be in [3, 32], got 1099511627776");
}

TEST(OptionFields, MatchOptionsValidateNamesTheMemberRangeAndValue) {
  // The members are float: just outside in float steps.
  const auto& table = matchOptionFields();
  const std::vector<std::pair<const char*, float>> cases = {{"ratio", 0.f},
                                                            {"ratio", std::nextafter(1.f, 2.f)},
                                                            {"max_distance", std::nextafter(0.f, -1.f)},
                                                            {"max_distance", std::nextafter(512.f, 600.f)}};
  for (const auto& [keyword, value] : cases) {
    const std::size_t i = findField(table, keyword, &OptionField<MatchOptions>::keyword);
    ASSERT_LT(i, table.size());
    MatchOptions o;
    table[i].set(o, FieldValue(static_cast<double>(value)));
    const std::string expected = "MatchOptions::" + table[i].member + " must be " + table[i].range(o).text(false) +
                                 ", got " + fieldValueText(static_cast<double>(value));
    EXPECT_EQ(messageOf([&] { validate(o); }), expected);
    EXPECT_EQ(messageOf([&] { matchBruteForce(cv::Mat(), cv::Mat(), o); }), expected);
  }
}

TEST(OptionFields, FileStorageNamesTheKeyRangeAndValue) {
  const auto& table = mdBriefOptionFields();
  const cv::Ptr<MdBrief> feature = MdBrief::create(nullptr, [] {
    MdBriefOptions o;
    o.descriptor.kind = DescriptorKind::Brief;
    return o;
  }());
  for (const OutOfRange& c : valuesJustOutside(table)) {
    const OptionField<MdBriefOptions>& f = table[c.field];
    // A Brief feature has no camera: keep the kind Brief unless the field is the kind itself.
    const std::string yaml = "%YAML:1.0\n---\nname: Feature2D.MdBrief\n" + std::string(f.section) + ":\n  " +
                             f.key() + ": " + valueArgument(c.value) + "\n";
    cv::FileStorage in(yaml, cv::FileStorage::READ | cv::FileStorage::MEMORY);
    const std::string expected = std::string(f.section) + "." + f.key() + " " + c.problem;
    try {
      feature->read(in.root());
      ADD_FAILURE() << expected << ": accepted";
    } catch (const OptionError& e) {
      EXPECT_EQ(e.what(), expected);
    }
    EXPECT_EQ(feature->options().descriptor.kind, DescriptorKind::Brief) << "a bad file changed the options";
  }
}

namespace {

struct CliRun {
  int code = -1;
  std::string err;
};

CliRun runMdbrief(std::vector<std::string> args) {
  args.insert(args.begin(), "mdbrief");
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  CliRun r;
  r.code = cli::runCli(static_cast<int>(argv.size()), argv.data(), {cli::addExtractCommand});
  r.err = ::testing::internal::GetCapturedStderr();
  ::testing::internal::GetCapturedStdout();
  return r;
}

}  // namespace

TEST(OptionFields, CommandLineNamesTheFlagRangeAndValue) {
  const auto& table = mdBriefOptionFields();
  mdbrief::testing::TempDir dir("option_flags");
  const std::string output = (dir.path / "out.yml").string();
  const std::string image = (dir.path / "not-decoded.png").string();
  std::ofstream(image) << "x";
  std::size_t checked = 0;
  for (const OutOfRange& c : valuesJustOutside(table)) {
    const char* flag = table[c.field].flag;
    ASSERT_NE(flag, nullptr) << table[c.field].member << " has no flag";
    // Checked before the image is read: it need only be a file.
    const CliRun r = runMdbrief({"extract", "--descriptor", "brief", std::string(flag) + "=" + valueArgument(c.value),
                                 image, "-o", output});
    EXPECT_EQ(r.code, 2) << flag;
    EXPECT_NE(r.err.find(std::string(flag) + " " + c.problem), std::string::npos) << r.err;
    ++checked;
  }
  EXPECT_GE(checked, 2u * 20);
}

TEST(OptionFields, TrainerStructAndCommandLineNameTheOptionRangeAndValue) {
  const auto& table = train::trainOptionFields();
  mdbrief::testing::TempDir dir("train_flags");
  const auto cases = valuesJustOutside(table);
  ASSERT_GE(cases.size(), 2u * 15);
  for (const OutOfRange& c : cases) {
    const OptionField<train::TrainOptions>& f = table[c.field];
    // Struct: fields whose member cannot hold the value (size_t, uint32_t) are refused by setField.
    train::TrainOptions o;
    const std::string structMessage =
        messageOf([&] { setField(table, c.field, o, c.value, "TrainOptions::" + f.member); train::train(o); });
    EXPECT_EQ(structMessage, "TrainOptions::" + f.member + " " + c.problem);
    // Command line.
    std::ostringstream out, err;
    const int code = train::runTrainCli({std::string(f.flag) + "=" + valueArgument(c.value), "--out",
                                         dir.path.string()},
                                        out, err);
    EXPECT_EQ(code, 2) << f.flag;
    EXPECT_EQ(err.str(), "error: " + std::string(f.flag) + " " + c.problem + "\n");
  }
  EXPECT_TRUE(fs::is_empty(dir.path));
}

// A flag given a value CLI11 cannot read as true or false (fuzz/regressions/train_config/
// crash-b93041fd...: `make-default = tpue` in a config) ended in std::terminate.
TEST(OptionFields, FlagValuesThatAreNeitherTrueNorFalseAreRefusedNamingTheFlag) {
  mdbrief::testing::TempDir dir("train_flag_values");
  const fs::path config = dir.path / "bad.toml";
  std::ofstream(config) << "make-default = tpue\n";
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"--make-default=tpue", "--out", dir.path.string()},
        std::vector<std::string>{"--make-default=99999999999999999999", "--out", dir.path.string()},
        std::vector<std::string>{"--config", config.string(), "--out", dir.path.string()}}) {
    std::ostringstream out, err;
    EXPECT_EQ(train::runTrainCli(args, out, err), 2) << args[0];
    EXPECT_NE(err.str().find("--make-default"), std::string::npos) << err.str();
    EXPECT_NE(err.str().find("neither true nor false"), std::string::npos) << err.str();
  }
  std::ostringstream out, err;
  EXPECT_EQ(train::runTrainCli({"--make-default=false", "--patches=-1", "--out", dir.path.string()}, out, err), 2);
  EXPECT_EQ(err.str().find("neither true nor false"), std::string::npos) << err.str();
  fs::remove(config);
  EXPECT_TRUE(fs::is_empty(dir.path));
}

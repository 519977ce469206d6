// Every input-file flag of every command of `mdbrief` and `mdbrief-eval`, and of the training
// tools (mdbrief-patchextract, mdbrief-train, mdbrief-train-vocabulary, mdbrief-pattern-random),
// is checked before any work (issue 45: `bench --image` read /dev/zero until memory ran out,
// blocked on a FIFO and called a folder an internal error; the training tools found such files
// only once they came to read them). The flags are found in the tools' CLI11 apps by their check
// (toolkit/input_file_flag.hpp); a text flag without it must be listed below as not an input
// file, so a new file flag cannot be added unchecked. Each checked flag is then given a folder, a
// FIFO, /dev/zero and a missing file in a subprocess with a time limit. The numeric flags are walked
// too: one that sets a library option takes exactly its option's range (toolkit/option_flags.hpp
// fieldRangeCheck), any other range must be listed as the tool's own; and a flag spelt as a field
// of the library's option tables is made from that field (its help is the field's).
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "eval/eval_cli.hpp"
#include "eval/eval_commands.hpp"
#include "patchextract/patch_extraction.hpp"
#include "patchextract/patchextract_cli.hpp"
#include "patchextract/view_change.hpp"
#include "trainer/pattern_random_cli.hpp"
#include "trainer/train_cli.hpp"
#include "trainer/train_options.hpp"
#include "vocabulary/train_vocabulary_cli.hpp"
#include "mdbrief/describe/descriptor.hpp"
#include "mdbrief/detect/detector.hpp"
#include "mdbrief/detect/image_pyramid.hpp"
#include "mdbrief/geometry/two_view.hpp"
#include "mdbrief/match/match_refinement.hpp"
#include "mdbrief/match/matcher.hpp"
#include "program_runner.hpp"
#include "toolkit/input_file_flag.hpp"
#include "toolkit/option_flags.hpp"

namespace {

namespace fs = std::filesystem;
using mdbrief::testing::ProgramRun;
using namespace mdbrief;

// Text flags that do not name an input file: outputs, names, folders, ids, sizes, and values
// that are either a built-in name or a file (read by the library, which checks the file itself).
const std::set<std::string> kNotInputFiles = {
    // mdbrief
    "extract --output", "extract --camera-id", "extract --camera-size", "extract --pattern",
    "match --output", "match --camera-id", "match --camera-size", "match --camera-b-id", "match --camera-b-size",
    "draw --output", "draw --camera-id", "draw --camera-size", "draw --other-camera-id", "draw --other-camera-size",
    "draw --pattern",
    "camera convert --output", "camera convert --camera-id", "camera convert --camera-size",
    "bench --camera-id", "bench --camera-size", "bench --level",
    // mdbrief-eval (sim and eval also in mdbrief)
    "sim --out", "sim --opencv-doc-dir",
    "eval --out", "eval --oxford-dir", "eval --sequences", "eval --opencv-doc-dir", "eval --user-camera-id",
    "eval --test-set",
    "pipelines --out", "pipelines --oxford-dir", "pipelines --sequences", "pipelines --opencv-doc-dir",
    "pipelines --user-camera-id", "pipelines --only",
    "tracker --out", "tracker --data", "tracker --opencv-doc-dir", "tracker --only", "tracker --stereo-refine",
    "map-poster-points --poster-dir",
    "retrieval --out", "retrieval --data", "retrieval --opencv-doc-dir", "retrieval --photos",
    "timing --out", "timing --camera-id", "timing --opencv-doc-dir",
    "export-user-sample --out", "export-user-sample --camera-id", "export-user-sample --opencv-doc-dir",
    "export-rotated-views --out", "export-rotated-views --camera-id",
    "held-out-images --out", "held-out-images --data", "held-out-images --opencv-doc-dir", "held-out-images --only",
    // the training tools: image folders (the vocabulary's also take image files, each checked
    // when the folders are listed), outputs and names
    "mdbrief-patchextract --images", "mdbrief-patchextract --camera-id", "mdbrief-patchextract --out",
    "mdbrief-train --images", "mdbrief-train --camera-id", "mdbrief-train --save-patches", "mdbrief-train --name",
    "mdbrief-train --out",
    "mdbrief-train-vocabulary --images", "mdbrief-train-vocabulary --camera-id", "mdbrief-train-vocabulary --out",
    "mdbrief-train-vocabulary --dbow2-text",
    "mdbrief-pattern-random --name", "mdbrief-pattern-random --out",
};

struct FileFlag {
  std::vector<std::string> command;  // the subcommand's words ({"camera", "convert"}); none for a tool's own flags
  std::string flag;                  // "--image", or a positional's name ("images")
  bool positional = false;
  int positionalIndex = 0;           // how many positionals come before it
};

bool takesText(const CLI::Option& option) {
  const std::string type = option.get_type_name();
  // Choices ("TEXT:{a,b}") are names, not files.
  return option.get_expected_min() > 0 && type.rfind("TEXT", 0) == 0 && type.find('{') == std::string::npos;
}

bool isInputFileFlag(CLI::Option& option) {
  try {
    option.get_validator(mdbrief::kInputFileCheck);
    return true;
  } catch (const CLI::OptionNotFound&) {
    return false;
  }
}

std::string flagName(const CLI::Option& option) {
  if (!option.nonpositional()) return option.get_name();
  return option.get_lnames().empty() ? "-" + option.get_snames().front() : "--" + option.get_lnames().front();
}

// The flags of app (named `name` in kNotInputFiles: a subcommand's path, or a tool's name) and of
// its subcommands (`camera convert`).
void collectFileFlags(CLI::App& app, const std::string& name, const std::vector<std::string>& words,
                      std::vector<FileFlag>& flags, std::vector<std::string>& unlisted) {
  int positionals = 0;
  for (CLI::Option* option : app.get_options()) {
    const bool positional = !option->nonpositional();
    const std::string flag = (name.empty() ? "" : name + " ") + flagName(*option);
    if (isInputFileFlag(*option))
      flags.push_back({words, flagName(*option), positional, positionals});
    // A hidden flag (group "") is an old spelling that only says what replaced it (addRenamedFlag).
    else if (takesText(*option) && !option->get_group().empty() && !kNotInputFiles.count(flag))
      unlisted.push_back(flag);
    positionals += positional;
  }
  for (CLI::App* command : app.get_subcommands({})) {
    std::vector<std::string> commandWords = words;
    commandWords.push_back(command->get_name());
    collectFileFlags(*command, name.empty() ? command->get_name() : name + " " + command->get_name(), commandWords,
                     flags, unlisted);
  }
}

std::vector<FileFlag> fileFlags(CLI::App& app, const std::string& name, std::vector<std::string>& unlisted) {
  std::vector<FileFlag> flags;
  collectFileFlags(app, name, {}, flags, unlisted);
  return flags;
}

void addMdbriefCommands(CLI::App& app) {
  for (const auto& add : {mdbrief::cli::addExtractCommand, mdbrief::cli::addMatchCommand, mdbrief::cli::addDrawCommand,
                          mdbrief::cli::addCameraCommand, mdbrief::cli::addBenchCommand})
    add(app);
  // mdbrief's sim and eval are mdbrief-eval's (cli/command_sim.cpp, command_eval.cpp).
  mdbrief::eval::addSimCommand(app);
  mdbrief::eval::addEvalCommand(app);
}

// The subcommand names `program --help` lists, so that the apps built here are the programs'.
std::set<std::string> listedCommands(const std::string& program) {
  const fs::path out = fs::temp_directory_path() / ("file_flags_help_" + std::to_string(::getpid()));
  const std::string command = "'" + program + "' --help > '" + out.string() + "'";
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  std::ifstream in(out);
  std::set<std::string> names;
  bool inList = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("Subcommands:", 0) == 0) inList = true;
    else if (inList && line.size() > 2 && line[0] == ' ' && line[2] != ' ')
      names.insert(line.substr(2, line.find(' ', 2) - 2));
  }
  fs::remove(out);
  return names;
}

std::set<std::string> commandNames(CLI::App& app) {
  std::set<std::string> names;
  for (CLI::App* command : app.get_subcommands({})) names.insert(command->get_name());
  return names;
}

class BadInputs : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("file_flags_" + std::to_string(::getpid()));
    fs::create_directories(dir_ / "a folder");
    ASSERT_EQ(::mkfifo((dir_ / "fifo").c_str(), 0600), 0);
    std::ofstream(dir_ / "regular.txt") << "x\n";
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Each flag with each bad file: exit 2 within the limit, the message naming the file and why.
  // `name`: the tool's, for a tool whose app is its own (no subcommands).
  void expectRefused(const std::string& program, CLI::App& app, const std::string& name = "") {
    std::vector<std::string> unlisted;
    const std::vector<FileFlag> flags = fileFlags(app, name, unlisted);
    EXPECT_TRUE(unlisted.empty()) << "text flags neither checked as input files (toolkit/input_file_flag.hpp) nor "
                                     "listed in kNotInputFiles: "
                                  << ::testing::PrintToString(unlisted);
    const std::map<std::string, std::string> bad = {{(dir_ / "a folder").string(), "is a folder"},
                                                    {(dir_ / "fifo").string(), "is a FIFO"},
                                                    {"/dev/zero", "is a character device"},
                                                    {(dir_ / "missing.txt").string(), "no such file"}};
    for (const FileFlag& flag : flags)
      for (const auto& [path, why] : bad) {
        std::vector<std::string> args = flag.command;
        if (flag.positional) {
          for (int i = 0; i < flag.positionalIndex; ++i) args.push_back((dir_ / "regular.txt").string());
        } else {
          args.push_back(flag.flag);
        }
        args.push_back(path);
        const ProgramRun run = mdbrief::testing::runProgram(program, args, std::chrono::seconds(30));
        const std::string what = program + " " + ::testing::PrintToString(args);
        EXPECT_EQ(run.code, 2) << what << ": " << run.err;
        EXPECT_NE(run.err.find(path + ": " + why), std::string::npos) << what << ": " << run.err;
      }
  }

  fs::path dir_;
};

TEST(FileFlags, TheAppsWalkedAreThePrograms) {
  CLI::App mdbrief, eval;
  addMdbriefCommands(mdbrief);
  mdbrief::eval::addEvalCommands(eval);
  EXPECT_EQ(commandNames(mdbrief), listedCommands(MDBRIEF_CLI_PATH));
  EXPECT_EQ(commandNames(eval), listedCommands(MDBRIEF_EVAL_PATH));
}

TEST_F(BadInputs, EveryFileFlagOfMdbriefRefusesAFolderAFifoAndADeviceBeforeAnyWork) {
  CLI::App app;
  addMdbriefCommands(app);
  expectRefused(MDBRIEF_CLI_PATH, app);
  std::vector<std::string> unlisted;
  EXPECT_FALSE(fileFlags(app, "", unlisted).empty());
}

TEST_F(BadInputs, EveryFileFlagOfMdbriefEvalRefusesAFolderAFifoAndADeviceBeforeAnyWork) {
  CLI::App app;
  mdbrief::eval::addEvalCommands(app);
  expectRefused(MDBRIEF_EVAL_PATH, app);
  std::vector<std::string> unlisted;
  EXPECT_FALSE(fileFlags(app, "", unlisted).empty());
}

// The training tools' apps as their programs build them (each program's --help is its app's), and
// the file flags each has.
struct TrainingTool {
  const char* name;
  const char* program;
  std::unique_ptr<CLI::App> (*commandLine)();
  std::set<std::string> fileFlags;
};

const std::vector<TrainingTool>& trainingTools() {
  static const std::vector<TrainingTool> tools = {
      {"mdbrief-patchextract", MDBRIEF_PATCHEXTRACT_PATH, train::patchExtractCommandLine, {"--camera", "--held-out"}},
      {"mdbrief-train", MDBRIEF_TRAIN_PATH, train::trainCommandLine,
       {"--camera", "--held-out", "--patches-file", "--config"}},
      {"mdbrief-train-vocabulary", MDBRIEF_TRAIN_VOCABULARY_PATH, vocab::trainVocabularyCommandLine,
       {"--camera", "--descriptors", "--masks", "--held-out"}},
      {"mdbrief-pattern-random", MDBRIEF_PATTERN_RANDOM_PATH, train::patternRandomCommandLine, {}},
  };
  return tools;
}

TEST(FileFlags, TheTrainingToolsAppsAreThePrograms) {
  for (const TrainingTool& tool : trainingTools()) {
    const std::unique_ptr<CLI::App> app = tool.commandLine();
    const ProgramRun help = mdbrief::testing::runProgram(tool.program, {"--help"}, std::chrono::seconds(30));
    EXPECT_EQ(help.code, 0) << tool.name << ": " << help.err;
    EXPECT_EQ(help.out, app->help()) << tool.name;
    std::vector<std::string> unlisted;
    std::set<std::string> checked;
    for (const FileFlag& flag : fileFlags(*app, tool.name, unlisted)) checked.insert(flag.flag);
    EXPECT_EQ(checked, tool.fileFlags) << tool.name;
  }
}

TEST_F(BadInputs, EveryFileFlagOfTheTrainingToolsRefusesAFolderAFifoADeviceAndAMissingFileBeforeAnyWork) {
  for (const TrainingTool& tool : trainingTools()) {
    SCOPED_TRACE(tool.name);
    const std::unique_ptr<CLI::App> app = tool.commandLine();
    expectRefused(tool.program, *app, tool.name);
  }
}

// Numeric flags that are parameters of the tools' own experiments or outputs, not of a library
// option.
const std::set<std::string> kToolOwnRanges = {
    "sim --views", "sim --recognition-views", "sim --keypoints", "sim --mask-deg",
    "sim --detected-views", "sim --detected-keypoints", "sim --mask-angles",
    "eval --poses", "eval --keypoints", "eval --radius",
    "pipelines --poses", "pipelines --budgets", "pipelines --radius",
    "tracker --budget", "tracker --ratios", "tracker --stereo-budget",
    "retrieval --training-count", "retrieval --branching", "retrieval --depth",
    "retrieval --recall-at",
    "timing --repeats", "timing --keypoints",
    "export-user-sample --poses", "export-rotated-views --views",
    "mdbrief-train-vocabulary --branching", "mdbrief-train-vocabulary --depth", "mdbrief-train-vocabulary --rounds",
    "mdbrief-train-vocabulary --mask-agreement",
    "mdbrief-pattern-random --tests",
};

struct TableField {
  std::string keyword;
  FieldRange range;
  bool integer;
};

std::vector<TableField> numericFields() {
  std::vector<TableField> fields;
  const auto add = [&](const auto& table, const auto& defaults) {
    for (const auto& f : table)
      if (f.keyword && (f.type == FieldType::Integer || f.type == FieldType::Real))
        fields.push_back({f.keyword, f.range(defaults), f.type == FieldType::Integer});
  };
  add(twoViewOptionFields(), TwoViewOptions{});
  add(pyramidOptionFields(), PyramidOptions{});
  add(detectorOptionFields(), DetectorOptions{});
  add(descriptorOptionFields(), DescriptorOptions{});
  add(matchOptionFields(), MatchOptions{});
  return fields;
}

std::string numberText(double v) {
  std::ostringstream text;
  text.precision(17);
  text << v;
  return text.str();
}

void walkOptions(CLI::App& app, const std::string& path, const std::function<void(const std::string&, CLI::Option&)>& visit) {
  for (CLI::App* command : app.get_subcommands({})) {
    const std::string commandPath = path.empty() ? command->get_name() : path + " " + command->get_name();
    for (CLI::Option* option : command->get_options()) visit(commandPath + " " + flagName(*option), *option);
    walkOptions(*command, commandPath, visit);
  }
}

// Every flag of every command of mdbrief and mdbrief-eval, and of the training tools, with its
// path ("bench --nfeatures", "mdbrief-train-vocabulary --bits").
void visitEveryToolFlag(const std::function<void(const std::string&, CLI::Option&)>& visit) {
  for (const bool eval : {false, true}) {
    CLI::App app;
    if (eval) mdbrief::eval::addEvalCommands(app);
    else addMdbriefCommands(app);
    walkOptions(app, "", visit);
  }
  for (const TrainingTool& tool : trainingTools()) {
    const std::unique_ptr<CLI::App> app = tool.commandLine();
    for (CLI::Option* option : app->get_options()) visit(std::string(tool.name) + " " + flagName(*option), *option);
  }
}

// Issue 45: --inlier-threshold took [0, 1e6] while the library's maxPixels is (0, 1000], so 0,
// 5000 or nan failed after the matching with a message about maxPixels.
TEST(FlagRanges, EveryFlagOfALibraryOptionTakesTheOptionsRangeAndNoOther) {
  const std::vector<TableField> fields = numericFields();
  std::set<std::string> fielded;
  std::vector<std::string> unlisted;
  const auto visit = [&](const std::string& name, CLI::Option& option) {
    for (const TableField& field : fields) {
      CLI::Validator* check = nullptr;
      try {
        check = option.get_validator(kOptionFieldCheck + field.keyword);
      } catch (const CLI::OptionNotFound&) {
        continue;
      }
      fielded.insert(name);
      const FieldRange& r = field.range;
      std::vector<double> probes{r.low, r.high};
      if (field.integer) {
        probes.insert(probes.end(), {r.low - 1, r.high + 1});
      } else {
        probes.insert(probes.end(), {std::nextafter(r.low, -HUGE_VAL), std::nextafter(r.high, HUGE_VAL),
                                     (r.low + r.high) / 2, std::nan(""), HUGE_VAL, -HUGE_VAL});
      }
      for (const double v : probes) {
        std::string text = numberText(v);
        EXPECT_EQ((*check)(text).empty(), r.contains(v)) << name << " " << text << " against " << field.keyword << " "
                                                         << r.text(field.integer);
      }
      return;
    }
    // CLI::Range's description: "<TYPE> in [low - high]".
    if (option.get_type_name().find(" in [") != std::string::npos && !kToolOwnRanges.count(name))
      unlisted.push_back(name);
  };
  visitEveryToolFlag(visit);
  EXPECT_TRUE(unlisted.empty()) << "ranges neither from an option table (fieldRangeCheck) nor listed as the tool's "
                                   "own: "
                                << ::testing::PrintToString(unlisted);
  for (const char* name : {"match --inlier-threshold", "draw --inlier-threshold", "pipelines --levels",
                           "pipelines --scale-factor", "pipelines --hessian-sigma", "pipelines --hessian-threshold",
                           "eval --support-scales", "bench --nfeatures", "sim --bits", "retrieval --nfeatures",
                           "mdbrief-train-vocabulary --nfeatures", "mdbrief-train-vocabulary --bits"})
    EXPECT_TRUE(fielded.count(name)) << name;
}

// Flags spelt as a field's of an option table that set an option of a struct without a table:
// the seed of a vocabulary's training (not TwoViewOptions::seed), and the random pattern's
// RandomPatternOptions (up to 4096 tests, where the trainer's TrainOptions learns at most 512).
const std::set<std::string> kSameNameOtherOption = {
    "retrieval --seed", "mdbrief-train-vocabulary --seed", "mdbrief-pattern-random --seed",
    "mdbrief-pattern-random --tests", "mdbrief-pattern-random --make-default"};

// Issue 46: bench and mdbrief-train-vocabulary spelt --nfeatures by hand, each with its own help
// and range (bench's [1, 100000] against the library's [1, 10000000]), and sim its own --bits. A
// flag spelt as a field's flag of an option table (the library's, the trainer's, the patch
// extraction's) is made from a field of that name (OptionFlags, or addFieldFlag for a tool that
// takes a few): its help holds the field's doc, so a change of the flag is one edit of the table.
// Numbers and switches: a text flag's name (--camera, --out) says too little to be one option.
TEST(FlagRanges, AFlagSpeltAsAnOptionsFlagIsMadeFromItsField) {
  std::multimap<std::string, std::string> docs;  // flag -> the doc of each field of that flag
  const auto add = [&](const auto& table) {
    for (const auto& f : table)
      if (f.flag && (f.type == FieldType::Integer || f.type == FieldType::Real || f.type == FieldType::Flag))
        docs.emplace(f.flag, f.doc);
  };
  add(pyramidOptionFields());
  add(detectorOptionFields());
  add(descriptorOptionFields());
  add(matchOptionFields());
  add(twoViewOptionFields());
  add(matchRefinementOptionFields());
  add(train::trainOptionFields());
  add(train::extractionOptionFields());
  add(train::viewChangeOptionFields());
  std::vector<std::string> byHand;
  std::set<std::string> made;
  visitEveryToolFlag([&](const std::string& name, CLI::Option& option) {
    const auto [first, last] = docs.equal_range(flagName(option));
    if (first == last || kSameNameOtherOption.count(name)) return;
    bool fromField = false;
    for (auto doc = first; doc != last; ++doc)
      fromField = fromField || option.get_description().find(doc->second) != std::string::npos;
    if (fromField) made.insert(name);
    else byHand.push_back(name);
  });
  EXPECT_TRUE(byHand.empty()) << "flags spelt as an option's but not made from its field: "
                              << ::testing::PrintToString(byHand);
  for (const char* name : {"extract --nfeatures", "bench --nfeatures", "mdbrief-train-vocabulary --nfeatures",
                           "retrieval --nfeatures", "mdbrief-train-vocabulary --bits", "sim --bits", "match --ratio",
                           "pipelines --spread"})
    EXPECT_TRUE(made.count(name)) << name;
}

}  // namespace

#pragma once
// mdbrief-train-vocabulary: trains a vocabulary (vocabulary_training.hpp) from training images
// described as the run time describes them (training_features.hpp) or from descriptor files
// (descriptor_npy.hpp), and writes it (mdbrief/recognition/vocabulary.hpp's file; optionally also DBoW2's
// text). In a library so tests run the whole tool in-process.
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace mdbrief::vocab {

// The tool's flags on an app that holds what they are parsed into (tests/test_cli_file_flags.cpp
// walks them); runTrainVocabularyCli parses this app.
std::unique_ptr<CLI::App> trainVocabularyCommandLine();

// args without the program name. Returns the exit code by the tools' rule
// (toolkit/tool_errors.hpp): 0 success, 2 bad input or a file that cannot be read or written
// (message on err naming the option or file and the problem), 1 an internal error.
// Progress and the summary go to out; progressTty draws the progress as a bar.
int runTrainVocabularyCli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
                          bool progressTty = false);

}  // namespace mdbrief::vocab

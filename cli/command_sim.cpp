// `mdbrief sim`: the paper's simulation, forwarded to the evaluation library (eval/,
// the same command as `mdbrief-eval sim`).
#include "cli/commands.hpp"
#include "eval/eval_commands.hpp"

namespace mdbrief::cli {

void addSimCommand(CLI::App& app) { eval::addSimCommand(app); }

}  // namespace mdbrief::cli

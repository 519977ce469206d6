// `mdbrief eval`: the precision-recall evaluation, forwarded to the evaluation library
// (eval/, the same command as `mdbrief-eval eval`).
#include "cli/commands.hpp"
#include "eval/eval_commands.hpp"

namespace mdbrief::cli {

void addEvalCommand(CLI::App& app) { eval::addEvalCommand(app); }

}  // namespace mdbrief::cli

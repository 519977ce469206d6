#pragma once
// The subcommands of mdbrief-eval (and of `mdbrief sim` / `mdbrief eval`): sim, eval, pipelines,
// tracker, map-poster-points, retrieval, timing, export-user-sample, export-rotated-views, held-out-images.
// Bad input (unreadable file, inconsistent flags) is reported by throwing InputError, whose
// message starts with the file or flag at fault (toolkit/tool_errors.hpp: the tool exits 2).
#include <CLI/CLI.hpp>

#include "toolkit/tool_errors.hpp"

namespace mdbrief::eval {

void addSimCommand(CLI::App& app);
void addEvalCommand(CLI::App& app);
void addPipelinesCommand(CLI::App& app);
void addTrackerCommand(CLI::App& app);         // tracker_command.cpp
void addMapPosterPointsCommand(CLI::App& app);  // tracker_command.cpp
void addRetrievalCommand(CLI::App& app);         // retrieval_command.cpp
void addTimingCommand(CLI::App& app);
void addExportUserSampleCommand(CLI::App& app);
void addExportRotatedViewsCommand(CLI::App& app);
void addHeldOutImagesCommand(CLI::App& app);

}  // namespace mdbrief::eval

#pragma once
// `dynamap map`'s command line as a job, and what the command says about a finished run: shared
// by the command and the Python bindings, so that both run the same job from the same options.

#include <string>
#include <vector>

#include "commands.h"
#include "dynamap/outputs/map_job.h"

namespace dynamap::app {

/// The command line of `dynamap map` (without the word map) as a job; false after --help (the
/// usage printed). Throws UsageError for a bad command line and ConfigError for a bad --config,
/// each with the message the command prints.
bool parseMapJob(const Args& args, MapJob& job, bool& verbose);

/// The warnings the command prints after a run, one line each without the "dynamap map: "
/// prefix: the reader's assumptions, records and scans skipped, timestamps going backwards,
/// and the input's fault when it ended in one.
std::vector<std::string> mapWarnings(const MapJobResult& r);

}  // namespace dynamap::app

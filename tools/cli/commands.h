// The `ellipsekit` subcommands. Each takes the arguments after its name and returns the exit
// status: 0 ok, 1 a file / detection problem (reported on stderr), 2 bad usage (UsageError).
#pragma once

#include <string>
#include <vector>

namespace ellipsekit::cli {

int RunDetect(const std::vector<std::string>& args);
int RunEval(const std::vector<std::string>& args);
int RunScenes(const std::vector<std::string>& args);
int RunDemo(const std::vector<std::string>& args);
int RunConform(const std::vector<std::string>& args);  // tools/cli/conform_command.cc
int RunTrack(const std::vector<std::string>& args);    // tools/cli/track_command.cc

extern const char kDetectUsage[];
extern const char kEvalUsage[];
extern const char kScenesUsage[];
extern const char kDemoUsage[];
extern const char kTrackUsage[];

}  // namespace ellipsekit::cli

// ellipsekit: command-line front end of the ellipse detector.
//
//   ellipsekit detect [--backend B] [--repeat R] [--warmup W] [--format txt|json] [--draw DIR] IMAGE...
//   ellipsekit eval DATASET_DIR [--backend B] [--per-image] [--json FILE]
//   ellipsekit scenes --out DIR [--count N] [--seed S]
//   ellipsekit demo [--out DIR]
//   ellipsekit track SEQ_DIR [--conveyor] [--radius R] [--latency S] --out FILE.jsonl
//
// Exit status: 0 ok, 1 a file or detection problem (each reported on stderr), 2 bad usage.
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "tools/cli/args.h"
#include "tools/cli/commands.h"

namespace {

constexpr char kUsage[] =
    "Usage: ellipsekit <command> [options]\n"
    "\n"
    "Finds ellipses in images (Dong et al., IEEE T-RO 2018).\n"
    "\n"
    "Commands:\n"
    "  detect IMAGE...      detect ellipses and print them (txt or json), optionally draw them\n"
    "  eval DATASET_DIR     detect on a dataset (images/, gt/) and print precision, recall, F-measure\n"
    "  scenes --out DIR     write a generated dataset of synthetic scenes with exact ground truth\n"
    "  demo [--out DIR]     detect on 12 generated scenes, write overlays and a summary\n"
    "  track SEQ_DIR        track cylinder tops in a sequence (depth, conveyor speed, grasps)\n"
    "\n"
    "Run 'ellipsekit <command> --help' for the options of a command.\n"
    "Exit status: 0 ok, 1 a file or detection problem (reported on stderr), 2 bad usage.\n";

}  // namespace

int main(int argc, char** argv) {
  using namespace ellipsekit::cli;
  if (argc < 2) {
    std::fputs(kUsage, stderr);
    return kExitUsage;
  }
  const std::string command = argv[1];
  if (command == "--help" || command == "-h" || command == "help") {
    std::fputs(kUsage, stdout);
    return kExitOk;
  }
  const std::vector<std::string> args(argv + 2, argv + argc);
  int (*run)(const std::vector<std::string>&) = nullptr;
  if (command == "detect") {
    run = RunDetect;
  } else if (command == "eval") {
    run = RunEval;
  } else if (command == "scenes") {
    run = RunScenes;
  } else if (command == "demo") {
    run = RunDemo;
  } else if (command == "conform") { run = RunConform;
  } else if (command == "track") {
    run = RunTrack;
  } else {
    std::fprintf(stderr, "ellipsekit: unknown command '%s' (run 'ellipsekit --help')\n",
                 command.c_str());
    return kExitUsage;
  }
  try {
    return run(args);
  } catch (const UsageError& e) {
    std::fprintf(stderr, "ellipsekit %s: %s (run 'ellipsekit %s --help')\n", command.c_str(),
                 e.what(), command.c_str());
    return kExitUsage;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ellipsekit %s: internal error: %s\n", command.c_str(), e.what());
    return kExitFailure;
  }
}

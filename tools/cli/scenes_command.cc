// ellipsekit scenes: write a generated dataset (tools/scenes, ellipsekit::scenes::WriteSceneDataset).
#include <cstdio>
#include <string>
#include <vector>

#include "tools/cli/args.h"
#include "tools/cli/commands.h"
#ifdef ELLIPSEKIT_HAVE_SCENES
#include "tools/scenes/scene_generator.h"
#endif

namespace ellipsekit::cli {

const char kScenesUsage[] =
    "Usage: ellipsekit scenes --out DIR [--count N] [--seed S]\n"
    "\n"
    "Writes N generated scenes (ray-cast cylinders, exact ground truth) as a dataset:\n"
    "DIR/images/ and DIR/gt/<stem>.txt, usable with 'ellipsekit eval DIR'.\n"
    "Scene i is RenderScene(MixSeed(S, i)).\n"
    "\n"
    "Options:\n"
    "  --out DIR         output directory (required)\n"
    "  --count N         number of scenes, N >= 1 (default 200)\n"
    "  --seed S          unsigned 64-bit seed (default 7)\n"
    "  -h, --help        this text\n";

int RunScenes(const std::vector<std::string>& argv) {
  std::string out;
  int count = 200;
  std::uint64_t seed = 7;
  ArgReader r(argv);
  while (r.Next()) {
    if (!r.IsFlag()) throw UsageError("unexpected argument '" + r.positional() + "'");
    const std::string& name = r.name();
    if (name == "--help" || name == "-h") {
      std::fputs(kScenesUsage, stdout);
      return kExitOk;
    } else if (name == "--out") {
      out = r.Value();
    } else if (name == "--count") {
      count = ParseIntValue(name, r.Value(), 1, 10000000);
    } else if (name == "--seed") {
      seed = ParseUint64Value(name, r.Value());
    } else {
      throw UsageError("unknown option '" + name + "'");
    }
  }
  if (out.empty()) throw UsageError("--out DIR is required");
#ifdef ELLIPSEKIT_HAVE_SCENES
  const Status st = scenes::WriteSceneDataset(out, count, seed);
  if (!st.ok()) {
    std::fprintf(stderr, "ellipsekit scenes: %s\n", st.message().c_str());
    return kExitFailure;
  }
  std::printf("wrote %d scenes (seed %llu) to %s (images/, gt/)\n", count,
              static_cast<unsigned long long>(seed), out.c_str());
  return kExitOk;
#else
  (void)seed;
  std::fprintf(stderr, "ellipsekit scenes: this build has no scene generator (tools/scenes)\n");
  return kExitFailure;
#endif
}

}  // namespace ellipsekit::cli

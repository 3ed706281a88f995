// ellipsekit scenes: write a generated dataset (tools/scenes, ellipsekit::scenes::WriteSceneDataset).
#include <cstdio>
#include <cstdlib>
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
    "       ellipsekit scenes --conveyor [--speed V] --out DIR [--seed S]\n"
    "\n"
    "Writes N generated scenes (ray-cast cylinders, exact ground truth) as a dataset:\n"
    "DIR/images/ and DIR/gt/<stem>.txt, usable with 'ellipsekit eval DIR'.\n"
    "Scene i is RenderScene(MixSeed(S, i)).\n"
    "With --conveyor, writes a sequence instead: a can riding a straight guide at V m/s, 30 fps,\n"
    "3 s (90 frames), turning round at the guide's ends: DIR/frames/NNNNNN.png, DIR/depth/NNNNNN.png\n"
    "(uint16 mm along the camera z axis, 0 = invalid), timestamps.txt, camera.json, conveyor.json,\n"
    "truth.jsonl (true top centres and ellipses per frame); input of 'ellipsekit track'.\n"
    "\n"
    "Options:\n"
    "  --out DIR         output directory (required)\n"
    "  --count N         number of scenes, N >= 1 (default 200)\n"
    "  --seed S          unsigned 64-bit seed (default 7)\n"
    "  --conveyor        write a conveyor sequence (see above)\n"
    "  --speed V         conveyor speed in m/s, 0 < V <= 10 (default 0.05; needs --conveyor)\n"
    "  -h, --help        this text\n";

int RunScenes(const std::vector<std::string>& argv) {
  std::string out;
  int count = 200;
  std::uint64_t seed = 7;
  bool conveyor = false, count_given = false;
  double speed = 0.05;
  std::string speed_text;
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
      count_given = true;
    } else if (name == "--seed") {
      seed = ParseUint64Value(name, r.Value());
    } else if (name == "--conveyor") {
      r.NoValue();
      conveyor = true;
    } else if (name == "--speed") {
      speed_text = r.Value();
      char* end = nullptr;
      speed = std::strtod(speed_text.c_str(), &end);
      if (speed_text.empty() || *end != '\0' || !(speed > 0 && speed <= 10))
        throw UsageError("--speed: bad value '" + speed_text + "' (metres per second, 0 < V <= 10)");
    } else {
      throw UsageError("unknown option '" + name + "'");
    }
  }
  if (out.empty()) throw UsageError("--out DIR is required");
  if (!conveyor && !speed_text.empty()) throw UsageError("--speed needs --conveyor");
  if (conveyor && count_given) throw UsageError("--count does not apply to --conveyor");
#ifdef ELLIPSEKIT_HAVE_SCENES
  if (conveyor) {
    scenes::ConveyorSceneOptions co;
    co.speed_m_s = speed;
    scenes::ConveyorSequence info;
    const Status cst = scenes::WriteConveyorSequence(out, seed, co, &info);
    if (!cst.ok()) {
      std::fprintf(stderr, "ellipsekit scenes: %s\n", cst.message().c_str());
      return kExitFailure;
    }
    std::printf("wrote conveyor sequence (%d frames, %.3f m/s, guide %.3f m, seed %llu) to %s\n", info.frames,
                info.speed_m_s, info.length_m, static_cast<unsigned long long>(seed), out.c_str());
    return kExitOk;
  }
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

// ellipsekit scenes: write a generated dataset (tools/scenes, ellipsekit::scenes::WriteSceneDataset).
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "tools/cli/args.h"
#include "tools/cli/commands.h"
#ifdef ELLIPSEKIT_HAVE_SCENES
#include "tools/scenes/crowded_scenes.h"
#include "tools/scenes/scene_generator.h"
#include "tools/scenes/tabletop_scenes.h"
#endif

namespace ellipsekit::cli {

const char kScenesUsage[] =
    "Usage: ellipsekit scenes --out DIR [--count N] [--seed S]\n"
    "       ellipsekit scenes --crowded [--layout L] [--objects N] --out DIR [--count N] [--seed S]\n"
    "       ellipsekit scenes --hard [--size WxH] [--bottles] --out DIR [--count N] [--seed S]\n"
    "       ellipsekit scenes --conveyor [--speed V] [--exposure T] --out DIR [--seed S]\n"
    "       ellipsekit scenes --stack|--crossing [--speed V] [--frames N] --out DIR [--seed S]\n"
    "\n"
    "Writes N generated scenes (ray-cast cylinders, exact ground truth) as a dataset:\n"
    "DIR/images/ and DIR/gt/<stem>.txt, usable with 'ellipsekit eval DIR'.\n"
    "Scene i is RenderScene(MixSeed(S, i)).\n"
    "With --crowded, crowded scenes instead (RenderCrowdedScene): one flat layout of 50-300 circles\n"
    "(dot or ring calibration grids, crates of can tops, trays of caps or open cups) under perspective,\n"
    "640x480 to 1920x1080; the truth lists every dot, both edges of every ring, every top's outer rim.\n"
    "With --hard, the hard tabletop set instead (RenderTabletopScene): 2-8 cans, cups, jars, wooden\n"
    "and cardboard cylinders among boxes that hide tops, tops cut by the frame's edge, textured\n"
    "tables, camera tilt 30-70 degrees at 0.4-1.2 m; also DIR/meta/<stem>.txt, one 'kind visible_fraction'\n"
    "per truth line, for 'ellipsekit eval DIR --by kind,size,visibility' (tools/scenes/tabletop_scenes.h).\n"
    "With --conveyor, writes a sequence instead: a can riding a straight guide at V m/s, 30 fps,\n"
    "3 s (90 frames), turning round at the guide's ends: DIR/frames/NNNNNN.png, DIR/depth/NNNNNN.png\n"
    "(uint16 mm along the camera z axis, 0 = invalid), timestamps.txt, camera.json, conveyor.json,\n"
    "truth.jsonl (true top centres and ellipses per frame); input of 'ellipsekit track'.\n"
    "With --stack, the same kind of sequence (no conveyor.json) of a static stacking scene: one can\n"
    "on the feed side (right half), one on the stack side (left half), N frames (default 20) with\n"
    "independent image and depth noise. With --crossing, two cans on parallel lanes moving in\n"
    "opposite directions at V m/s (default 0.05) and passing each other at mid-sequence (default 30\n"
    "frames). Camera 0.5-1.0 m from the tops; truth.jsonl has one entry per can.\n"
    "\n"
    "Options:\n"
    "  --out DIR         output directory (required)\n"
    "  --count N         number of scenes, N >= 1 (default 200)\n"
    "  --seed S          unsigned 64-bit seed (default 7)\n"
    "  --crowded         write crowded scenes (see above)\n"
    "  --layout L        with --crowded: any (default), dots, rings, cans, caps or cups\n"
    "  --objects N       with --crowded: objects per scene, 1 <= N <= 2000 (default: drawn, 50-300)\n"
    "  --clutter         with --crowded: bars and cables above the layout, marks on the table; the\n"
    "                    truth keeps the circles with >= half of the rim visible\n"
    "  --size WxH        with --crowded: frame size, 64..8192 each (default: drawn per scene from\n"
    "                    640x480, 1280x720, 1920x1080); with --hard: default 640x480\n"
    "  --hard            write the hard tabletop set (see above)\n"
    "  --bottles         with --hard: a quarter of the containers are capped bottles (a tall body,\n"
    "                    a rounded shoulder, a narrow neck and cap; the truth is the cap's top rim);\n"
    "                    without it, the fixed set of the README\n"
    "  --conveyor        write a conveyor sequence (see above)\n"
    "  --speed V         conveyor speed in m/s, 0 < V <= 10 (default 0.05; needs --conveyor or --crossing)\n"
    "  --exposure T      with --conveyor: shutter time in s, 0 <= T <= 1/30 (default 0): each image\n"
    "                    averages the can's motion over T (motion blur); truth and depth at mid-exposure\n"
    "  --stack           write a static stacking sequence (see above)\n"
    "  --crossing        write a sequence of two cans crossing (see above)\n"
    "  --frames N        frames of a --stack or --crossing sequence, 1 <= N <= 100000\n"
    "  --container K     with --conveyor, --stack or --crossing: what stands there, flat-can (default),\n"
    "                    recessed-can (rolled rim, lid 3-6 mm down), cup, filled-cup, jar or bottle\n"
    "                    (its cap); truth.jsonl then gives each top's rim circle\n"
    "                    (tools/scenes/scene_generator.h Container)\n"
    "  --metal-top       with --container: a specular metal lid\n"
    "  -h, --help        this text\n";

int RunScenes(const std::vector<std::string>& argv) {
  std::string out;
  int count = 200;
  std::uint64_t seed = 7;
  bool conveyor = false, count_given = false;
  bool stack = false, crossing = false, crowded = false, hard = false, clutter = false, bottles = false;
  std::string layout_name;
  int objects = 0;
  int width = 0, height = 0;
  int frames = 0;  // 0: the default of the sequence kind
  double speed = 0.05;
  std::string speed_text;
  double exposure = 0;
  bool exposure_given = false;
  std::string container_name;
  bool metal_top = false;
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
    } else if (name == "--crowded") {
      r.NoValue();
      crowded = true;
    } else if (name == "--hard") {
      r.NoValue();
      hard = true;
    } else if (name == "--bottles") {
      r.NoValue();
      bottles = true;
    } else if (name == "--clutter") {
      r.NoValue();
      clutter = true;
    } else if (name == "--layout") {
      layout_name = r.Value();
    } else if (name == "--size") {
      const std::string v = r.Value();
      const std::size_t x = v.find('x');
      if (x == std::string::npos) throw UsageError("--size: bad value '" + v + "' (WxH, e.g. 1280x720)");
      width = ParseIntValue(name, v.substr(0, x), 64, 8192);
      height = ParseIntValue(name, v.substr(x + 1), 64, 8192);
    } else if (name == "--objects") {
      objects = ParseIntValue(name, r.Value(), 1, 2000);
    } else if (name == "--conveyor") {
      r.NoValue();
      conveyor = true;
    } else if (name == "--stack") {
      r.NoValue();
      stack = true;
    } else if (name == "--crossing") {
      r.NoValue();
      crossing = true;
    } else if (name == "--container") {
      container_name = r.Value();
    } else if (name == "--metal-top") {
      r.NoValue();
      metal_top = true;
    } else if (name == "--frames") {
      frames = ParseIntValue(name, r.Value(), 1, 100000);
    } else if (name == "--speed") {
      speed_text = r.Value();
      char* end = nullptr;
      speed = std::strtod(speed_text.c_str(), &end);
      if (speed_text.empty() || *end != '\0' || !(speed > 0 && speed <= 10))
        throw UsageError("--speed: bad value '" + speed_text + "' (metres per second, 0 < V <= 10)");
    } else if (name == "--exposure") {
      const std::string v = r.Value();
      char* end = nullptr;
      exposure = std::strtod(v.c_str(), &end);
      exposure_given = true;
      if (v.empty() || *end != '\0' || !(exposure >= 0 && exposure <= 1.0 / 30))
        throw UsageError("--exposure: bad value '" + v + "' (seconds, 0 <= T <= 1/30)");
    } else {
      throw UsageError("unknown option '" + name + "'");
    }
  }
  if (out.empty()) throw UsageError("--out DIR is required");
  if (exposure_given && !conveyor) throw UsageError("--exposure needs --conveyor");
  if (static_cast<int>(conveyor) + static_cast<int>(stack) + static_cast<int>(crossing) + static_cast<int>(crowded) +
          static_cast<int>(hard) > 1)
    throw UsageError("--conveyor, --stack, --crossing, --crowded and --hard exclude each other");
  if (!crowded && (!layout_name.empty() || objects > 0 || clutter || (width > 0 && !hard)))
    throw UsageError("--layout, --objects, --clutter and --size need --crowded (--size also --hard)");
  if (bottles && !hard) throw UsageError("--bottles needs --hard");
  if (crossing && speed_text.empty()) speed = 0.05;
  if (!conveyor && !crossing && !speed_text.empty()) throw UsageError("--speed needs --conveyor");
  if (frames > 0 && !stack && !crossing) throw UsageError("--frames needs --stack or --crossing");
  if ((stack || crossing) && count_given) throw UsageError("--count does not apply to --stack or --crossing");
  if (conveyor && count_given) throw UsageError("--count does not apply to --conveyor");
  if ((!container_name.empty() || metal_top) && !conveyor && !stack && !crossing)
    throw UsageError("--container and --metal-top need --conveyor, --stack or --crossing");
  if (metal_top && container_name.empty()) throw UsageError("--metal-top needs --container");
#ifdef ELLIPSEKIT_HAVE_SCENES
  scenes::Container container = scenes::Container::kFlatCan;
  if (!container_name.empty() && !scenes::ParseContainer(container_name, &container))
    throw UsageError("--container: unknown container '" + container_name +
                     "' (flat-can, recessed-can, cup, filled-cup, jar, bottle)");
  if (conveyor) {
    scenes::ConveyorSceneOptions co;
    co.speed_m_s = speed;
    co.container = container;
    co.metal_top = metal_top;
    co.exposure_s = exposure;
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
  if (stack || crossing) {
    scenes::CanSceneOptions co;
    co.speed_m_s = crossing ? speed : 0;
    co.containers = {container, container};
    co.metal_top = metal_top;
    co.frames = frames > 0 ? frames : (crossing ? 30 : 20);
    scenes::CanSequence info;
    const Status cst = scenes::WriteCanSequence(out, seed, co, &info);
    if (!cst.ok()) {
      std::fprintf(stderr, "ellipsekit scenes: %s\n", cst.message().c_str());
      return kExitFailure;
    }
    std::printf("wrote %s sequence (%d frames, %.3f m/s, radii %.4f/%.4f m, seed %llu) to %s\n",
                crossing ? "crossing" : "stacking", info.frames, co.speed_m_s, info.radius_m[0], info.radius_m[1],
                static_cast<unsigned long long>(seed), out.c_str());
    return kExitOk;
  }
  if (hard) {
    scenes::TabletopSceneOptions to;
    to.bottles = bottles;
    if (width > 0) {
      to.width = width;
      to.height = height;
    }
    const Status tst = scenes::WriteTabletopDataset(out, count, seed, to);
    if (!tst.ok()) {
      std::fprintf(stderr, "ellipsekit scenes: %s\n", tst.message().c_str());
      return kExitFailure;
    }
    std::printf("wrote %d hard tabletop scenes (%dx%d, seed %llu%s) to %s (images/, gt/, meta/)\n", count, to.width,
                to.height, static_cast<unsigned long long>(seed), bottles ? ", with bottles" : "", out.c_str());
    return kExitOk;
  }
  if (crowded) {
    scenes::CrowdedSceneOptions co;
    co.objects = objects;
    co.clutter = clutter;
    co.width = width;
    co.height = height;
    if (!layout_name.empty() && !scenes::ParseCrowdedLayout(layout_name, &co.layout))
      throw UsageError("--layout: unknown layout '" + layout_name + "' (any, dots, rings, cans, caps, cups)");
    const Status cst = scenes::WriteCrowdedDataset(out, count, seed, co);
    if (!cst.ok()) {
      std::fprintf(stderr, "ellipsekit scenes: %s\n", cst.message().c_str());
      return kExitFailure;
    }
    std::printf("wrote %d crowded scenes (layout %s, seed %llu) to %s (images/, gt/)\n", count,
                scenes::CrowdedLayoutName(co.layout), static_cast<unsigned long long>(seed), out.c_str());
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

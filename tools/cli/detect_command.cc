// ellipsekit detect: run the detector on image files and print what it found.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "ellipsekit/detector.h"
#include "tools/cli/args.h"
#include "tools/cli/commands.h"
#include "tools/cli/draw.h"
#include "tools/cli/image_io.h"
#include "tools/cli/json.h"
#include "tools/cli/timing.h"
#include "tools/eval/ellipse_io.h"

namespace ellipsekit::cli {

const char kDetectUsage[] =
    "Usage: ellipsekit detect [options] IMAGE...\n"
    "\n"
    "Detects ellipses in each image (loaded as 8-bit gray: colour converted, 16-bit scaled).\n"
    "\n"
    "Options:\n"
    "  --backend B       auto (default), scalar, simd or vulkan\n"
    "  --option NAME=VALUE  set a detector option (repeatable; names as in ellipsekit/options.h)\n"
    "  --repeat R        timed detections per image, R >= 1 (default 1)\n"
    "  --warmup W        untimed detections per image before them, W >= 0 (default 1)\n"
    "  --format F        txt (default) or json\n"
    "  --exact           json: each ellipse's numbers and noise_sigma with 17 significant digits, so\n"
    "                    that read back they are the detector's doubles bit for bit (default: 4\n"
    "                    decimals for px, 6 for theta, score and noise_sigma)\n"
    "  --draw DIR        write DIR/<image stem>.png: the image with the ellipses drawn in green\n"
    "  -h, --help        this text\n"
    "\n"
    "txt output, per image:\n"
    "  # <image path> <number of ellipses> <median detect() ms>\n"
    "  cx cy a b theta            (one line per ellipse, best score first)\n"
    "json output: one array of {path, median_ms, backend, [simd_target,] [arc_backend (when the arc\n"
    "  stage ran elsewhere: Vulkan's on the CPU),] ellipses: [{cx, cy, a, b, theta, score}],\n"
    "  timings: {edges_ms, curves_ms, arcs_ms, fit_ms, validate_ms, total_ms} (per-stage medians),\n"
    "  counts: {edge_pixels, curves, arcs, pairs, triplets, candidates, noise_sigma,\n"
    "  denoise_passes, caps_hit}} (the last run;\n"
    "  caps_hit names the caps that bounded the work (CapName in ellipsekit/detector.h), [] when none).\n"
    "Conventions: pixel centres at integers, x right, y down; a >= b semi-axes in px; theta in rad,\n"
    "the major axis along (cos theta, sin theta) (OpenCV RotatedRect angle).\n"
    "A missing or unreadable image is reported on stderr, the others are processed, exit status 1.\n";

namespace {

struct DetectArgs {
  Options options;
  int repeat = 1;
  int warmup = 1;
  bool json = false;
  bool exact = false;  // --exact: round-trip digits for the ellipses
  std::string draw_dir;
  std::vector<std::string> images;
};

struct ImageReport {
  std::string path;
  double median_ms = 0;
  DetectionResult result;  // of the last timed run
  StageTimings timings;    // per-stage medians over the timed runs
};

StageTimings MedianTimings(const std::vector<StageTimings>& runs) {
  auto median_of = [&](double StageTimings::*field) {
    std::vector<double> v;
    for (const StageTimings& t : runs) v.push_back(t.*field);
    return Median(v);
  };
  StageTimings m;
  m.edges_ms = median_of(&StageTimings::edges_ms);
  m.curves_ms = median_of(&StageTimings::curves_ms);
  m.arcs_ms = median_of(&StageTimings::arcs_ms);
  m.fit_ms = median_of(&StageTimings::fit_ms);
  m.validate_ms = median_of(&StageTimings::validate_ms);
  m.total_ms = median_of(&StageTimings::total_ms);
  return m;
}

std::string ReportJson(const ImageReport& r, bool exact) {
  auto px = [&](double v) { return exact ? JsonExactNumber(v) : JsonNumber(v, 4); };
  auto unit = [&](double v) { return exact ? JsonExactNumber(v) : JsonNumber(v, 6); };
  std::string s = "  {\"path\": " + JsonString(r.path) + ", \"median_ms\": " + JsonNumber(r.median_ms, 4) +
                  ", \"backend\": " + JsonString(BackendName(r.result.backend)) +
                  (r.result.simd_target[0] != '\0' ? ", \"simd_target\": " + JsonString(r.result.simd_target) : "") +
                  (r.result.arc_backend != r.result.backend
                       ? ", \"arc_backend\": " + JsonString(BackendName(r.result.arc_backend)) : "") +
                  ",\n   \"ellipses\": [";
  for (std::size_t i = 0; i < r.result.ellipses.size(); ++i) {
    const Ellipse& e = r.result.ellipses[i];
    s += (i ? ",\n     " : "\n     ");
    s += "{\"cx\": " + px(e.cx) + ", \"cy\": " + px(e.cy) + ", \"a\": " + px(e.a) + ", \"b\": " + px(e.b) +
         ", \"theta\": " + unit(e.theta) + ", \"score\": " + unit(e.score) + "}";
  }
  s += r.result.ellipses.empty() ? "],\n" : "\n   ],\n";
  const StageTimings& t = r.timings;
  s += "   \"timings\": {\"edges_ms\": " + JsonNumber(t.edges_ms, 4) + ", \"curves_ms\": " +
       JsonNumber(t.curves_ms, 4) + ", \"arcs_ms\": " + JsonNumber(t.arcs_ms, 4) + ", \"fit_ms\": " +
       JsonNumber(t.fit_ms, 4) + ", \"validate_ms\": " + JsonNumber(t.validate_ms, 4) +
       ", \"total_ms\": " + JsonNumber(t.total_ms, 4) + "},\n";
  const DetectionResult& d = r.result;
  s += "   \"counts\": {\"edge_pixels\": " + std::to_string(d.num_edge_pixels) + ", \"curves\": " +
       std::to_string(d.num_curves) + ", \"arcs\": " + std::to_string(d.num_arcs) + ", \"pairs\": " +
       std::to_string(d.num_pairs) + ", \"triplets\": " + std::to_string(d.num_triplets) +
       ", \"candidates\": " + std::to_string(d.num_candidates) + ", \"noise_sigma\": " + unit(d.noise_sigma) +
       ", \"denoise_passes\": " + std::to_string(d.denoise_passes) +
       ", \"caps_hit\": [";
  bool first = true;
  for (const CapFlags flag : kAllCaps) {
    if ((d.caps_hit & flag) == 0) continue;
    s += (first ? "" : ", ") + JsonString(CapName(flag));
    first = false;
  }
  s += "]}}";
  return s;
}

DetectArgs ParseDetectArgs(const std::vector<std::string>& argv, bool* help) {
  DetectArgs a;
  ArgReader r(argv);
  while (r.Next()) {
    if (!r.IsFlag()) {
      a.images.push_back(r.positional());
      continue;
    }
    const std::string& name = r.name();
    if (name == "--help" || name == "-h") {
      *help = true;
      return a;
    } else if (ApplyDetectorFlag(name, &r, &a.options)) {
      // --backend, --option
    } else if (name == "--repeat") {
      a.repeat = ParseIntValue(name, r.Value(), 1, 1000000);
    } else if (name == "--warmup") {
      a.warmup = ParseIntValue(name, r.Value(), 0, 1000000);
    } else if (name == "--format") {
      const std::string v = r.Value();
      if (v != "txt" && v != "json") throw UsageError(name + ": bad value '" + v + "': expected txt or json");
      a.json = v == "json";
    } else if (name == "--exact") {
      a.exact = true;
    } else if (name == "--draw") {
      a.draw_dir = r.Value();
      if (a.draw_dir.empty()) throw UsageError("--draw needs a directory");
    } else {
      throw UsageError("unknown option '" + name + "'");
    }
  }
  if (a.images.empty()) throw UsageError("no image given");
  if (a.exact && !a.json) throw UsageError("--exact applies to --format json");
  return a;
}

}  // namespace

int RunDetect(const std::vector<std::string>& argv) {
  bool help = false;
  const DetectArgs args = ParseDetectArgs(argv, &help);
  if (help) {
    std::fputs(kDetectUsage, stdout);
    return kExitOk;
  }
  std::string error;
  if (!args.draw_dir.empty() && !EnsureDirectory(args.draw_dir, &error)) {
    std::fprintf(stderr, "ellipsekit detect: %s\n", error.c_str());
    return kExitFailure;
  }

  const Options& options = args.options;
  Detector detector(options);
  if (!detector.status().ok()) {
    std::fprintf(stderr, "ellipsekit detect: %s\n", detector.status().message().c_str());
    return kExitFailure;
  }
  if (!detector.backend_note().empty()) std::fprintf(stderr, "ellipsekit detect: note: %s\n", detector.backend_note().c_str());

  bool failed = false;
  bool first_json = true;
  if (args.json) std::fputs("[\n", stdout);
  for (const std::string& path : args.images) {
    LoadedImage image;
    if (!LoadImage(path, &image, &error)) {
      std::fprintf(stderr, "ellipsekit detect: %s: %s\n", path.c_str(), error.c_str());
      failed = true;
      continue;
    }
    if (!image.note.empty()) std::fprintf(stderr, "ellipsekit detect: %s: note: %s\n", path.c_str(), image.note.c_str());
    const ImageView view = ViewOf(image.gray);

    ImageReport report;
    report.path = path;
    Status st;
    for (int i = 0; i < args.warmup && st.ok(); ++i) st = detector.detect(view, &report.result);
    std::vector<double> ms;
    std::vector<StageTimings> stages;
    for (int i = 0; i < args.repeat && st.ok(); ++i) {
      const auto start = std::chrono::steady_clock::now();
      st = detector.detect(view, &report.result);
      ms.push_back(MillisecondsSince(start));
      stages.push_back(report.result.timings);
    }
    if (!st.ok()) {
      std::fprintf(stderr, "ellipsekit detect: %s: detection failed: %s\n", path.c_str(), st.message().c_str());
      failed = true;
      continue;
    }
    report.median_ms = Median(ms);
    report.timings = MedianTimings(stages);

    if (args.json) {
      std::fputs(first_json ? "" : ",\n", stdout);
      std::fputs(ReportJson(report, args.exact).c_str(), stdout);
      first_json = false;
    } else {
      std::printf("# %s %zu %.3f\n", path.c_str(), report.result.ellipses.size(), report.median_ms);
      for (const Ellipse& e : report.result.ellipses) std::printf("%s\n", eval::FormatEllipse(e).c_str());
    }
    std::fflush(stdout);

    if (!args.draw_dir.empty()) {
      cv::Mat overlay = image.color.clone();
      DrawEllipses(&overlay, report.result.ellipses, kGreen, 2);
      const std::string out =
          (std::filesystem::path(args.draw_dir) / (std::filesystem::path(path).stem().string() + ".png")).string();
      if (!WriteImageAtomically(out, overlay, &error)) {
        std::fprintf(stderr, "ellipsekit detect: %s: %s\n", out.c_str(), error.c_str());
        failed = true;
      }
    }
  }
  if (args.json) std::fputs(first_json ? "]\n" : "\n]\n", stdout);
  return failed ? kExitFailure : kExitOk;
}

}  // namespace ellipsekit::cli

// ellipsekit demo: 12 generated scenes (seed 1), detected and scored, with overlays and a summary.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "ellipsekit/detector.h"
#include "tools/cli/args.h"
#include "tools/cli/commands.h"
#include "tools/cli/draw.h"
#include "tools/cli/image_io.h"
#include "tools/cli/json.h"
#include "tools/cli/timing.h"
#include "tools/eval/ellipse_io.h"
#include "tools/eval/metrics.h"
#ifdef ELLIPSEKIT_HAVE_SCENES
#include "tools/scenes/scene_generator.h"
#endif

namespace ellipsekit::cli {

const char kDemoUsage[] =
    "Usage: ellipsekit demo [--out DIR] [--backend B]\n"
    "\n"
    "Renders 12 synthetic scenes (scene i = RenderScene(MixSeed(1, i))), detects ellipses and\n"
    "scores them (Jaccard > 0.8). Writes DIR/scene_NNNN.png overlays (ground truth thin red,\n"
    "detections green, correct detections marked with a yellow cross), DIR/summary.md and\n"
    "DIR/summary.json, and prints the totals.\n"
    "\n"
    "Options:\n"
    "  --out DIR         output directory (default out/demo)\n"
    "  --backend B       auto (default), scalar, simd or vulkan\n"
    "  --option NAME=VALUE  set a detector option (repeatable; names as in ellipsekit/options.h)\n"
    "  -h, --help        this text\n";

#ifdef ELLIPSEKIT_HAVE_SCENES
namespace {

constexpr int kDemoScenes = 12;
constexpr std::uint64_t kDemoSeed = 1;

struct DemoRow {
  std::string name;
  eval::MatchCounts counts;
  double ms = 0;
};

}  // namespace
#endif

int RunDemo(const std::vector<std::string>& argv) {
  std::string out = "out/demo";
  Options options;
  ArgReader r(argv);
  while (r.Next()) {
    if (!r.IsFlag()) throw UsageError("unexpected argument '" + r.positional() + "'");
    const std::string& name = r.name();
    if (name == "--help" || name == "-h") {
      std::fputs(kDemoUsage, stdout);
      return kExitOk;
    } else if (name == "--out") {
      out = r.Value();
      if (out.empty()) throw UsageError("--out needs a directory");
    } else if (ApplyDetectorFlag(name, &r, &options)) {
      // --backend, --option
    } else {
      throw UsageError("unknown option '" + name + "'");
    }
  }
#ifdef ELLIPSEKIT_HAVE_SCENES
  std::string error;
  if (!EnsureDirectory(out, &error)) {
    std::fprintf(stderr, "ellipsekit demo: %s\n", error.c_str());
    return kExitFailure;
  }
  Detector detector(options);
  if (!detector.status().ok()) {
    std::fprintf(stderr, "ellipsekit demo: %s\n", detector.status().message().c_str());
    return kExitFailure;
  }

  namespace fs = std::filesystem;
  std::vector<DemoRow> rows;
  eval::MatchCounts total;
  DetectionResult result;
  Backend ran = options.backend;
  for (int i = 0; i < kDemoScenes; ++i) {
    const scenes::Scene scene = scenes::RenderScene(scenes::MixSeed(kDemoSeed, static_cast<std::uint64_t>(i)));
    if (scene.gray.empty() || scene.gray.type() != CV_8UC1) {
      std::fprintf(stderr, "ellipsekit demo: scene %d: the generator returned no 8-bit gray image\n", i);
      return kExitFailure;
    }
    cv::Mat gray = scene.gray;
    if (!gray.isContinuous()) gray = gray.clone();
    const ImageView view = ViewOf(gray);
    Status st;
    if (i == 0) st = detector.detect(view, &result);  // untimed warm-up
    double ms = 0;
    if (st.ok()) {
      const auto start = std::chrono::steady_clock::now();
      st = detector.detect(view, &result);
      ms = MillisecondsSince(start);
    }
    if (!st.ok()) {
      std::fprintf(stderr, "ellipsekit demo: scene %d: detection failed: %s\n", i, st.message().c_str());
      return kExitFailure;
    }
    ran = result.backend;
    const eval::MatchResult match = eval::MatchEllipses(result.ellipses, scene.truth);

    char name[32];
    std::snprintf(name, sizeof name, "scene_%04d.png", i);
    cv::Mat overlay;
    cv::cvtColor(gray, overlay, cv::COLOR_GRAY2BGR);
    DrawEllipses(&overlay, scene.truth, kRed, 1);
    DrawEllipses(&overlay, result.ellipses, kGreen, 2);
    for (const eval::MatchPair& p : match.pairs) DrawCentreMark(&overlay, result.ellipses[p.detection], kYellow);
    char caption[128];
    std::snprintf(caption, sizeof caption, "truth %d  found %d  correct %d  %.2f ms", match.counts.truth,
                  match.counts.detected, match.counts.correct, ms);
    DrawCaption(&overlay, caption);
    const std::string path = (fs::path(out) / name).string();
    if (!WriteImageAtomically(path, overlay, &error)) {
      std::fprintf(stderr, "ellipsekit demo: %s: %s\n", path.c_str(), error.c_str());
      return kExitFailure;
    }
    rows.push_back({name, match.counts, ms});
    total += match.counts;
  }

  std::vector<double> times;
  for (const DemoRow& row : rows) times.push_back(row.ms);
  const double median_ms = Median(times);
  const double precision = eval::Precision(total), recall = eval::Recall(total);
  const double f = eval::FMeasure(precision, recall);

  std::string md = "# ellipsekit demo\n\n";
  md += "12 generated scenes (scene i = RenderScene(MixSeed(1, i))), backend `" + std::string(BackendName(ran)) +
        "`. A detection is correct when its Jaccard overlap with a ground-truth ellipse is > 0.8 "
        "(one-to-one matching).\nOverlays: ground truth thin red, detections green, correct detections "
        "marked with a yellow cross.\n\n";
  md += "| image | ground truth | found | correct | ms |\n|---|---:|---:|---:|---:|\n";
  std::string js = "{\n  \"backend\": " + JsonString(BackendName(ran)) + ",\n  \"seed\": 1,\n  \"images\": [";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const DemoRow& row = rows[i];
    char line[256];
    std::snprintf(line, sizeof line, "| [%s](%s) | %d | %d | %d | %.2f |\n", row.name.c_str(), row.name.c_str(),
                  row.counts.truth, row.counts.detected, row.counts.correct, row.ms);
    md += line;
    js += (i ? ",\n    " : "\n    ");
    js += "{\"image\": " + JsonString(row.name) + ", \"truth\": " + std::to_string(row.counts.truth) +
          ", \"found\": " + std::to_string(row.counts.detected) + ", \"correct\": " +
          std::to_string(row.counts.correct) + ", \"ms\": " + JsonNumber(row.ms, 4) + "}";
  }
  char totals[512];
  std::snprintf(totals, sizeof totals,
                "\n**Totals:** ground truth %d, found %d, correct %d; precision %.4f, recall %.4f, "
                "F-measure %.4f; median detect %.3f ms.\n",
                total.truth, total.detected, total.correct, precision, recall, f, median_ms);
  md += totals;
  js += "\n  ],\n  \"totals\": {\"truth\": " + std::to_string(total.truth) + ", \"found\": " +
        std::to_string(total.detected) + ", \"correct\": " + std::to_string(total.correct) +
        ", \"precision\": " + JsonNumber(precision) + ", \"recall\": " + JsonNumber(recall) +
        ", \"f_measure\": " + JsonNumber(f) + ", \"median_ms\": " + JsonNumber(median_ms, 4) + "}\n}\n";
  const std::string md_path = (fs::path(out) / "summary.md").string();
  const std::string json_path = (fs::path(out) / "summary.json").string();
  for (const auto& [path, text] : {std::pair{md_path, md}, std::pair{json_path, js}}) {
    if (Status st = eval::WriteFileAtomically(path, text); !st.ok()) {
      std::fprintf(stderr, "ellipsekit demo: %s\n", st.message().c_str());
      return kExitFailure;
    }
  }
  std::printf("wrote %d overlays %s/scene_0000.png .. scene_%04d.png\n", kDemoScenes, out.c_str(), kDemoScenes - 1);
  std::printf("summary: %s, %s\n", md_path.c_str(), json_path.c_str());
  std::printf("ground truth %d, found %d, correct %d\n", total.truth, total.detected, total.correct);
  std::printf("precision: %.4f\nrecall: %.4f\nF-measure: %.4f\nmedian detect ms: %.3f\n", precision, recall, f,
              median_ms);
  return kExitOk;
#else
  (void)options;
  std::fprintf(stderr, "ellipsekit demo: this build has no scene generator (tools/scenes)\n");
  return kExitFailure;
#endif
}

}  // namespace ellipsekit::cli

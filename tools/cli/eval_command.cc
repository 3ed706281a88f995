// ellipsekit eval: detect on every image of a dataset, match against the ground truth
// (tools/eval/metrics.h: Jaccard > 0.8, one-to-one, maximum cardinality) and print the totals.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "ellipsekit/detector.h"
#include "tools/cli/args.h"
#include "tools/cli/commands.h"
#include "tools/cli/image_io.h"
#include "tools/cli/json.h"
#include "tools/cli/timing.h"
#include "tools/eval/dataset.h"
#include "tools/eval/ellipse_io.h"
#include "tools/eval/metrics.h"

namespace ellipsekit::cli {

const char kEvalUsage[] =
    "Usage: ellipsekit eval DATASET_DIR [options]\n"
    "\n"
    "Detects on every image of DATASET_DIR (images/ and gt/<stem>.txt, see tools/eval/dataset.h)\n"
    "and scores the detections (Dong et al. 2018, sec. III-A): a detection is correct when its\n"
    "Jaccard overlap with a ground-truth ellipse is > 0.8; each ground truth and each detection is\n"
    "matched at most once (maximum matching). Counts are summed over the dataset, then\n"
    "precision = correct/detected (1 when nothing detected), recall = correct/truth (1 when no\n"
    "truth), F = 2PR/(P+R) (0 when P+R = 0). Time: median wall time of detect() over the images,\n"
    "after one untimed warm-up detection on the first image.\n"
    "\n"
    "Options:\n"
    "  --backend B       auto (default), scalar, simd or vulkan\n"
    "  --option NAME=VALUE  set a detector option (repeatable; names as in ellipsekit/options.h)\n"
    "  --per-image       print one line per image before the totals\n"
    "  --json FILE       also write everything as JSON to FILE\n"
    "  -h, --help        this text\n"
    "A progress bar goes to stderr when stdout is a terminal.\n";

namespace {

struct EvalArgs {
  std::string dataset;
  Options options;
  bool per_image = false;
  std::string json_path;
};

struct ImageScore {
  std::string stem, path;
  eval::MatchCounts counts;
  double ms = 0;
};

EvalArgs ParseEvalArgs(const std::vector<std::string>& argv, bool* help) {
  EvalArgs a;
  ArgReader r(argv);
  int positional = 0;
  while (r.Next()) {
    if (!r.IsFlag()) {
      if (positional++ > 0) throw UsageError("more than one dataset directory given");
      a.dataset = r.positional();
      continue;
    }
    const std::string& name = r.name();
    if (name == "--help" || name == "-h") {
      *help = true;
      return a;
    } else if (ApplyDetectorFlag(name, &r, &a.options)) {
      // --backend, --option
    } else if (name == "--per-image") {
      r.NoValue();
      a.per_image = true;
    } else if (name == "--json") {
      a.json_path = r.Value();
      if (a.json_path.empty()) throw UsageError("--json needs a file name");
    } else {
      throw UsageError("unknown option '" + name + "'");
    }
  }
  if (a.dataset.empty()) throw UsageError("no dataset directory given");
  return a;
}

void Progress(bool enabled, std::size_t done, std::size_t total) {
  if (!enabled) return;
  constexpr int kWidth = 30;
  const int filled = total ? static_cast<int>(kWidth * done / total) : kWidth;
  std::fprintf(stderr, "\r[%s%s] %zu/%zu", std::string(filled, '#').c_str(),
               std::string(kWidth - filled, ' ').c_str(), done, total);
  std::fflush(stderr);
}

void ClearProgress(bool enabled) {
  if (enabled) std::fputs("\r\033[K", stderr);
}

}  // namespace

int RunEval(const std::vector<std::string>& argv) {
  bool help = false;
  const EvalArgs args = ParseEvalArgs(argv, &help);
  if (help) {
    std::fputs(kEvalUsage, stdout);
    return kExitOk;
  }
  eval::Dataset dataset;
  if (Status st = eval::LoadDataset(args.dataset, &dataset); !st.ok()) {
    std::fprintf(stderr, "ellipsekit eval: %s\n", st.message().c_str());
    return kExitFailure;
  }
  const Options& options = args.options;
  Detector detector(options);
  if (!detector.status().ok()) {
    std::fprintf(stderr, "ellipsekit eval: %s\n", detector.status().message().c_str());
    return kExitFailure;
  }
  if (!detector.backend_note().empty()) std::fprintf(stderr, "ellipsekit eval: note: %s\n", detector.backend_note().c_str());

  const bool progress = ::isatty(STDOUT_FILENO) == 1;
  bool failed = false;
  bool warmed_up = false;
  Backend ran = args.options.backend;
  std::vector<ImageScore> scores;
  eval::MatchCounts total;
  DetectionResult result;
  std::string error;
  for (std::size_t i = 0; i < dataset.images.size(); ++i) {
    Progress(progress, i, dataset.images.size());
    const eval::DatasetImage& item = dataset.images[i];
    LoadedImage image;
    std::vector<Ellipse> truth;
    Status st;
    if (!LoadImage(item.image_path, &image, &error)) {
      st = Status(StatusCode::kInvalidArgument, item.image_path + ": " + error);
    } else if (st = eval::ReadEllipses(item.truth_path, &truth); st.ok()) {
      const ImageView view = ViewOf(image.gray);
      if (!warmed_up) {
        st = detector.detect(view, &result);
        warmed_up = true;
      }
      if (st.ok()) {
        const auto start = std::chrono::steady_clock::now();
        st = detector.detect(view, &result);
        const double ms = MillisecondsSince(start);
        if (st.ok()) {
          const auto boxes = dataset.dont_care.find(item.stem);
          const eval::MatchResult match = eval::MatchEllipses(
              result.ellipses, truth, eval::kOverlapThreshold,
              boxes == dataset.dont_care.end() ? std::vector<eval::BoundingBox>{} : boxes->second);
          scores.push_back({item.stem, item.image_path, match.counts, ms});
          total += match.counts;
          ran = result.backend;
        } else {
          st = Status(st.code(), item.image_path + ": detection failed: " + st.message());
        }
      } else {
        st = Status(st.code(), item.image_path + ": detection failed: " + st.message());
      }
    }
    if (!st.ok()) {
      ClearProgress(progress);
      std::fprintf(stderr, "ellipsekit eval: %s\n", st.message().c_str());
      failed = true;
      continue;
    }
    if (args.per_image) {
      ClearProgress(progress);
      const ImageScore& s = scores.back();
      std::printf("%-24s truth %3d  detected %3d  correct %3d  %9.3f ms\n", s.stem.c_str(),
                  s.counts.truth, s.counts.detected, s.counts.correct, s.ms);
      std::fflush(stdout);
    }
  }
  Progress(progress, dataset.images.size(), dataset.images.size());
  ClearProgress(progress);

  std::vector<double> times;
  for (const ImageScore& s : scores) times.push_back(s.ms);
  const double median_ms = Median(times);
  const double precision = eval::Precision(total), recall = eval::Recall(total);
  const double f = eval::FMeasure(precision, recall);

  std::printf("dataset: %s\n", args.dataset.c_str());
  std::printf("backend: %s\n", BackendName(ran));
  std::printf("images: %zu\n", scores.size());
  std::printf("ground truth: %d\n", total.truth);
  std::printf("detected: %d\n", total.detected);
  std::printf("correct: %d\n", total.correct);
  std::printf("precision: %.4f\n", precision);
  std::printf("recall: %.4f\n", recall);
  std::printf("F-measure: %.4f\n", f);
  std::printf("median detect ms: %.3f\n", median_ms);
  std::fflush(stdout);

  if (!args.json_path.empty()) {
    std::string j = "{\n  \"dataset\": " + JsonString(args.dataset) + ",\n  \"backend\": " +
                    JsonString(BackendName(ran)) + ",\n  \"overlap_threshold\": " +
                    JsonNumber(eval::kOverlapThreshold, 2) + ",\n  \"images\": [";
    for (std::size_t i = 0; i < scores.size(); ++i) {
      const ImageScore& s = scores[i];
      j += (i ? ",\n    " : "\n    ");
      j += "{\"stem\": " + JsonString(s.stem) + ", \"path\": " + JsonString(s.path) +
           ", \"truth\": " + std::to_string(s.counts.truth) + ", \"detected\": " +
           std::to_string(s.counts.detected) + ", \"correct\": " + std::to_string(s.counts.correct) +
           ", \"ms\": " + JsonNumber(s.ms, 4) + "}";
    }
    j += scores.empty() ? "],\n" : "\n  ],\n";
    j += "  \"totals\": {\"images\": " + std::to_string(scores.size()) + ", \"truth\": " +
         std::to_string(total.truth) + ", \"detected\": " + std::to_string(total.detected) +
         ", \"correct\": " + std::to_string(total.correct) + ", \"precision\": " +
         JsonNumber(precision) + ", \"recall\": " + JsonNumber(recall) + ", \"f_measure\": " +
         JsonNumber(f) + ", \"median_ms\": " + JsonNumber(median_ms, 4) + "},\n";
    j += "  \"failed\": " + std::string(failed ? "true" : "false") + "\n}\n";
    if (Status st = eval::WriteFileAtomically(args.json_path, j); !st.ok()) {
      std::fprintf(stderr, "ellipsekit eval: %s\n", st.message().c_str());
      return kExitFailure;
    }
  }
  return failed ? kExitFailure : kExitOk;
}

}  // namespace ellipsekit::cli

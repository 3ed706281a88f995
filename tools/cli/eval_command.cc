// ellipsekit eval: detect on every image of a dataset, match against the ground truth
// (tools/eval/metrics.h: Jaccard > 0.8, one-to-one, maximum cardinality) and print the totals.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "ellipsekit/detector.h"
#include "tools/cli/args.h"
#include "tools/cli/commands.h"
#include "tools/cli/draw.h"
#include "tools/cli/pr_plot.h"
#include "tools/cli/image_io.h"
#include "tools/cli/json.h"
#include "tools/cli/timing.h"
#include "tools/eval/breakdown.h"
#include "tools/eval/dataset.h"
#include "tools/eval/ellipse_io.h"
#include "tools/eval/errors.h"
#include "tools/eval/metrics.h"
#include "tools/eval/pr_curve.h"
#include "tools/eval/sensor_noise.h"
#include "tools/eval/shadows.h"

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
    "after one untimed warm-up detection on the first image. The errors: each missed truth\n"
    "ellipse is a near miss when some detection overlaps it by 0.5-0.8 (the right object, the\n"
    "wrong ellipse), and each false detection likewise when it overlaps a truth by 0.5-0.8.\n"
    "\n"
    "Options:\n"
    "  --backend B       auto (default), scalar, simd or vulkan\n"
    "  --option NAME=VALUE  set a detector option (repeatable; names as in ellipsekit/options.h)\n"
    "  --scale S         resize every image by S (0.1 to 8; cubic up, area down: the soft edges of a\n"
    "                    higher-resolution camera) and its truth alike (centres (c + 0.5) S - 0.5,\n"
    "                    axes S times), to measure how detection holds across resolutions\n"
    "  --contrast C      multiply every grey level by C (0.05 to 1; after --scale, before --noise;\n"
    "                    rounded): a dim exposure, every contrast C times, to measure low contrast\n"
    "  --shadow G        darken every image under three soft round shadows of gain G (0.05 to 1;\n"
    "                    after --contrast; placed by the image's stem, the same on every run): a dim\n"
    "                    region in a bright frame, to measure local contrast (tools/eval/shadows.h)\n"
    "  --noise SIGMA     add white Gaussian noise of standard deviation SIGMA grey levels (0 to 64) to\n"
    "                    every image (after --scale; rounded, saturated), drawn from a generator seeded\n"
    "                    by the image's stem, the same on every run: how detection holds on a noisy sensor\n"
    "  --per-image       print one line per image before the totals\n"
    "  --curve FILE.png  sweep the score threshold: write the precision-recall curve to FILE.png and\n"
    "                    its points to FILE.csv, print the average precision (tools/eval/pr_curve.h)\n"
    "  --write-scaled DIR  also write the frames as scored: DIR/images/<stem>.png (lossless) and\n"
    "                    DIR/gt/<stem>.txt (the truth mapped as for --scale), a dataset that other\n"
    "                    detectors can be run on\n"
    "  --draw DIR        write DIR/<image stem>.png: the (scaled) image with the truth in red, correct\n"
    "                    detections in green, false ones in yellow\n"
    "  --by LIST         also print recall per group: kind, size (semi-minor < 15, 15-30, >= 30 px),\n"
    "                    visibility (< 60 %, >= 60 % of the rim), a comma-separated list or 'all';\n"
    "                    kind and visibility read DIR/meta/<stem>.txt (tools/eval/breakdown.h)\n"
    "  --json FILE       also write everything as JSON to FILE, per image with the missed truth\n"
    "                    ellipses and the false detections, each with the index and overlap of\n"
    "                    the ellipse on the other side that overlaps it most (-1 and 0: none)\n"
    "  -h, --help        this text\n"
    "A progress bar goes to stderr when stdout is a terminal.\n";

namespace {

struct EvalArgs {
  std::string dataset;
  Options options;
  bool per_image = false;
  double scale = 1;
  double contrast = 1;  // --contrast
  double shadow = 1;    // --shadow
  double noise = 0;     // --noise
  std::string json_path;
  std::string draw_dir;
  std::string scaled_dir;  // --write-scaled
  std::string curve_path;
  std::vector<eval::GroupBy> by;  // --by
};

struct ImageScore {
  std::string stem, path;
  eval::MatchCounts counts;
  eval::ImageErrors errors;
  std::vector<Ellipse> truth, detections;  // kept for --json only
  double ms = 0;
};

// --json: each unmatched ellipse (`own` names its side; with_score: a detection's score too) with
// the other side's ellipse that overlaps it most (`other`: its index, -1 when none does).
std::string UnmatchedJson(const std::vector<eval::UnmatchedEllipse>& list, const std::vector<Ellipse>& ellipses,
                          const char* own, const char* other, bool with_score) {
  std::string j = "[";
  for (std::size_t k = 0; k < list.size(); ++k) {
    const eval::UnmatchedEllipse& u = list[k];
    const Ellipse& e = ellipses[static_cast<std::size_t>(u.index)];
    j += (k ? ", " : "");
    j += "{\"" + std::string(own) + "\": " + std::to_string(u.index) + ", \"cx\": " + JsonNumber(e.cx, 4) +
         ", \"cy\": " + JsonNumber(e.cy, 4) + ", \"a\": " + JsonNumber(e.a, 4) + ", \"b\": " + JsonNumber(e.b, 4) +
         ", \"theta\": " + JsonNumber(e.theta);
    if (with_score) j += ", \"score\": " + JsonNumber(e.score);
    j += ", \"" + std::string(other) + "\": " + std::to_string(u.nearest) + ", \"best_overlap\": " +
         JsonNumber(u.best_overlap, 4) + "}";
  }
  return j + "]";
}

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
    } else if (name == "--curve") {
      a.curve_path = r.Value();
      if (std::filesystem::path(a.curve_path).extension() != ".png") throw UsageError("--curve needs a .png file name");
    } else if (name == "--write-scaled") {
      a.scaled_dir = r.Value();
      if (a.scaled_dir.empty()) throw UsageError("--write-scaled needs a directory");
    } else if (name == "--draw") {
      a.draw_dir = r.Value();
      if (a.draw_dir.empty()) throw UsageError("--draw needs a directory");
    } else if (name == "--scale") {
      a.scale = ParseDoubleValue(name, r.Value(), 0.1, 8);
    } else if (name == "--contrast") {
      a.contrast = ParseDoubleValue(name, r.Value(), 0.05, 1);
    } else if (name == "--shadow") {
      a.shadow = ParseDoubleValue(name, r.Value(), 0.05, 1);
    } else if (name == "--noise") {
      a.noise = ParseDoubleValue(name, r.Value(), 0, 64);
    } else if (name == "--by") {
      const std::string v = r.Value();
      if (!eval::ParseGroupBy(v, &a.by)) throw UsageError("--by: bad value '" + v + "' (kind, size, visibility, all)");
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

// --scale: the image resized by `scale` (cubic when enlarging, area when reducing) and the truth
// mapped alike, pixel centres at integers on both sides.
void Rescale(double scale, cv::Mat* gray, std::vector<Ellipse>* truth) {
  const int w = std::max(1, static_cast<int>(std::lround(gray->cols * scale)));
  const int h = std::max(1, static_cast<int>(std::lround(gray->rows * scale)));
  const double sx = static_cast<double>(w) / gray->cols, sy = static_cast<double>(h) / gray->rows;
  cv::Mat resized;
  cv::resize(*gray, resized, cv::Size(w, h), 0, 0, scale > 1 ? cv::INTER_CUBIC : cv::INTER_AREA);
  *gray = resized;
  for (Ellipse& e : *truth) {
    e.cx = (e.cx + 0.5) * sx - 0.5;
    e.cy = (e.cy + 0.5) * sy - 0.5;
    e.a *= scale;
    e.b *= scale;
  }
}

// --draw: the truth in red (thin), correct detections in green, false ones in yellow.
Status DrawMatches(const std::string& dir, const std::string& stem, const cv::Mat& gray,
                   const std::vector<Ellipse>& truth, const std::vector<Ellipse>& detected,
                   const eval::MatchResult& match) {
  cv::Mat overlay;
  cv::cvtColor(gray, overlay, cv::COLOR_GRAY2BGR);
  DrawEllipses(&overlay, truth, kRed, 1);
  for (std::size_t i = 0; i < detected.size(); ++i) {
    const bool correct = i < match.truth_of_detection.size() && match.truth_of_detection[i] >= 0;
    DrawEllipse(&overlay, detected[i], correct ? kGreen : kYellow, 1);
  }
  const std::string out = (std::filesystem::path(dir) / (stem + ".png")).string();
  std::string error;
  if (!WriteImageAtomically(out, overlay, &error)) return {StatusCode::kInternal, out + ": " + error};
  return Status::Ok();
}

// --write-scaled: the frame and its truth as they were scored, as a dataset of its own.
Status WriteScaled(const std::string& dir, const std::string& stem, const cv::Mat& gray,
                   const std::vector<Ellipse>& truth) {
  const std::filesystem::path root(dir);
  const std::string image = (root / "images" / (stem + ".png")).string();
  std::string error;
  if (!WriteImageAtomically(image, gray, &error)) return {StatusCode::kInternal, image + ": " + error};
  return eval::WriteEllipses((root / "gt" / (stem + ".txt")).string(), truth);
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

  std::string error;
  if (!args.draw_dir.empty() && !EnsureDirectory(args.draw_dir, &error)) {
    std::fprintf(stderr, "ellipsekit eval: %s\n", error.c_str());
    return kExitFailure;
  }
  for (const char* sub : {"images", "gt"}) {
    if (!args.scaled_dir.empty() && !EnsureDirectory((std::filesystem::path(args.scaled_dir) / sub).string(), &error)) {
      std::fprintf(stderr, "ellipsekit eval: %s\n", error.c_str());
      return kExitFailure;
    }
  }
  if (const std::string parent = std::filesystem::path(args.curve_path).parent_path().string();
      !args.curve_path.empty() && !parent.empty() && !EnsureDirectory(parent, &error)) {
    std::fprintf(stderr, "ellipsekit eval: %s\n", error.c_str());
    return kExitFailure;
  }
  const bool progress = ::isatty(STDOUT_FILENO) == 1;
  bool failed = false;
  bool warmed_up = false;
  Backend ran = args.options.backend;
  std::vector<ImageScore> scores;
  std::vector<eval::ScoredDetection> scored;  // --curve
  eval::MatchCounts total;
  eval::ErrorCounts errors;
  eval::RecallBreakdown breakdown(args.by);  // --by
  DetectionResult result;
  for (std::size_t i = 0; i < dataset.images.size(); ++i) {
    Progress(progress, i, dataset.images.size());
    const eval::DatasetImage& item = dataset.images[i];
    LoadedImage image;
    std::vector<Ellipse> truth;
    Status st;
    if (!LoadImage(item.image_path, &image, &error)) {
      st = Status(StatusCode::kInvalidArgument, item.image_path + ": " + error);
    } else if (st = eval::ReadEllipses(item.truth_path, &truth); st.ok()) {
      if (args.scale != 1) Rescale(args.scale, &image.gray, &truth);
      if (args.contrast != 1) image.gray.convertTo(image.gray, CV_8U, args.contrast);  // --contrast
      eval::AddShadows(args.shadow, eval::StemSeed(item.stem), &image.gray);              // --shadow
      eval::AddSensorNoise(args.noise, eval::StemSeed(item.stem), &image.gray);           // --noise
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
          scores.push_back({item.stem, item.image_path, match.counts, eval::ClassifyErrors(result.ellipses, truth, match), {}, {}, ms});
          errors += eval::CountErrors(scores.back().errors);
          if (!args.json_path.empty()) {
            scores.back().truth = truth;
            scores.back().detections = result.ellipses;
          }
          for (std::size_t d = 0; d < result.ellipses.size(); ++d) {
            if (d < match.detection_ignored.size() && match.detection_ignored[d]) continue;
            scored.push_back({result.ellipses[d].score, match.truth_of_detection[d] >= 0});
          }
          if (!args.by.empty()) st = breakdown.AddImage(args.dataset, item.stem, truth, match);
          if (st.ok() && !args.draw_dir.empty()) st = DrawMatches(args.draw_dir, item.stem, image.gray, truth, result.ellipses, match);
          if (st.ok() && !args.scaled_dir.empty()) st = WriteScaled(args.scaled_dir, item.stem, image.gray, truth);
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
  std::printf("missed: %d (near misses, a detection overlaps by %.1f-%.1f: %d)\n", errors.missed,
              eval::kNearMissOverlap, eval::kOverlapThreshold, errors.missed_near);
  std::printf("false: %d (overlapping a truth by %.1f-%.1f: %d)\n", errors.false_detections, eval::kNearMissOverlap,
              eval::kOverlapThreshold, errors.false_near);
  std::printf("median detect ms: %.3f\n", median_ms);
  if (!args.by.empty()) std::fputs(breakdown.Format().c_str(), stdout);
  if (!args.curve_path.empty()) {
    const eval::PrCurve curve = eval::ComputePrCurve(scored, total.truth);
    std::printf("average precision: %.4f\n", curve.average_precision);
    const std::string csv = std::filesystem::path(args.curve_path).replace_extension(".csv").string();
    if (!WritePrCurve(curve, std::filesystem::path(args.dataset).filename().string(), args.curve_path, csv, &error)) {
      std::fprintf(stderr, "ellipsekit eval: %s\n", error.c_str());
      failed = true;
    }
  }
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
           ", \"ms\": " + JsonNumber(s.ms, 4) + ",\n     \"missed\": " +
           UnmatchedJson(s.errors.missed, s.truth, "truth", "detection", false) + ",\n     \"false\": " +
           UnmatchedJson(s.errors.false_detections, s.detections, "detection", "truth", true) + "}";
    }
    j += scores.empty() ? "],\n" : "\n  ],\n";
    j += "  \"totals\": {\"images\": " + std::to_string(scores.size()) + ", \"truth\": " +
         std::to_string(total.truth) + ", \"detected\": " + std::to_string(total.detected) +
         ", \"correct\": " + std::to_string(total.correct) + ", \"precision\": " +
         JsonNumber(precision) + ", \"recall\": " + JsonNumber(recall) + ", \"f_measure\": " +
         JsonNumber(f) + ", \"median_ms\": " + JsonNumber(median_ms, 4) + ", \"missed\": " +
         std::to_string(errors.missed) + ", \"missed_near\": " + std::to_string(errors.missed_near) +
         ", \"false\": " + std::to_string(errors.false_detections) + ", \"false_near\": " +
         std::to_string(errors.false_near) + "},\n";
    j += "  \"failed\": " + std::string(failed ? "true" : "false") + "\n}\n";
    if (Status st = eval::WriteFileAtomically(args.json_path, j); !st.ok()) {
      std::fprintf(stderr, "ellipsekit eval: %s\n", st.message().c_str());
      return kExitFailure;
    }
  }
  return failed ? kExitFailure : kExitOk;
}

}  // namespace ellipsekit::cli

// A program that uses only the installed ellipsekit headers and library.
// Built twice by tests/install/install_consumer.sh: with find_package(ellipsekit) and with pkg-config.
// Exit status 0 when the API behaves; 1 with a message otherwise.
#include <ellipsekit/ellipsekit.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

namespace {

int failures = 0;

void Check(bool condition, const char* what) {
  if (!condition) {
    std::fprintf(stderr, "consumer: FAILED: %s\n", what);
    ++failures;
  }
}

// A bright ring (an elliptic annulus, 3 px wide) on a dark background, anti-aliased by 4x4
// supersampling. The rows are padded (stride > width) so the stride handling is exercised too.
struct Ring {
  static constexpr int kWidth = 160;
  static constexpr int kHeight = 120;
  static constexpr int kStride = 176;
  static constexpr double kCx = 80.0, kCy = 58.0, kA = 45.0, kB = 30.0, kTheta = 0.4;
  std::vector<std::uint8_t> pixels = std::vector<std::uint8_t>(kStride * kHeight, 0xEE);

  Ring() {
    const double c = std::cos(kTheta), s = std::sin(kTheta);
    for (int y = 0; y < kHeight; ++y) {
      for (int x = 0; x < kWidth; ++x) {
        int inside = 0;
        for (int sy = 0; sy < 4; ++sy) {
          for (int sx = 0; sx < 4; ++sx) {
            const double dx = x + (sx + 0.5) / 4 - 0.5 - kCx;
            const double dy = y + (sy + 0.5) / 4 - 0.5 - kCy;
            const double u = dx * c + dy * s;   // along the major axis
            const double v = -dx * s + dy * c;  // along the minor axis
            // Outer ellipse (a, b) minus inner ellipse (a - 3, b - 3).
            const double outer = (u * u) / (kA * kA) + (v * v) / (kB * kB);
            const double inner = (u * u) / ((kA - 3) * (kA - 3)) + (v * v) / ((kB - 3) * (kB - 3));
            inside += (outer <= 1.0 && inner > 1.0) ? 1 : 0;
          }
        }
        pixels[y * kStride + x] = static_cast<std::uint8_t>(20 + inside * 200 / 16);
      }
    }
  }

  ellipsekit::ImageView view() const {
    ellipsekit::ImageView v;
    v.data = pixels.data();
    v.width = kWidth;
    v.height = kHeight;
    v.stride = kStride;
    return v;
  }
};

}  // namespace

int main() {
  ellipsekit::Options options;  // the paper's defaults, Backend::kAuto
  Check(ellipsekit::ValidateOptions(options).ok(), "default options validate");

  ellipsekit::Detector detector(options);
  Check(detector.status().ok(), "detector constructed with default options is ok");

  // 1. A real frame: detect() must succeed.
  const Ring ring;
  ellipsekit::DetectionResult result;
  const ellipsekit::Status st = detector.detect(ring.view(), &result);
  Check(st.ok(), "detect() on a synthetic ring returns ok");
  if (!st.ok()) std::fprintf(stderr, "consumer: detect() said: %s\n", st.message().c_str());
  std::printf("consumer: backend %s, %zu ellipse(s), %d edge px, %d arcs, %.3f ms\n",
              ellipsekit::BackendName(result.backend), result.ellipses.size(), result.num_edge_pixels,
              result.num_arcs, result.timings.total_ms);
  for (const ellipsekit::Ellipse& e : result.ellipses) {
    std::printf("consumer:   cx %.1f cy %.1f a %.1f b %.1f theta %.3f score %.2f\n", e.cx, e.cy, e.a, e.b,
                e.theta, e.score);
  }
  // Detection quality is the end-to-end tests' job; this test proves the package links and runs.
  // Still, say so when the ring's centre was not among the results.
  bool near = false;
  for (const ellipsekit::Ellipse& e : result.ellipses) {
    near = near || (std::hypot(e.cx - Ring::kCx, e.cy - Ring::kCy) < 3.0);
  }
  if (!near) std::printf("consumer: note: no ellipse found near the ring's centre\n");

  // 2. Bad input is an error with a message, never a crash.
  ellipsekit::ImageView null_view = ring.view();
  null_view.data = nullptr;
  const ellipsekit::Status null_st = detector.detect(null_view, &result);
  Check(!null_st.ok(), "detect() on a null-data view returns a non-ok status");
  Check(null_st.code() == ellipsekit::StatusCode::kInvalidArgument, "null data is kInvalidArgument");
  Check(!null_st.message().empty(), "the null-data status has a message");
  std::printf("consumer: null data -> \"%s\"\n", null_st.message().c_str());

  ellipsekit::ImageView narrow_stride = ring.view();
  narrow_stride.stride = Ring::kWidth - 1;
  Check(!detector.detect(narrow_stride, &result).ok(), "detect() with stride < width returns non-ok");

  if (failures != 0) {
    std::fprintf(stderr, "consumer: %d check(s) failed\n", failures);
    return 1;
  }
  std::printf("consumer: OK\n");
  return 0;
}

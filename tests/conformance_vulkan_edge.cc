// Conformance: the Vulkan edge stage (runtime/vulkan_edge_stage.h) against the scalar kernels,
// bit for bit: dx, dy and the sign-classified edge map, with and without the Gaussian pre-filter.
// No Vulkan device -> the tests skip with the reason, except under CI=true (CI has lavapipe),
// where that is a failure. ELLIPSEKIT_VK_TIMING=1 also prints warm timings (best of 10).
#include <gtest/gtest.h>

#if defined(ELLIPSEKIT_HAVE_VULKAN)

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <unistd.h>

#include <opencv2/imgcodecs.hpp>

#include "ellipsekit/options.h"
#include "runtime/vulkan_edge_stage.h"
#include "tests/stage_test_util.h"

namespace ellipsekit {
namespace {

using stage_test::Edges;
using stage_test::ScalarEdges;
using stage_test::ViewOf;

#define REQUIRE_VULKAN(stage) REQUIRE_VULKAN_STAGE(VulkanEdgeStage, stage, "Vulkan device")

// First mismatch, for a readable failure.
template <typename T>
std::string FirstDiff(const std::vector<T>& a, const std::vector<T>& b, int w) {
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i] != b[i])
      return "at (" + std::to_string(i % w) + ", " + std::to_string(i / w) + "): scalar " + std::to_string(a[i]) +
             ", vulkan " + std::to_string(b[i]);
  return "";
}

void ExpectSame(VulkanEdgeStage* stage, const ImageView& image, const Options& o, const std::string& what) {
  Edges want, got;
  ScalarEdges(image, o, &want);
  const std::size_t n = static_cast<std::size_t>(image.width) * image.height;
  // Sentinel-filled outputs: every element must be written.
  got.dx.assign(n, 0x5a5a);
  got.dy.assign(n, 0x5a5a);
  got.edge_map.assign(n, 0xa5);
  const Status st = stage->Run(image, o, got.dx.data(), got.dy.data(), got.edge_map.data());
  ASSERT_TRUE(st.ok()) << what << ": " << st.message();
  const std::string tag = what + (o.gaussian_blur ? " (blur)" : " (no blur)");
  EXPECT_TRUE(want.dx == got.dx) << tag << " dx " << FirstDiff(want.dx, got.dx, image.width);
  EXPECT_TRUE(want.dy == got.dy) << tag << " dy " << FirstDiff(want.dy, got.dy, image.width);
  EXPECT_TRUE(want.edge_map == got.edge_map) << tag << " edge_map " << FirstDiff(want.edge_map, got.edge_map, image.width);
}

void ExpectSameBothBlurs(VulkanEdgeStage* stage, const ImageView& image, const std::string& what) {
  for (bool blur : {true, false}) {
    Options o;
    o.gaussian_blur = blur;
    ExpectSame(stage, image, o, what);
  }
}

std::vector<std::uint8_t> Noise(int w, int h, std::ptrdiff_t stride, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<std::uint8_t> img(static_cast<std::size_t>(stride) * h, 0xee);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img[y * stride + x] = static_cast<std::uint8_t>(rng() & 255);
  return img;
}

// Random filled rectangles and discs: long, connected edges (many hysteresis tiles crossed).
std::vector<std::uint8_t> Shapes(int w, int h, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<std::uint8_t> img(static_cast<std::size_t>(w) * h);
  for (auto& v : img) v = static_cast<std::uint8_t>(100 + rng() % 8);
  for (int s = 0; s < 40; ++s) {
    const int cx = rng() % w, cy = rng() % h, r = 3 + rng() % std::max(4, std::min(w, h) / 4);
    const std::uint8_t v = static_cast<std::uint8_t>(rng() & 255);
    const bool disc = rng() & 1;
    for (int y = std::max(0, cy - r); y < std::min(h, cy + r); ++y)
      for (int x = std::max(0, cx - r); x < std::min(w, cx + r); ++x)
        if (!disc || (x - cx) * (x - cx) + (y - cy) * (y - cy) < r * r) img[y * w + x] = v;
  }
  return img;
}

TEST(ConformanceVulkanEdge, RandomSizes) {
  REQUIRE_VULKAN(stage);
  const int sizes[][2] = {{1, 1}, {2, 3}, {7, 5}, {33, 17}, {640, 480}, {1920, 1080}};
  std::uint32_t seed = 1234;
  for (const auto& s : sizes) {
    const int w = s[0], h = s[1];
    auto noise = Noise(w, h, w, seed++);
    ExpectSameBothBlurs(stage, ImageView{noise.data(), w, h, w}, "noise " + std::to_string(w) + "x" + std::to_string(h));
    auto shapes = Shapes(w, h, seed++);
    ExpectSameBothBlurs(stage, ImageView{shapes.data(), w, h, w}, "shapes " + std::to_string(w) + "x" + std::to_string(h));
  }
}

// Dim frames, whose strongest gradients stay under canny_contrast_ref: the device lowers the
// threshold floor from its own quantiles (kernels/canny_thresholds.h) exactly as the host does.
// Each frame is checked to be one where the lowered floor, above Q(900) and under min_high, is the
// high threshold: set by the contrast (a little noise) or by the noise bound 3 x Q(500) (more).
// Noise spreads the magnitudes over every level, so a floor one level off shows.
TEST(ConformanceVulkanEdge, DimFramesLowerTheFloor) {
  REQUIRE_VULKAN(stage);
  std::uint32_t seed = 300;
  for (const int noise : {2, 9}) {
    for (const auto& s : {std::pair{640, 480}, std::pair{333, 250}, std::pair{1280, 720}}) {
      const int w = s.first, h = s.second;
      const std::string what = "dim shapes " + std::to_string(w) + "x" + std::to_string(h) + ", noise " + std::to_string(noise);
      auto img = Shapes(w, h, seed++);
      std::mt19937 rng(seed);
      for (auto& v : img) v = static_cast<std::uint8_t>(100 + v / 8 + rng() % noise);  // contrast / 8
      const ImageView view{img.data(), w, h, w};
      const Options o;
      Edges e;
      ScalarEdges(view, o, &e);
      const int high = e.tiles.frame.high;
      // Q(permille) of the same histogram: the thresholds without a floor.
      auto quantile = [&](int permille) { return ThresholdsFromHistogram(e.hist.data(), permille, 0, 0, 0).high; };
      ASSERT_GT(high, quantile(900)) << what << ": the floor must decide";
      ASSERT_LT(high, o.canny_min_high) << what << ": the floor must be lowered";
      if (noise > 2) ASSERT_EQ(high, kNoiseFloorFactor * quantile(kNoisePermille)) << what << ": the noise must set it";
      ExpectSameBothBlurs(stage, view, what);
    }
  }
}

// Frames with a shadow (grey levels / 3 left of a slanted line): the device picks every tile's
// thresholds from its own tiles' maxima (kernels/canny_thresholds.h) exactly as the host does, at
// every tile size. The frames of each tile size are checked to hold tiles whose pair is lowered by
// their contrast, tiles lowered to the bound, and tiles that keep the frame's pair.
TEST(ConformanceVulkanEdge, ShadowedFramesLowerTileThresholds) {
  REQUIRE_VULKAN(stage);
  std::uint32_t seed = 500;
  for (const int tile : {32, 64, 128, 0}) {
    int by_contrast = 0, bounded = 0, kept = 0;
    for (const auto& s : {std::pair{640, 480}, std::pair{333, 250}, std::pair{1280, 720}}) {
      const int w = s.first, h = s.second;
      const std::string what = "shadowed shapes " + std::to_string(w) + "x" + std::to_string(h) + ", tile " +
                               std::to_string(tile);
      auto img = Shapes(w, h, seed++);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          if (2 * x + y < w) img[y * w + x] = static_cast<std::uint8_t>(img[y * w + x] / 3);
      const ImageView view{img.data(), w, h, w};
      Options o;
      o.canny_tile = tile;
      Edges e;
      ScalarEdges(view, o, &e);
      const CannyTiles& t = e.tiles;
      const int bound = std::max(t.frame.high / 4, t.frame.noise);
      for (const std::int32_t high : t.high) {
        kept += high == t.frame.high;
        bounded += high == bound;
        by_contrast += high < t.frame.high && high > bound;
      }
      for (bool blur : {true, false}) {
        o.gaussian_blur = blur;
        ExpectSame(stage, view, o, what);
      }
    }
    const std::string what = "tile " + std::to_string(tile);
    EXPECT_GT(kept, 0) << what << ": bright tiles keep the frame's pair";
    if (tile == 0) {
      EXPECT_EQ(by_contrast + bounded, 0) << what << ": one tile per frame keeps the frame's pair";
    } else {
      EXPECT_GT(by_contrast, 0) << what << ": some tiles must be lowered by their contrast";
      EXPECT_GT(bounded, 0) << what << ": some tiles must reach the bound";
    }
  }
}

TEST(ConformanceVulkanEdge, OddSizesAndPaddedStride) {
  REQUIRE_VULKAN(stage);
  const int sizes[][2] = {{3, 1}, {1, 4}, {15, 16}, {16, 15}, {17, 17}, {255, 3}, {3, 257}, {101, 67}};
  std::uint32_t seed = 99;
  for (const auto& s : sizes) {
    const int w = s[0], h = s[1];
    const std::ptrdiff_t stride = w + 13;
    auto img = Noise(w, h, stride, seed++);
    ExpectSameBothBlurs(stage, ImageView{img.data(), w, h, stride}, "padded " + std::to_string(w) + "x" + std::to_string(h));
  }
}

TEST(ConformanceVulkanEdge, FlatImages) {
  REQUIRE_VULKAN(stage);
  for (int v : {0, 1, 128, 255}) {
    for (const auto& s : {std::pair{1, 1}, std::pair{33, 17}, std::pair{640, 480}}) {
      std::vector<std::uint8_t> img(static_cast<std::size_t>(s.first) * s.second, static_cast<std::uint8_t>(v));
      ExpectSameBothBlurs(stage, ImageView{img.data(), s.first, s.second, s.first},
                          "flat " + std::to_string(v) + " " + std::to_string(s.first) + "x" + std::to_string(s.second));
    }
  }
}

// A 1-px serpentine whose brightness rises along the path: only its bright end is strong, the
// rest weak, so hysteresis must walk the whole path across many strips (many passes).
std::vector<std::uint8_t> Serpentine(int w, int h) {
  std::vector<std::uint8_t> img(static_cast<std::size_t>(w) * h, 0);
  int step = 0;
  const int total = (h / 4) * (w - 4);
  for (int row = 0; row < h / 4 - 1; ++row) {
    const int y = 2 + 4 * row;
    for (int i = 0; i < w - 4; ++i) {
      const int x = (row % 2 == 0) ? 2 + i : w - 3 - i;
      img[y * w + x] = static_cast<std::uint8_t>(40 + (215 * step++) / total);
    }
    const int xe = (row % 2 == 0) ? w - 3 : 2;
    for (int k = 1; k < 4; ++k) img[(y + k) * w + xe] = static_cast<std::uint8_t>(40 + (215 * step) / total);
  }
  return img;
}
Options SerpentineOptions() {
  Options o;
  o.gaussian_blur = false;
  o.canny_min_high = 600;
  o.canny_low_permille = 50;
  return o;
}

TEST(ConformanceVulkanEdge, LongHysteresisChain) {
  REQUIRE_VULKAN(stage);
  const auto img = Serpentine(256, 256);
  ExpectSame(stage, ImageView{img.data(), 256, 256, 256}, SerpentineOptions(), "serpentine");
}

// The blocks' passes before the one-workgroup hysteresis (hysteresis_blocks.comp) leave the edge
// map unchanged, however many run: the GPU's path (none by default on a CPU device) forced here,
// on frames whose chains cross many blocks and strips. Then the default again.
TEST(ConformanceVulkanEdge, HysteresisBlockPasses) {
  REQUIRE_VULKAN(stage);
  const bool cpu = stage->context()->properties().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
  if (!stage->context()->memory_model()) {
    EXPECT_EQ(stage->hysteresis_block_passes(1080), 0) << "no blocks' pass without the memory model";
  } else {
    EXPECT_EQ(stage->hysteresis_block_passes(1080), cpu ? 0 : 5) << "default: one pass per 256 rows on a GPU";
  }
  const auto serpentine = Serpentine(300, 520);
  const auto shapes = Shapes(640, 480, 23);
  const auto noise = Noise(200, 150, 200, 5);
  for (int passes : {1, 3, 0}) {
    stage->set_hysteresis_block_passes(passes);
    const std::string tag = std::to_string(passes) + " blocks' passes: ";
    ExpectSame(stage, ImageView{serpentine.data(), 300, 520, 300}, SerpentineOptions(), tag + "serpentine");
    ExpectSameBothBlurs(stage, ImageView{shapes.data(), 640, 480, 640}, tag + "shapes 640x480");
    ExpectSameBothBlurs(stage, ImageView{noise.data(), 200, 150, 200}, tag + "noise 200x150");
  }
  stage->set_hysteresis_block_passes(-1);
}

TEST(ConformanceVulkanEdge, SizeChangesReuseAndRecreate) {
  REQUIRE_VULKAN(stage);
  std::uint32_t seed = 7;
  for (const auto& s : {std::pair{64, 48}, std::pair{64, 48}, std::pair{31, 9}, std::pair{64, 48}}) {
    auto img = Shapes(s.first, s.second, seed++);
    ExpectSameBothBlurs(stage, ImageView{img.data(), s.first, s.second, s.first}, "resize");
  }
}

// ELLIPSEKIT_VK_PIPELINE_CACHE (runtime/vulkan_context.h): the cache is written to the file when
// the stage goes away, a new stage starts from it with the same results, and a file that is not a
// pipeline cache is no obstacle (it is replaced by a real one, never left as <file>.tmp).
TEST(ConformanceVulkanEdge, PipelineCacheFile) {
  REQUIRE_VULKAN(shared);  // a device exists (or the test skips / fails in CI)
  namespace fs = std::filesystem;
  const fs::path file = fs::temp_directory_path() / ("ellipsekit_vk_cache_" + std::to_string(::getpid()) + ".bin");
  fs::remove(file);
  ::setenv("ELLIPSEKIT_VK_PIPELINE_CACHE", file.c_str(), 1);
  auto img = Shapes(64, 48, 3);
  const ImageView view{img.data(), 64, 48, 64};
  for (const char* start : {"no file", "the file written before", "a file of garbage"}) {
    if (std::string(start) == "a file of garbage") std::ofstream(file, std::ios::binary | std::ios::trunc) << "not a cache";
    {
      std::unique_ptr<VulkanEdgeStage> stage;
      const Status st = VulkanEdgeStage::Create(&stage);
      ASSERT_TRUE(st.ok()) << start << ": " << st.message();
      ExpectSameBothBlurs(stage.get(), view, std::string("pipeline cache from ") + start);
    }
    // A pipeline cache starts with its header: uint32 header length (32 for version one).
    std::ifstream in(file, std::ios::binary);
    std::uint32_t header_length = 0;
    in.read(reinterpret_cast<char*>(&header_length), sizeof header_length);
    EXPECT_TRUE(in.good()) << start << ": no cache file written";
    EXPECT_GE(header_length, 32u) << start;
    EXPECT_GE(fs::file_size(file), header_length) << start;
    EXPECT_FALSE(fs::exists(file.string() + ".tmp")) << start;
  }
  ::unsetenv("ELLIPSEKIT_VK_PIPELINE_CACHE");
  fs::remove(file);
}

TEST(ConformanceVulkanEdge, DatasetImages) {
  REQUIRE_VULKAN(stage);
  namespace fs = std::filesystem;
  const fs::path root = "../shared/datasets";
  if (!fs::exists(root)) GTEST_SKIP() << "no " << root << " (tests run from the repository root)";
  int count = 0;
  for (const auto& set : fs::directory_iterator(root)) {
    const fs::path images = set.path() / "images";
    if (!fs::is_directory(images)) continue;
    std::vector<fs::path> files;
    for (const auto& f : fs::directory_iterator(images))
      if (f.is_regular_file()) files.push_back(f.path());
    std::sort(files.begin(), files.end());
    for (const fs::path& f : files) {
      const cv::Mat gray = cv::imread(f.string(), cv::IMREAD_GRAYSCALE);
      if (gray.empty()) continue;
      ExpectSameBothBlurs(stage, ViewOf(gray), f.string());
      ++count;
    }
  }
  EXPECT_GT(count, 0) << "no readable image under " << root;
}

// Which hysteresis shader runs: relaxed atomics under the Vulkan memory model where the device has
// it, atomicOr otherwise; ELLIPSEKIT_VK_NO_MEMORY_MODEL=1 forces the fallback (ctest also runs this
// file's conformance tests that way: ConformanceVulkanEdgeFallback). Asserted in every run: the
// shared stage's variant follows the device (Vulkan 1.3 makes vulkanMemoryModel and
// vulkanMemoryModelDeviceScope mandatory, so a 1.3 device such as lavapipe must get the relaxed
// shader unless forced off), and a second stage created with the variable set gets the fallback and
// gives the scalar edge map bit for bit on frames whose hysteresis crosses many strips.
TEST(ConformanceVulkanEdge, HysteresisVariant) {
  REQUIRE_VULKAN(stage);
  const char* off = std::getenv("ELLIPSEKIT_VK_NO_MEMORY_MODEL");
  const bool forced_off = off != nullptr && std::string(off) == "1";
  const std::uint32_t api = stage->context()->properties().apiVersion;
  std::printf("[vulkan] %s (Vulkan %u.%u): hysteresis with %s\n", stage->device_name().c_str(), VK_API_VERSION_MAJOR(api),
              VK_API_VERSION_MINOR(api),
              stage->context()->memory_model() ? "relaxed atomics (Vulkan memory model)" : "atomicOr");
  if (forced_off) {
    EXPECT_FALSE(stage->context()->memory_model());
  } else if (api >= VK_API_VERSION_1_3) {
    EXPECT_TRUE(stage->context()->memory_model()) << "a Vulkan 1.3 device has the memory model";
  }
  // The other variant in this process: a fresh context reads the variable when it is created.
  const std::string saved = off != nullptr ? off : "";
  ::setenv("ELLIPSEKIT_VK_NO_MEMORY_MODEL", "1", 1);
  std::unique_ptr<VulkanEdgeStage> fallback;
  const Status st = VulkanEdgeStage::Create(&fallback);
  if (off != nullptr) ::setenv("ELLIPSEKIT_VK_NO_MEMORY_MODEL", saved.c_str(), 1);
  else ::unsetenv("ELLIPSEKIT_VK_NO_MEMORY_MODEL");
  ASSERT_TRUE(st.ok()) << st.message();
  EXPECT_FALSE(fallback->context()->memory_model());
  for (const auto& size : {std::pair{640, 480}, std::pair{97, 301}}) {
    const auto img = Shapes(size.first, size.second, 17);
    const ImageView view{img.data(), size.first, size.second, size.first};
    ExpectSameBothBlurs(fallback.get(), view, "atomicOr variant " + std::to_string(size.first) + "x" +
                                                 std::to_string(size.second));
    ExpectSameBothBlurs(stage, view, "shared variant " + std::to_string(size.first) + "x" + std::to_string(size.second));
  }
}

TEST(ConformanceVulkanEdge, Timing) {
  REQUIRE_VULKAN(stage);
  const char* t = std::getenv("ELLIPSEKIT_VK_TIMING");
  if (t == nullptr || std::string(t) != "1") GTEST_SKIP() << "set ELLIPSEKIT_VK_TIMING=1 to print timings";
  using Clock = std::chrono::steady_clock;
  stage->set_timing(true);  // device_ms; the timestamps add to the wall time
  for (const auto& s : {std::pair{640, 480}, std::pair{1920, 1080}}) {
    const int w = s.first, h = s.second;
    auto img = Shapes(w, h, 42);
    const ImageView view{img.data(), w, h, w};
    Options o;
    Edges out;
    out.dx.resize(static_cast<std::size_t>(w) * h);
    out.dy.resize(out.dx.size());
    out.edge_map.resize(out.dx.size());
    double best_vk = 1e30, best_dev = 1e30, best_scalar = 1e30;
    ASSERT_TRUE(stage->Run(view, o, out.dx.data(), out.dy.data(), out.edge_map.data()).ok());  // warm-up
    for (int i = 0; i < 10; ++i) {
      const auto a = Clock::now();
      ASSERT_TRUE(stage->Run(view, o, out.dx.data(), out.dy.data(), out.edge_map.data()).ok());
      const auto b = Clock::now();
      best_vk = std::min(best_vk, std::chrono::duration<double, std::milli>(b - a).count());
      best_dev = std::min(best_dev, stage->last_device_ms());
    }
    for (int i = 0; i < 10; ++i) {
      const auto a = Clock::now();
      ScalarEdges(view, o, &out);
      const auto b = Clock::now();
      best_scalar = std::min(best_scalar, std::chrono::duration<double, std::milli>(b - a).count());
    }
    std::printf("%dx%d on %s: vulkan %.2f ms wall (device %.2f ms), scalar %.2f ms\n", w, h,
                stage->device_name().c_str(), best_vk, best_dev, best_scalar);
  }
  stage->set_timing(false);
}

}  // namespace
}  // namespace ellipsekit

#else  // !ELLIPSEKIT_HAVE_VULKAN

TEST(ConformanceVulkanEdge, NotBuilt) {
  GTEST_SKIP() << "ellipsekit was built without the Vulkan edge stage (ELLIPSEKIT_HAVE_VULKAN unset)";
}

#endif

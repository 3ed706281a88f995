// Scene generator: the public API (scene_generator.h) over the world of tools/scenes/world.h:
// options checks, datasets and sequence directories written to disk.
//
// World frame: metres, z up, the table is the plane z = 0, optional back wall x = wall_x.
// Camera: x_cam ~ K (R X + t), R's rows are the camera's right, down and forward axes in world
// coordinates, t = -R pos. The ray of image point (u, v) is pos + s D with
// D = forward + right (u - pcx) / f + down (v - pcy) / f (not normalised: s = 1 at depth 1).
#include "tools/scenes/scene_generator.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <string>
#include <system_error>
#include <utility>

#include <opencv2/imgcodecs.hpp>

#include "tools/scenes/rng.h"
#include "tools/scenes/world.h"

namespace ellipsekit::scenes {

using detail::World;

namespace {

std::string JoinPath(const std::filesystem::path& dir, const std::string& name) { return (dir / name).string(); }

}  // namespace

// ---------------------------------------------------------------- public API
ellipsekit::Status ValidateSceneOptions(const SceneOptions& o) {
  auto bad = [](const std::string& m) { return ellipsekit::Status(ellipsekit::StatusCode::kInvalidArgument, m); };
  if (o.width < 16 || o.width > 8192 || o.height < 16 || o.height > 8192)
    return bad("scene size must be 16..8192 px, got " + std::to_string(o.width) + "x" + std::to_string(o.height));
  if (!(o.min_tilt_deg > 0 && o.min_tilt_deg <= o.max_tilt_deg && o.max_tilt_deg <= 90))
    return bad("tilt range must satisfy 0 < min_tilt_deg <= max_tilt_deg <= 90");
  if (o.min_objects < 0 || o.max_objects < o.min_objects || o.max_objects > 100)
    return bad("object counts must satisfy 0 <= min_objects <= max_objects <= 100");
  if (o.clutter_shapes < 0 || o.clutter_shapes > 1000) return bad("clutter_shapes must be 0..1000");
  if (!(o.noise_sigma >= 0 && o.noise_sigma <= 1000)) return bad("noise_sigma must be finite and >= 0");
  if (!(o.blur_sigma >= 0 && o.blur_sigma <= 50)) return bad("blur_sigma must be 0..50");
  return ellipsekit::Status::Ok();
}

Scene RenderScene(std::uint64_t seed, const SceneOptions& options) {
  if (!ValidateSceneOptions(options).ok()) return Scene();
  World world(options, seed);
  return world.Build();
}

std::uint64_t MixSeed(std::uint64_t seed, std::uint64_t index) {
  const std::uint64_t a = Mix64(seed + 0x9E3779B97F4A7C15ull);
  return Mix64(a ^ Mix64(index * 0xD1B54A32D192ED03ull + 0x8CB92BA72F3D8DD7ull));
}

std::string FormatTruthLine(const ellipsekit::Ellipse& e) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%.4f %.4f %.4f %.4f %.6f", e.cx, e.cy, e.a, e.b, e.theta);
  return buf;
}

ellipsekit::Status WriteSceneDataset(const std::string& dir, int count, std::uint64_t seed,
                                     const SceneOptions& options) {
  if (ellipsekit::Status st = ValidateSceneOptions(options); !st.ok()) return st;
  return WriteDataset(dir, count, seed, [&options](std::uint64_t s) { return RenderScene(s, options); });
}

ellipsekit::Status WriteDataset(const std::string& dir, int count, std::uint64_t seed,
                                const std::function<Scene(std::uint64_t)>& render) {
  using ellipsekit::Status;
  using ellipsekit::StatusCode;
  if (dir.empty()) return Status(StatusCode::kInvalidArgument, "dataset directory is empty");
  if (count < 0) return Status(StatusCode::kInvalidArgument, "scene count must be >= 0, got " + std::to_string(count));
  if (count > 10000) return Status(StatusCode::kInvalidArgument, "scene count must be <= 10000 (4-digit names)");
  const std::filesystem::path root(dir);
  const std::filesystem::path images = root / "images", gt = root / "gt";
  for (const auto& d : {images, gt}) {
    std::error_code ec;
    std::filesystem::create_directories(d, ec);
    if (ec || !std::filesystem::is_directory(d, ec))
      return Status(StatusCode::kInternal, "cannot create directory " + d.string() + ": " + ec.message());
  }
  for (int i = 0; i < count; ++i) {
    const Scene scene = render(MixSeed(seed, static_cast<std::uint64_t>(i)));
    char stem[32];
    std::snprintf(stem, sizeof stem, "scene_%04d", i);
    // Image: imwrite picks the format from the extension, so the temporary name ends in .png too.
    const std::string png = JoinPath(images, std::string(stem) + ".png");
    const std::string png_tmp = JoinPath(images, std::string(".") + stem + ".tmp.png");
    bool written = false;
    try {
      written = cv::imwrite(png_tmp, scene.gray);
    } catch (const cv::Exception& e) {
      written = false;
    }
    std::error_code ec;
    if (!written) {
      std::filesystem::remove(png_tmp, ec);
      return Status(StatusCode::kInternal, "cannot write image " + png_tmp);
    }
    std::filesystem::rename(png_tmp, png, ec);
    if (ec) return Status(StatusCode::kInternal, "cannot rename " + png_tmp + " to " + png + ": " + ec.message());
    // Ground truth.
    const std::string txt = JoinPath(gt, std::string(stem) + ".txt");
    const std::string txt_tmp = JoinPath(gt, std::string(".") + stem + ".tmp.txt");
    std::FILE* f = std::fopen(txt_tmp.c_str(), "wb");
    if (f == nullptr) return Status(StatusCode::kInternal, "cannot open " + txt_tmp + " for writing");
    bool ok = true;
    for (const ellipsekit::Ellipse& e : scene.truth) {
      const std::string line = FormatTruthLine(e) + "\n";
      ok &= std::fwrite(line.data(), 1, line.size(), f) == line.size();
    }
    ok &= std::fclose(f) == 0;
    if (!ok) {
      std::filesystem::remove(txt_tmp, ec);
      return Status(StatusCode::kInternal, "cannot write ground truth " + txt_tmp);
    }
    std::filesystem::rename(txt_tmp, txt, ec);
    if (ec) return Status(StatusCode::kInternal, "cannot rename " + txt_tmp + " to " + txt + ": " + ec.message());
  }
  return Status::Ok();
}

// ---------------------------------------------------------------- conveyor sequences
double ConveyorSequence::PositionAt(double t) const {
  if (!(length_m > 0) || !(speed_m_s > 0)) return 0;
  const double p = std::fmod(std::max(0.0, speed_m_s * t), 2 * length_m);
  return p <= length_m ? p : 2 * length_m - p;
}

cv::Vec3d ConveyorSequence::TopCentreAt(double t) const {
  const double s = PositionAt(t);
  const cv::Vec3d d = end_point - start_point;
  const double n = std::sqrt(d.dot(d));
  return n > 0 ? start_point + d * (s / n) : start_point;
}

ellipsekit::Status ValidateConveyorOptions(const ConveyorSceneOptions& o) {
  auto bad = [](const std::string& m) { return ellipsekit::Status(ellipsekit::StatusCode::kInvalidArgument, m); };
  if (o.width < 64 || o.width > 8192 || o.height < 64 || o.height > 8192)
    return bad("conveyor image size must be 64..8192 px, got " + std::to_string(o.width) + "x" +
               std::to_string(o.height));
  if (!(o.speed_m_s > 0 && o.speed_m_s <= 10)) return bad("conveyor speed must be in (0, 10] m/s");
  if (!(o.fps > 0 && o.fps <= 10000)) return bad("conveyor fps must be in (0, 10000]");
  if (o.frames < 1 || o.frames > 1000000) return bad("conveyor frames must be 1..999999");
  if (!(o.guide_length_m > 0.01 && o.guide_length_m <= 10)) return bad("guide_length_m must be in (0.01, 10]");
  if (o.clutter_shapes < 0 || o.clutter_shapes > 1000) return bad("clutter_shapes must be 0..1000");
  if (!(o.noise_sigma >= 0 && o.noise_sigma <= 1000)) return bad("noise_sigma must be finite and >= 0");
  if (!(o.blur_sigma >= 0 && o.blur_sigma <= 50)) return bad("blur_sigma must be 0..50");
  if (!(o.depth_noise_mm >= 0 && o.depth_noise_mm <= 1000)) return bad("depth_noise_mm must be finite and >= 0");
  if (!(o.depth_invalid_fraction >= 0 && o.depth_invalid_fraction <= 1))
    return bad("depth_invalid_fraction must be in [0, 1]");
  if (!(o.exposure_s >= 0 && o.exposure_s <= 1 / o.fps)) return bad("exposure_s must be in [0, 1 / fps]");
  return ellipsekit::Status::Ok();
}

ellipsekit::Status RenderConveyorSequence(std::uint64_t seed, const ConveyorSceneOptions& options,
                                          ConveyorSequence* info,
                                          const std::function<ellipsekit::Status(const ConveyorFrame&)>& sink) {
  if (ellipsekit::Status st = ValidateConveyorOptions(options); !st.ok()) return st;
  SceneOptions so;
  so.width = options.width;
  so.height = options.height;
  so.min_tilt_deg = 45;
  so.max_tilt_deg = 65;
  so.min_objects = so.max_objects = 1;
  so.occlusion = false;
  so.clutter_shapes = options.clutter_shapes;
  so.noise_sigma = options.noise_sigma;
  so.blur_sigma = options.blur_sigma;
  World world(so, seed);
  return world.BuildConveyor(options, seed, info, sink);
}

const char* ContainerName(Container c) {
  switch (c) {
    case Container::kFlatCan: return "flat-can";
    case Container::kRecessedCan: return "recessed-can";
    case Container::kCupEmpty: return "cup";
    case Container::kCupFilled: return "filled-cup";
    case Container::kJar: return "jar";
    case Container::kBottle: return "bottle";
  }
  return "?";
}

bool ParseContainer(const std::string& name, Container* out) {
  for (Container c : {Container::kFlatCan, Container::kRecessedCan, Container::kCupEmpty, Container::kCupFilled,
                      Container::kJar, Container::kBottle}) {
    if (name == ContainerName(c)) {
      *out = c;
      return true;
    }
  }
  return false;
}

// ---------------------------------------------------------------- stacking and crossing sequences
cv::Vec3d CanSequence::TopCentreAt(int can, double t) const {
  if (can < 0 || can >= static_cast<int>(start_point.size())) return cv::Vec3d(0, 0, 0);
  const std::size_t k = static_cast<std::size_t>(can);
  return start_point[k] + velocity_m_s[k] * t;
}

ellipsekit::Status ValidateCanSceneOptions(const CanSceneOptions& o) {
  auto bad = [](const std::string& m) { return ellipsekit::Status(ellipsekit::StatusCode::kInvalidArgument, m); };
  if (o.width < 64 || o.width > 8192 || o.height < 64 || o.height > 8192)
    return bad("can scene image size must be 64..8192 px, got " + std::to_string(o.width) + "x" +
               std::to_string(o.height));
  if (!(o.fps > 0 && o.fps <= 10000)) return bad("can scene fps must be in (0, 10000]");
  if (o.frames < 1 || o.frames > 999999) return bad("can scene frames must be 1..999999");
  if (!(o.speed_m_s >= 0 && o.speed_m_s <= 10)) return bad("can scene speed_m_s must be in [0, 10]");
  if (!(o.lane_gap_m >= 0 && o.lane_gap_m <= 1)) return bad("lane_gap_m must be in [0, 1]");
  if (!(o.crossing_height_difference_m >= 0 && o.crossing_height_difference_m <= 0.5))
    return bad("crossing_height_difference_m must be in [0, 0.5]");
  if (!(o.min_radius_m >= 0.005 && o.min_radius_m <= o.max_radius_m && o.max_radius_m <= 0.5))
    return bad("radius range must satisfy 0.005 <= min_radius_m <= max_radius_m <= 0.5");
  if (!(o.min_height_m >= 0.02 && o.min_height_m <= o.max_height_m && o.max_height_m <= 1))
    return bad("height range must satisfy 0.02 <= min_height_m <= max_height_m <= 1");
  if (!(o.min_distance_m >= 0.1 && o.min_distance_m <= o.max_distance_m && o.max_distance_m <= 10))
    return bad("distance range must satisfy 0.1 <= min_distance_m <= max_distance_m <= 10");
  if (!(o.min_tilt_deg >= 10 && o.min_tilt_deg <= o.max_tilt_deg && o.max_tilt_deg <= 90))
    return bad("tilt range must satisfy 10 <= min_tilt_deg <= max_tilt_deg <= 90");
  if (o.clutter_shapes < 0 || o.clutter_shapes > 1000) return bad("clutter_shapes must be 0..1000");
  if (!(o.noise_sigma >= 0 && o.noise_sigma <= 1000)) return bad("noise_sigma must be finite and >= 0");
  if (!(o.blur_sigma >= 0 && o.blur_sigma <= 50)) return bad("blur_sigma must be 0..50");
  if (!(o.depth_noise_mm >= 0 && o.depth_noise_mm <= 1000)) return bad("depth_noise_mm must be finite and >= 0");
  if (!(o.depth_invalid_fraction >= 0 && o.depth_invalid_fraction <= 1))
    return bad("depth_invalid_fraction must be in [0, 1]");
  return ellipsekit::Status::Ok();
}

ellipsekit::Status RenderCanSequence(std::uint64_t seed, const CanSceneOptions& options, CanSequence* info,
                                     const std::function<ellipsekit::Status(const CanFrame&)>& sink) {
  if (ellipsekit::Status st = ValidateCanSceneOptions(options); !st.ok()) return st;
  SceneOptions so;
  so.width = options.width;
  so.height = options.height;
  so.min_tilt_deg = options.min_tilt_deg;
  so.max_tilt_deg = options.max_tilt_deg;
  so.min_objects = so.max_objects = 2;
  so.occlusion = false;
  so.clutter_shapes = options.clutter_shapes;
  so.noise_sigma = options.noise_sigma;
  so.blur_sigma = options.blur_sigma;
  World world(so, seed);
  return world.BuildCans(options, seed, info, sink);
}

namespace {

ellipsekit::Status WriteTextFile(const std::filesystem::path& path, const std::string& text) {
  using ellipsekit::Status;
  using ellipsekit::StatusCode;
  std::string tmp_name(".");  // (appends: GCC 12 warns falsely on "literal" + string)
  tmp_name += path.filename().string();
  tmp_name += ".tmp";
  const std::filesystem::path tmp = path.parent_path() / tmp_name;
  std::FILE* f = std::fopen(tmp.string().c_str(), "wb");
  if (f == nullptr) return Status(StatusCode::kInternal, "cannot open " + tmp.string() + " for writing");
  bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  ok &= std::fclose(f) == 0;
  std::error_code ec;
  if (!ok) {
    std::filesystem::remove(tmp, ec);
    return Status(StatusCode::kInternal, "cannot write " + tmp.string());
  }
  std::filesystem::rename(tmp, path, ec);
  if (ec) return Status(StatusCode::kInternal, "cannot rename " + tmp.string() + " to " + path.string() + ": " + ec.message());
  return Status::Ok();
}

ellipsekit::Status WritePng(const std::filesystem::path& path, const cv::Mat& m) {
  using ellipsekit::Status;
  using ellipsekit::StatusCode;
  std::string tmp_name(".");
  tmp_name += path.stem().string();
  tmp_name += ".tmp.png";
  const std::filesystem::path tmp = path.parent_path() / tmp_name;
  bool written = false;
  try {
    written = cv::imwrite(tmp.string(), m);
  } catch (const cv::Exception&) {
    written = false;
  }
  std::error_code ec;
  if (!written) {
    std::filesystem::remove(tmp, ec);
    return Status(StatusCode::kInternal, "cannot write image " + tmp.string());
  }
  std::filesystem::rename(tmp, path, ec);
  if (ec) return Status(StatusCode::kInternal, "cannot rename " + tmp.string() + " to " + path.string() + ": " + ec.message());
  return Status::Ok();
}

std::string Fmt(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

template <class It>
std::string JsonList(It begin, It end, const char* fmt) {
  std::string s = "[";
  for (It it = begin; it != end; ++it) s += (it == begin ? "" : ", ") + Fmt(fmt, *it);
  return s + "]";
}

}  // namespace

namespace {

// The folders of a sequence directory (frames/, depth/), created with their parents.
ellipsekit::Status CreateDirectories(std::initializer_list<std::filesystem::path> dirs) {
  for (const auto& d : dirs) {
    std::error_code ec;
    std::filesystem::create_directories(d, ec);
    if (ec || !std::filesystem::is_directory(d, ec))
      return ellipsekit::Status(ellipsekit::StatusCode::kInternal,
                                "cannot create directory " + d.string() + ": " + ec.message());
  }
  return ellipsekit::Status::Ok();
}

// frames/NNNNNN.png (8-bit gray) and depth/NNNNNN.png (uint16 mm) of frame `index`.
ellipsekit::Status WriteFrameImages(const std::filesystem::path& frames, const std::filesystem::path& depth,
                                    int index, const cv::Mat& gray, const cv::Mat& depth_mm) {
  char name[32];
  std::snprintf(name, sizeof name, "%06d.png", index);
  if (ellipsekit::Status s = WritePng(frames / name, gray); !s.ok()) return s;
  return WritePng(depth / name, depth_mm);
}

// camera.json of a sequence (README "Sequences"): rendered frames have no lens distortion.
std::string CameraJson(int width, int height, const cv::Matx33d& K, const cv::Matx44d& T_world_camera) {
  const double D[5] = {0, 0, 0, 0, 0};
  return "{\"width\": " + std::to_string(width) + ", \"height\": " + std::to_string(height) +
         ", \"K\": " + JsonList(K.val, K.val + 9, "%.17g") + ", \"D\": " + JsonList(D, D + 5, "%.17g") +
         ", \"T_world_camera\": " + JsonList(T_world_camera.val, T_world_camera.val + 16, "%.17g") + "}\n";
}

// The rim circle of a top in truth.jsonl; nothing for the original flat can (its files unchanged).
std::string RimJson(Container c, const RimCircle& rim) {
  if (c == Container::kFlatCan) return "";
  return ", \"container\": \"" + std::string(ContainerName(c)) + "\", \"rim\": {\"centre\": " +
         JsonList(rim.centre.val, rim.centre.val + 3, "%.6f") + ", \"normal\": " +
         JsonList(rim.normal.val, rim.normal.val + 3, "%.6f") + ", \"radius\": " + Fmt("%.6f", rim.radius) + "}";
}

}  // namespace

ellipsekit::Status WriteConveyorSequence(const std::string& dir, std::uint64_t seed,
                                         const ConveyorSceneOptions& options, ConveyorSequence* info) {
  using ellipsekit::Status;
  using ellipsekit::StatusCode;
  if (dir.empty()) return Status(StatusCode::kInvalidArgument, "sequence directory is empty");
  if (Status st = ValidateConveyorOptions(options); !st.ok()) return st;
  if (options.frames > 999999) return Status(StatusCode::kInvalidArgument, "at most 999999 frames (6-digit names)");
  const std::filesystem::path root(dir), frames = root / "frames", depth = root / "depth";
  if (Status st = CreateDirectories({frames, depth}); !st.ok()) return st;
  std::string times, truth;
  ConveyorSequence seq;
  Status st = RenderConveyorSequence(seed, options, &seq, [&](const ConveyorFrame& fr) {
    if (Status s = WriteFrameImages(frames, depth, fr.index, fr.gray, fr.depth_mm); !s.ok()) return s;
    times += Fmt("%.9g", fr.t) + "\n";
    const double el[5] = {fr.truth.cx, fr.truth.cy, fr.truth.a, fr.truth.b, fr.truth.theta};
    truth += "{\"t\": " + Fmt("%.9g", fr.t) + ", \"tops\": [{\"centre\": " +
             JsonList(fr.top_centre.val, fr.top_centre.val + 3, "%.6f") +
             ", \"pixel\": " + JsonList(fr.top_pixel.val, fr.top_pixel.val + 2, "%.4f") +
             ", \"ellipse\": " + JsonList(el, el + 5, "%.6f") + RimJson(options.container, fr.rim) + "}]}\n";
    return Status::Ok();
  });
  if (!st.ok()) return st;
  const std::string camera = CameraJson(seq.width, seq.height, seq.K, seq.T_world_camera);
  const std::string conveyor =
      "{\"references\": [{\"point\": " + JsonList(seq.start_point.val, seq.start_point.val + 3, "%.17g") +
      ", \"pixel\": " + JsonList(seq.start_pixel.val, seq.start_pixel.val + 2, "%.17g") + "}, {\"point\": " +
      JsonList(seq.end_point.val, seq.end_point.val + 3, "%.17g") +
      ", \"pixel\": " + JsonList(seq.end_pixel.val, seq.end_pixel.val + 2, "%.17g") + "}]}\n";
  for (const auto& [name, text] : {std::pair<const char*, const std::string*>{"timestamps.txt", &times},
                                   {"camera.json", &camera}, {"conveyor.json", &conveyor}, {"truth.jsonl", &truth}}) {
    if (Status s = WriteTextFile(root / name, *text); !s.ok()) return s;
  }
  if (info != nullptr) *info = seq;
  return Status::Ok();
}

ellipsekit::Status WriteCanSequence(const std::string& dir, std::uint64_t seed, const CanSceneOptions& options,
                                    CanSequence* info) {
  using ellipsekit::Status;
  using ellipsekit::StatusCode;
  if (dir.empty()) return Status(StatusCode::kInvalidArgument, "sequence directory is empty");
  if (Status st = ValidateCanSceneOptions(options); !st.ok()) return st;
  const std::filesystem::path root(dir), frames = root / "frames", depth = root / "depth";
  if (Status st = CreateDirectories({frames, depth}); !st.ok()) return st;
  std::string times, truth;
  CanSequence seq;
  Status st = RenderCanSequence(seed, options, &seq, [&](const CanFrame& fr) {
    if (Status s = WriteFrameImages(frames, depth, fr.index, fr.gray, fr.depth_mm); !s.ok()) return s;
    times += Fmt("%.9g", fr.t) + "\n";
    truth += "{\"t\": " + Fmt("%.9g", fr.t) + ", \"tops\": [";
    for (std::size_t k = 0; k < fr.truth.size(); ++k) {
      const ellipsekit::Ellipse& e = fr.truth[k];
      const double el[5] = {e.cx, e.cy, e.a, e.b, e.theta};
      if (k > 0) truth += ", ";
      truth += "{\"centre\": " + JsonList(fr.top_centre[k].val, fr.top_centre[k].val + 3, "%.6f") +
               ", \"pixel\": " + JsonList(fr.top_pixel[k].val, fr.top_pixel[k].val + 2, "%.4f") +
               ", \"ellipse\": " + JsonList(el, el + 5, "%.6f") + ", \"rim_visible\": " +
               Fmt("%.4f", fr.rim_visible[k]) + RimJson(options.containers[k], fr.rim[k]) + "}";
    }
    truth += "]}\n";
    return Status::Ok();
  });
  if (!st.ok()) return st;
  const std::string camera = CameraJson(seq.width, seq.height, seq.K, seq.T_world_camera);
  for (const auto& [name, text] : {std::pair<const char*, const std::string*>{"timestamps.txt", &times},
                                   {"camera.json", &camera}, {"truth.jsonl", &truth}}) {
    if (Status s = WriteTextFile(root / name, *text); !s.ok()) return s;
  }
  if (info != nullptr) *info = seq;
  return Status::Ok();
}

}  // namespace ellipsekit::scenes

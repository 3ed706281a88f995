// ellipsekit track: detect, track and locate cylinder tops in a recorded sequence; on a conveyor,
// estimate the speed along the guide and plan grasps (robot module: EllipseTracker,
// depth sampling / circle pose, ConveyorTracker, PlanConveyorGrasp).
//
// Sequence directory:
//   frames/NNNNNN.png   images (6 digits from 000000), read as 8-bit gray
//   depth/NNNNNN.png    optional uint16 millimetres along the camera z axis, 0 = invalid
//   timestamps.txt      one time in seconds per frame
//   camera.json         {"width": W, "height": H, "K": [9, row-major], "D": [k1, k2, p1, p2, k3],
//                        "T_world_camera": [16, row-major 4x4, world = T * camera]}
//   conveyor.json       (--conveyor) {"references": [{"point": [x, y, z], "pixel": [u, v]}, {...}]}
//
// Output: one JSON object per frame (see kTrackUsage), world frame, metres; written to a temporary
// file beside FILE, then renamed.
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Dense>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "ellipsekit/detector.h"
#include "ellipsekit/robot/camera_model.h"
#include "ellipsekit/robot/circle_pose.h"
#include "ellipsekit/robot/conveyor.h"
#include "ellipsekit/robot/depth_sampling.h"
#include "ellipsekit/robot/grasp.h"
#include "ellipsekit/robot/kalman.h"
#include "ellipsekit/robot/frame_loop.h"
#include "ellipsekit/robot/tracker.h"
#include "tools/cli/args.h"
#include "tools/cli/commands.h"
#include "tools/cli/json.h"
#include "tools/cli/track_draw.h"
#ifdef ELLIPSEKIT_HAVE_VIDEOIO
#include <opencv2/videoio.hpp>
#endif

namespace ellipsekit::cli {

const char kTrackUsage[] =
    "Usage: ellipsekit track SEQ_DIR [--conveyor] [--radius R] [--latency S] [--centre rim|interior]\n"
    "                        [--draw DIR] [--video FILE] --out FILE.jsonl\n"
    "\n"
    "Detects and tracks cylinder tops in a sequence directory (frames/NNNNNN.png, optional\n"
    "depth/NNNNNN.png in uint16 mm, timestamps.txt, camera.json, conveyor.json with --conveyor)\n"
    "and writes one JSON object per frame, world frame, metres:\n"
    "  {\"t\": T, \"tracks\": [{\"id\": N, \"state\": \"tentative\"|\"confirmed\"|\"lost\",\n"
    "    \"pixel\": [u, v], \"position\": [x, y, z], \"velocity\": [vx, vy, vz]}],\n"
    "   \"grasp\": null | {\"t\": T, \"target\": [x, y, z], \"position\": [x, y, z], \"pregrasp\": [x, y, z]}}\n"
    "A track's position is the centre of the top's rim circle (from depth on the rim by default;\n"
    "the median depth inside the ellipse with --centre interior, for flat discs; from the circle pose\n"
    "with --radius when the sequence has no depth). grasp.t = frame time + latency; target = top centre\n"
    "predicted then; "
    "position = 2 cm ahead along the motion; pregrasp = 10 cm back along the approach.\n"
    "The loop is the library's robot::FrameLoop (include/ellipsekit/robot/frame_loop.h).\n"
    "\n"
    "Options:\n"
    "  --conveyor        the object rides the guide of conveyor.json: speed and grasp planning\n"
    "  --radius R        top radius in metres (circle pose when there is no depth image)\n"
    "  --latency S       seconds from planning to the gripper at the pre-grasp pose (default 1.0)\n"
    "  --centre M        rim (default: the rim plane's circle) or interior (median depth inside)\n"
    "  --draw DIR        write each frame with its tracks drawn to DIR/NNNNNN.png (ellipse, id,\n"
    "                    state, trail, the predicted grasp target projected)\n"
    "  --video FILE      the same frames as one video (cv::VideoWriter; .avi: MJPG, .mp4: mp4v)\n"
    "  --out FILE        output JSON lines file (required)\n"
    "  -h, --help        this text\n";

namespace {

// ---------------------------------------------------------------- a small JSON reader
struct JsonValue {
  enum Kind { kNull, kBool, kNumber, kString, kArray, kObject } kind = kNull;
  double number = 0;
  bool boolean = false;
  std::string text;
  std::vector<JsonValue> items;
  std::vector<std::pair<std::string, JsonValue>> members;

  const JsonValue* Get(const std::string& key) const {
    for (const auto& m : members)
      if (m.first == key) return &m.second;
    return nullptr;
  }
};

class JsonParser {
 public:
  explicit JsonParser(const std::string& s) : s_(s) {}
  JsonValue ParseDocument() {
    JsonValue v = ParseValue(0);
    SkipSpace();
    if (i_ != s_.size()) Fail("trailing characters");
    return v;
  }

 private:
  [[noreturn]] void Fail(const std::string& what) const {
    throw std::runtime_error("bad JSON at offset " + std::to_string(i_) + ": " + what);
  }
  void SkipSpace() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  bool Eat(char c) {
    SkipSpace();
    if (i_ < s_.size() && s_[i_] == c) {
      ++i_;
      return true;
    }
    return false;
  }
  void Expect(char c) {
    if (!Eat(c)) Fail(std::string("expected '") + c + "'");
  }
  std::string ParseString() {
    Expect('"');
    std::string out;
    while (true) {
      if (i_ >= s_.size()) Fail("unterminated string");
      const char c = s_[i_++];
      if (c == '"') break;
      if (c == '\\') {
        if (i_ >= s_.size()) Fail("unterminated escape");
        const char e = s_[i_++];
        switch (e) {
          case 'n': out += '\n'; break;
          case 't': out += '\t'; break;
          case 'r': out += '\r'; break;
          case 'b': out += '\b'; break;
          case 'f': out += '\f'; break;
          case 'u':
            if (i_ + 4 > s_.size()) Fail("bad \\u escape");
            i_ += 4;
            out += '?';
            break;
          default: out += e;
        }
      } else {
        out += c;
      }
    }
    return out;
  }
  JsonValue ParseValue(int depth) {
    if (depth > 64) Fail("nested too deeply");
    SkipSpace();
    if (i_ >= s_.size()) Fail("unexpected end");
    JsonValue v;
    const char c = s_[i_];
    if (c == '{') {
      ++i_;
      v.kind = JsonValue::kObject;
      if (Eat('}')) return v;
      do {
        SkipSpace();
        std::string key = ParseString();
        Expect(':');
        v.members.emplace_back(std::move(key), ParseValue(depth + 1));
      } while (Eat(','));
      Expect('}');
    } else if (c == '[') {
      ++i_;
      v.kind = JsonValue::kArray;
      if (Eat(']')) return v;
      do {
        v.items.push_back(ParseValue(depth + 1));
      } while (Eat(','));
      Expect(']');
    } else if (c == '"') {
      v.kind = JsonValue::kString;
      v.text = ParseString();
    } else if (s_.compare(i_, 4, "true") == 0) {
      i_ += 4;
      v.kind = JsonValue::kBool;
      v.boolean = true;
    } else if (s_.compare(i_, 5, "false") == 0) {
      i_ += 5;
      v.kind = JsonValue::kBool;
    } else if (s_.compare(i_, 4, "null") == 0) {
      i_ += 4;
    } else {
      const char* begin = s_.c_str() + i_;
      char* end = nullptr;
      v.number = std::strtod(begin, &end);
      if (end == begin) Fail("unexpected character");
      i_ += static_cast<std::size_t>(end - begin);
      v.kind = JsonValue::kNumber;
    }
    return v;
  }

  const std::string& s_;
  std::size_t i_ = 0;
};

// A problem with the sequence: reported as "PATH: message", exit status 1.
class SequenceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

namespace fs = std::filesystem;

std::string ReadTextFile(const fs::path& p) {
  std::error_code ec;
  if (!fs::exists(p, ec)) throw SequenceError(p.string() + ": missing");
  std::ifstream in(p, std::ios::binary);
  if (!in) throw SequenceError(p.string() + ": cannot open");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

JsonValue ReadJsonFile(const fs::path& p) {
  const std::string text = ReadTextFile(p);
  try {
    JsonParser parser(text);
    return parser.ParseDocument();
  } catch (const std::runtime_error& e) {
    throw SequenceError(p.string() + ": " + e.what());
  }
}

std::vector<double> Numbers(const JsonValue& obj, const std::string& key, std::size_t min_n, std::size_t max_n,
                            const fs::path& file) {
  const JsonValue* v = obj.Get(key);
  if (v == nullptr) throw SequenceError(file.string() + ": missing \"" + key + "\"");
  std::vector<double> out;
  if (v->kind == JsonValue::kNumber) {
    out.push_back(v->number);
  } else if (v->kind == JsonValue::kArray) {
    for (const JsonValue& x : v->items) {
      if (x.kind != JsonValue::kNumber || !std::isfinite(x.number))
        throw SequenceError(file.string() + ": \"" + key + "\" must hold finite numbers");
      out.push_back(x.number);
    }
  }
  if (out.size() < min_n || out.size() > max_n) {
    throw SequenceError(file.string() + ": \"" + key + "\" must have " +
                        (min_n == max_n ? std::to_string(min_n) : std::to_string(min_n) + ".." + std::to_string(max_n)) +
                        " numbers, got " + std::to_string(out.size()));
  }
  return out;
}

struct Sequence {
  fs::path dir;
  int width = 0, height = 0;
  robot::CameraModel camera;
  Eigen::Matrix4d T_world_camera = Eigen::Matrix4d::Identity();
  std::vector<double> times;
  int frames = 0;
  bool has_depth = false;
  bool has_conveyor = false;
  robot::ConveyorReference ref[2];
};

std::string FrameName(int i) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%06d.png", i);
  return buf;
}

Sequence LoadSequence(const fs::path& dir, bool conveyor) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw SequenceError(dir.string() + ": not a directory");
  Sequence seq;
  seq.dir = dir;
  // camera.json
  const fs::path cam_path = dir / "camera.json";
  const JsonValue cam = ReadJsonFile(cam_path);
  if (cam.kind != JsonValue::kObject) throw SequenceError(cam_path.string() + ": not a JSON object");
  const double w = Numbers(cam, "width", 1, 1, cam_path)[0], h = Numbers(cam, "height", 1, 1, cam_path)[0];
  if (!(w >= 1 && h >= 1 && w <= 100000 && h <= 100000 && w == std::floor(w) && h == std::floor(h)))
    throw SequenceError(cam_path.string() + ": \"width\" and \"height\" must be positive integers");
  seq.width = static_cast<int>(w);
  seq.height = static_cast<int>(h);
  const std::vector<double> K = Numbers(cam, "K", 9, 9, cam_path);
  std::vector<double> D;
  if (cam.Get("D") != nullptr) D = Numbers(cam, "D", 0, 8, cam_path);
  if (!(K[0] > 0 && K[4] > 0)) throw SequenceError(cam_path.string() + ": \"K\" needs positive focal lengths");
  seq.camera = robot::CameraModel::FromIntrinsics(K[0], K[4], K[2], K[5], D, seq.width, seq.height);
  const std::vector<double> T = Numbers(cam, "T_world_camera", 16, 16, cam_path);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) seq.T_world_camera(r, c) = T[static_cast<std::size_t>(4 * r + c)];
  const Eigen::Matrix3d R = seq.T_world_camera.topLeftCorner<3, 3>();
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-3)
    throw SequenceError(cam_path.string() + ": \"T_world_camera\" rotation is not orthonormal");

  // frames and timestamps
  while (fs::exists(dir / "frames" / FrameName(seq.frames), ec)) ++seq.frames;
  if (seq.frames == 0) throw SequenceError((dir / "frames" / FrameName(0)).string() + ": missing (no frames)");
  const fs::path ts_path = dir / "timestamps.txt";
  {
    std::istringstream in(ReadTextFile(ts_path));
    std::string line;
    int lineno = 0;
    while (std::getline(in, line)) {
      ++lineno;
      const std::size_t b = line.find_first_not_of(" \t\r");
      if (b == std::string::npos) continue;
      char* end = nullptr;
      const double t = std::strtod(line.c_str() + b, &end);
      while (end && *end && std::isspace(static_cast<unsigned char>(*end))) ++end;
      if (end == line.c_str() + b || (end && *end) || !std::isfinite(t))
        throw SequenceError(ts_path.string() + ":" + std::to_string(lineno) + ": not a time in seconds");
      if (!seq.times.empty() && !(t > seq.times.back()))
        throw SequenceError(ts_path.string() + ":" + std::to_string(lineno) + ": times must increase");
      seq.times.push_back(t);
    }
  }
  if (static_cast<int>(seq.times.size()) != seq.frames) {
    throw SequenceError(ts_path.string() + ": " + std::to_string(seq.times.size()) + " times for " +
                        std::to_string(seq.frames) + " frames (frames/000000.png ...)");
  }
  seq.has_depth = fs::exists(dir / "depth" / FrameName(0), ec);
  if (seq.has_depth) {
    for (int i = 0; i < seq.frames; ++i) {
      if (!fs::exists(dir / "depth" / FrameName(i), ec))
        throw SequenceError((dir / "depth" / FrameName(i)).string() + ": missing (depth/ must match frames/)");
    }
  }

  if (conveyor) {
    const fs::path cv_path = dir / "conveyor.json";
    const JsonValue c = ReadJsonFile(cv_path);
    const JsonValue* refs = c.kind == JsonValue::kObject ? c.Get("references") : nullptr;
    if (refs == nullptr || refs->kind != JsonValue::kArray || refs->items.size() != 2)
      throw SequenceError(cv_path.string() + ": \"references\" must be an array of 2 objects");
    const Eigen::Matrix4d T_cw = seq.T_world_camera.inverse();
    for (int k = 0; k < 2; ++k) {
      const JsonValue& r = refs->items[static_cast<std::size_t>(k)];
      if (r.kind != JsonValue::kObject) throw SequenceError(cv_path.string() + ": a reference is not an object");
      const std::vector<double> p = Numbers(r, "point", 3, 3, cv_path), px = Numbers(r, "pixel", 2, 2, cv_path);
      seq.ref[k].point = Eigen::Vector3d(p[0], p[1], p[2]);
      seq.ref[k].pixel = Eigen::Vector2d(px[0], px[1]);
      const Eigen::Vector4d pc = T_cw * Eigen::Vector4d(p[0], p[1], p[2], 1);
      seq.ref[k].camera_depth_z = pc.z() > 0 ? pc.z() : 0;  // exact perspective mapping when in front
    }
    seq.has_conveyor = true;
  }
  return seq;
}

std::string Vec(const Eigen::Vector3d& v, int digits = 5) {
  std::string s(1, '[');  // (appends: GCC 12 warns falsely on "literal" + string)
  s += JsonNumber(v.x(), digits);
  s += ", ";
  s += JsonNumber(v.y(), digits);
  s += ", ";
  s += JsonNumber(v.z(), digits);
  s += ']';
  return s;
}

}  // namespace

int RunTrack(const std::vector<std::string>& argv) {
  std::string dir, out, draw_dir, video_path;
  bool conveyor = false;
  robot::TopCentreMethod method = robot::TopCentreMethod::kRimPlane;
  double radius = 0, latency = 1.0;
  ArgReader r(argv);
  auto parse_double = [](const std::string& flag, const std::string& text, double lo, double hi) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v) || v < lo || v > hi)
      throw UsageError(flag + ": bad value '" + text + "'");
    return v;
  };
  while (r.Next()) {
    if (!r.IsFlag()) {
      if (!dir.empty()) throw UsageError("unexpected argument '" + r.positional() + "'");
      dir = r.positional();
      continue;
    }
    const std::string& name = r.name();
    if (name == "--help" || name == "-h") {
      std::fputs(kTrackUsage, stdout);
      return kExitOk;
    } else if (name == "--conveyor") {
      r.NoValue();
      conveyor = true;
    } else if (name == "--radius") {
      radius = parse_double(name, r.Value(), 1e-4, 10);
    } else if (name == "--latency") {
      latency = parse_double(name, r.Value(), 0, 60);
    } else if (name == "--out") {
      out = r.Value();
    } else if (name == "--draw") {
      draw_dir = r.Value();
    } else if (name == "--video") {
      video_path = r.Value();
    } else if (name == "--centre") {
      const std::string m = r.Value();
      if (m == "rim") {
        method = robot::TopCentreMethod::kRimPlane;
      } else if (m == "interior") {
        method = robot::TopCentreMethod::kInteriorMedian;
      } else {
        throw UsageError("--centre: bad value '" + m + "' (rim or interior)");
      }
    } else {
      throw UsageError("unknown option '" + name + "'");
    }
  }
  if (dir.empty()) throw UsageError("no sequence directory given");
  if (out.empty()) throw UsageError("--out FILE is required");

  Sequence seq;
  try {
    seq = LoadSequence(dir, conveyor);
  } catch (const SequenceError& e) {
    std::fprintf(stderr, "ellipsekit track: %s\n", e.what());
    return kExitFailure;
  }
  if (!seq.has_depth && radius <= 0) {
    std::fprintf(stderr, "ellipsekit track: %s: no depth images; give --radius R for the circle pose\n",
                 (seq.dir / "depth").string().c_str());
    return kExitFailure;
  }

  robot::FrameLoopOptions lopt;
  lopt.T_world_camera = seq.T_world_camera;
  lopt.top_centre = method;
  lopt.top_radius_m = radius;
  lopt.grasp.latency_s = latency;
  if (seq.has_conveyor) lopt.conveyor = std::array<robot::ConveyorReference, 2>{seq.ref[0], seq.ref[1]};
  robot::FrameLoop loop(seq.camera, lopt);
  if (!loop.status().ok()) {
    std::fprintf(stderr, "ellipsekit track: %s\n", loop.status().message().c_str());
    return kExitFailure;
  }
  if (!draw_dir.empty()) {
    std::error_code ec;
    fs::create_directories(draw_dir, ec);
    if (!fs::is_directory(draw_dir, ec)) {
      std::fprintf(stderr, "ellipsekit track: %s: cannot create directory\n", draw_dir.c_str());
      return kExitFailure;
    }
  }
#ifdef ELLIPSEKIT_HAVE_VIDEOIO
  cv::VideoWriter video;
  if (!video_path.empty()) {
    const std::string ext = fs::path(video_path).extension().string();
    const int fourcc = ext == ".mp4" ? cv::VideoWriter::fourcc('m', 'p', '4', 'v') : cv::VideoWriter::fourcc('M', 'J', 'P', 'G');
    const double span = seq.frames > 1 ? seq.times.back() - seq.times.front() : 0;
    const double fps = span > 0 ? (seq.frames - 1) / span : 30;
    if (!video.open(video_path, fourcc, fps, cv::Size(seq.width, seq.height), true)) {
      std::fprintf(stderr, "ellipsekit track: %s: cannot open a video writer (codec %s)\n", video_path.c_str(),
                   ext == ".mp4" ? "mp4v" : "MJPG");
      return kExitFailure;
    }
  }
#else
  if (!video_path.empty()) {
    std::fprintf(stderr, "ellipsekit track: --video: this build has no OpenCV videoio\n");
    return kExitFailure;
  }
#endif
  TrackDrawer drawer;
  const bool drawing = !draw_dir.empty() || !video_path.empty();

  const fs::path out_path(out);
  std::string tmp_name(".");
  tmp_name += out_path.filename().string();
  tmp_name += ".tmp";
  const fs::path tmp_path = out_path.parent_path() / tmp_name;
  std::FILE* f = std::fopen(tmp_path.string().c_str(), "wb");
  if (f == nullptr) {
    std::fprintf(stderr, "ellipsekit track: %s: cannot open for writing\n", tmp_path.string().c_str());
    return kExitFailure;
  }
  auto fail = [&](const std::string& msg) {
    std::fclose(f);
    std::error_code ec;
    fs::remove(tmp_path, ec);
    std::fprintf(stderr, "ellipsekit track: %s\n", msg.c_str());
    return kExitFailure;
  };

  robot::FrameOutput frame;
  cv::Mat drawn;
  bool write_ok = true;
  for (int i = 0; i < seq.frames; ++i) {
    const double now = seq.times[static_cast<std::size_t>(i)];
    const fs::path img_path = seq.dir / "frames" / FrameName(i);
    cv::Mat gray = cv::imread(img_path.string(), cv::IMREAD_GRAYSCALE);
    if (gray.empty()) return fail(img_path.string() + ": not a readable image");
    if (gray.cols != seq.width || gray.rows != seq.height)
      return fail(img_path.string() + ": size " + std::to_string(gray.cols) + "x" + std::to_string(gray.rows) +
                  " differs from camera.json");
    cv::Mat depth;
    if (seq.has_depth) {
      const fs::path dp = seq.dir / "depth" / FrameName(i);
      depth = cv::imread(dp.string(), cv::IMREAD_ANYDEPTH);
      if (depth.empty() || depth.type() != CV_16UC1) return fail(dp.string() + ": not a 16-bit depth image");
      if (depth.cols != seq.width || depth.rows != seq.height) return fail(dp.string() + ": size differs from camera.json");
    }
    if (!gray.isContinuous()) gray = gray.clone();
    ImageView view;
    view.data = gray.ptr<std::uint8_t>(0);
    view.width = gray.cols;
    view.height = gray.rows;
    view.stride = static_cast<std::ptrdiff_t>(gray.step[0]);
    robot::DepthImageView dv;
    if (seq.has_depth) {
      dv.data = depth.data;
      dv.width = depth.cols;
      dv.height = depth.rows;
      dv.step = depth.step[0];
      dv.encoding = robot::DepthEncoding::k16UC1;
    }
    if (Status st = loop.ProcessFrame(view, seq.has_depth ? &dv : nullptr, now, &frame); !st.ok())
      return fail(img_path.string() + ": " + st.message());

    // One output line.
    std::string line = "{\"t\": " + JsonNumber(now, 6) + ", \"tracks\": [";
    bool first = true;
    for (const robot::TrackOutput& t : frame.tracks) {
      if (!t.has_position) continue;
      if (!first) line += ", ";
      first = false;
      line += "{\"id\": " + std::to_string(t.id) + ", \"state\": \"" + robot::TrackStateName(t.state) +
              "\", \"pixel\": [" + JsonNumber(t.ellipse.cx, 2) + ", " + JsonNumber(t.ellipse.cy, 2) +
              "], \"position\": " + Vec(t.position) + ", \"velocity\": " + Vec(t.velocity) + "}";
    }
    line += "], \"grasp\": ";
    bool grasp = false;
    if (frame.grasp.valid) {
      const auto& g = frame.grasp.plan.grasp.pose.position;
      const auto& p = frame.grasp.plan.pregrasp.pose.position;
      line += "{\"t\": " + JsonNumber(frame.grasp.target_time_s, 6) + ", \"target\": " + Vec(frame.grasp.target) +
              ", \"position\": " + Vec(Eigen::Vector3d(g.x, g.y, g.z)) +
              ", \"pregrasp\": " + Vec(Eigen::Vector3d(p.x, p.y, p.z)) + "}";
      grasp = true;
    }
    if (drawing) {
      drawer.Draw(gray, loop, frame, &drawn);
      if (!draw_dir.empty()) {
        const fs::path dp = fs::path(draw_dir) / FrameName(i);
        bool ok = false;
        try {
          ok = cv::imwrite(dp.string(), drawn);
        } catch (const cv::Exception&) {
          ok = false;
        }
        if (!ok) return fail(dp.string() + ": cannot write image");
      }
#ifdef ELLIPSEKIT_HAVE_VIDEOIO
      if (video.isOpened()) video.write(drawn);
#endif
    }
    if (!grasp) line += "null";
    line += "}\n";
    write_ok &= std::fwrite(line.data(), 1, line.size(), f) == line.size();
  }
  write_ok &= std::fclose(f) == 0;
  std::error_code ec;
  if (!write_ok) {
    fs::remove(tmp_path, ec);
    std::fprintf(stderr, "ellipsekit track: %s: write failed\n", tmp_path.string().c_str());
    return kExitFailure;
  }
  fs::rename(tmp_path, out_path, ec);
  if (ec) {
    std::fprintf(stderr, "ellipsekit track: cannot rename %s to %s: %s\n", tmp_path.string().c_str(),
                 out_path.string().c_str(), ec.message().c_str());
    return kExitFailure;
  }
  std::printf("tracked %d frames of %s -> %s\n", seq.frames, dir.c_str(), out.c_str());
  return kExitOk;
}

}  // namespace ellipsekit::cli

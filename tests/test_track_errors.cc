// `ellipsekit track` on malformed sequences: exit status 1 and a message naming the file.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "tools/scenes/scene_generator.h"

namespace {

namespace sc = ellipsekit::scenes;
namespace fs = std::filesystem;

fs::path CliPath() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : self.parent_path() / "ellipsekit";
}

struct CliRun {
  int rc = -1;
  std::string output;  // stdout and stderr
};

CliRun RunCli(const std::string& args) {
  CliRun r;
  const std::string cmd = "'" + CliPath().string() + "' " + args + " 2>&1";
  std::FILE* p = ::popen(cmd.c_str(), "r");
  if (p == nullptr) return r;
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
  const int st = ::pclose(p);
  r.rc = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

void WriteFile(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out << text;
}

class TrackErrors : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    ASSERT_TRUE(fs::exists(CliPath())) << CliPath();
    base_ = fs::temp_directory_path() / ("ellipsekit_test_track_errors_" + std::to_string(::getpid()));
    fs::remove_all(base_);
    sc::ConveyorSceneOptions co;
    co.width = 320;
    co.height = 240;
    co.frames = 6;
    ASSERT_TRUE(sc::WriteConveyorSequence((base_ / "good").string(), 5, co).ok());
  }
  static void TearDownTestSuite() { fs::remove_all(base_); }

  // A fresh copy of the good sequence.
  fs::path Copy(const std::string& name) {
    const fs::path d = base_ / name;
    fs::remove_all(d);
    fs::copy(base_ / "good", d, fs::copy_options::recursive);
    return d;
  }
  std::string Out() const { return "'" + (base_ / "out.jsonl").string() + "'"; }

  static fs::path base_;
};
fs::path TrackErrors::base_;

TEST_F(TrackErrors, GoodSequenceWorks) {
  const CliRun r = RunCli("track '" + (base_ / "good").string() + "' --conveyor --out " + Out());
  EXPECT_EQ(r.rc, 0) << r.output;
  std::ifstream in(base_ / "out.jsonl");
  int lines = 0;
  for (std::string l; std::getline(in, l);) {
    EXPECT_EQ(l.rfind("{\"t\": ", 0), 0u) << l;
    EXPECT_NE(l.find("\"grasp\": "), std::string::npos);
    ++lines;
  }
  EXPECT_EQ(lines, 6);
  // No temporary file left beside the output.
  for (const auto& e : fs::directory_iterator(base_)) EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos);
}

TEST_F(TrackErrors, MissingCameraJson) {
  const fs::path d = Copy("nocam");
  fs::remove(d / "camera.json");
  const CliRun r = RunCli("track '" + d.string() + "' --out " + Out());
  EXPECT_EQ(r.rc, 1);
  EXPECT_NE(r.output.find("camera.json: missing"), std::string::npos) << r.output;
}

TEST_F(TrackErrors, BadJson) {
  const fs::path d = Copy("badjson");
  WriteFile(d / "camera.json", "{\"width\": 320, \"height\": 240, \"K\": [1, 2,");
  CliRun r = RunCli("track '" + d.string() + "' --out " + Out());
  EXPECT_EQ(r.rc, 1);
  EXPECT_NE(r.output.find("camera.json: bad JSON at offset"), std::string::npos) << r.output;
  WriteFile(d / "camera.json", "{\"width\": 320, \"height\": 240, \"K\": [1, 2, 3], \"T_world_camera\": []}");
  r = RunCli("track '" + d.string() + "' --out " + Out());
  EXPECT_EQ(r.rc, 1);
  EXPECT_NE(r.output.find("camera.json: \"K\" must have 9 numbers, got 3"), std::string::npos) << r.output;
  const fs::path d2 = Copy("badconveyor");
  WriteFile(d2 / "conveyor.json", "{\"references\": [{\"point\": [0, 0, 0], \"pixel\": [1, 2]}]}");
  r = RunCli("track '" + d2.string() + "' --conveyor --out " + Out());
  EXPECT_EQ(r.rc, 1);
  EXPECT_NE(r.output.find("conveyor.json: \"references\" must be an array of 2 objects"), std::string::npos)
      << r.output;
}

TEST_F(TrackErrors, FrameCountDiffersFromTimestamps) {
  const fs::path d = Copy("count");
  WriteFile(d / "timestamps.txt", "0\n0.033\n0.066\n");
  const CliRun r = RunCli("track '" + d.string() + "' --out " + Out());
  EXPECT_EQ(r.rc, 1);
  EXPECT_NE(r.output.find("timestamps.txt: 3 times for 6 frames"), std::string::npos) << r.output;
}

TEST_F(TrackErrors, MissingConveyorJsonAndDepth) {
  const fs::path d = Copy("noconv");
  fs::remove(d / "conveyor.json");
  CliRun r = RunCli("track '" + d.string() + "' --conveyor --out " + Out());
  EXPECT_EQ(r.rc, 1);
  EXPECT_NE(r.output.find("conveyor.json: missing"), std::string::npos) << r.output;
  fs::remove_all(d / "depth");
  r = RunCli("track '" + d.string() + "' --out " + Out());
  EXPECT_EQ(r.rc, 1);
  EXPECT_NE(r.output.find("no depth images; give --radius"), std::string::npos) << r.output;
  // With --radius the circle pose replaces depth.
  r = RunCli("track '" + d.string() + "' --radius 0.035 --out " + Out());
  EXPECT_EQ(r.rc, 0) << r.output;
}

TEST_F(TrackErrors, Usage) {
  CliRun r = RunCli("track --out " + Out());
  EXPECT_EQ(r.rc, 2);
  EXPECT_NE(r.output.find("no sequence directory given"), std::string::npos) << r.output;
  r = RunCli("track '" + (base_ / "good").string() + "'");
  EXPECT_EQ(r.rc, 2);
  EXPECT_NE(r.output.find("--out FILE is required"), std::string::npos) << r.output;
  r = RunCli("track '" + (base_ / "good").string() + "' --latency -1 --out " + Out());
  EXPECT_EQ(r.rc, 2);
  r = RunCli("track --help");
  EXPECT_EQ(r.rc, 0);
  EXPECT_NE(r.output.find("Usage: ellipsekit track"), std::string::npos);
  r = RunCli("scenes --speed 0.1 --out " + Out());
  EXPECT_EQ(r.rc, 2);
  EXPECT_NE(r.output.find("--speed needs --conveyor"), std::string::npos) << r.output;
  r = RunCli("scenes --conveyor --speed 0 --out " + Out());
  EXPECT_EQ(r.rc, 2);
}

}  // namespace

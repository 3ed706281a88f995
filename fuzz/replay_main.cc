// Replays fuzz inputs through the same entry as the libFuzzer target, without libFuzzer:
//   fuzz_detect_replay PATH...       DetectOneInput (fuzz_detect.cc)
//   fuzz_detect_cpu_replay PATH...   DetectCpuOneInput (fuzz_detect_cpu.cc)
// (a PATH that is a folder: every regular file in it, sorted). The entry is ELLIPSEKIT_FUZZ_ENTRY
// (fuzz_detect.h; default DetectOneInput), set per target in CMakeLists.txt.
// Exit status 0 when every input ran, 1 when none was found or a file could not be read; a broken
// invariant aborts.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <string>
#include <vector>

#include "fuzz/fuzz_detect.h"

#ifndef ELLIPSEKIT_FUZZ_ENTRY
#define ELLIPSEKIT_FUZZ_ENTRY DetectOneInput
#endif

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  const std::string name = argc > 0 ? fs::path(argv[0]).filename().string() : "replay";
  std::vector<fs::path> files;
  for (int i = 1; i < argc; ++i) {
    std::error_code ec;
    if (fs::is_directory(argv[i], ec)) {
      for (const fs::directory_entry& e : fs::directory_iterator(argv[i], ec))
        if (e.is_regular_file()) files.push_back(e.path());
    } else {
      files.emplace_back(argv[i]);
    }
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) {
    std::fprintf(stderr, "%s: no input files\n", name.c_str());
    return 1;
  }
  int failed = 0;
  for (const fs::path& p : files) {
    std::ifstream f(p, std::ios::binary);
    if (!f) {
      std::fprintf(stderr, "%s: %s: cannot read\n", name.c_str(), p.string().c_str());
      ++failed;
      continue;
    }
    const std::vector<char> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    std::fprintf(stderr, "%s: %s (%zu bytes)\n", name.c_str(), p.string().c_str(), bytes.size());
    ellipsekit::fuzz::ELLIPSEKIT_FUZZ_ENTRY(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
  }
  std::printf("%s: %zu inputs, %d unreadable\n", name.c_str(), files.size(), failed);
  return failed ? 1 : 0;
}

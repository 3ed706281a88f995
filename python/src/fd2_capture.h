// File descriptors 1 and 2 are process-wide: whatever redirects them (the CLI's image loader turns
// decoder chatter on fd 2 into one message that way; FdCapture below collects what `ellipsekit track`
// prints) must hold Fd2Mutex(), or two threads would restore each other's descriptors.
#pragma once

#include <unistd.h>

#include <cstdio>
#include <mutex>
#include <string>

namespace ellipsekit::python {

inline std::mutex& Fd2Mutex() {
  static std::mutex m;
  return m;
}

// Redirects fd 1 and 2 (C's stdout and stderr) into temporary files for its lifetime (holding
// Fd2Mutex()); Finish() restores them and returns what went to fd 2, trailing newline removed (what
// went to fd 1 is dropped: a library call has no business printing).
class FdCapture {
 public:
  FdCapture() : lock_(Fd2Mutex()) {
    std::fflush(stdout);
    std::fflush(stderr);
    sink_ = std::tmpfile();
    out_sink_ = std::tmpfile();
    saved_ = sink_ != nullptr ? ::dup(2) : -1;
    if (saved_ >= 0) ::dup2(::fileno(sink_), 2);
    saved_out_ = out_sink_ != nullptr ? ::dup(1) : -1;
    if (saved_out_ >= 0) ::dup2(::fileno(out_sink_), 1);
  }
  FdCapture(const FdCapture&) = delete;
  FdCapture& operator=(const FdCapture&) = delete;
  ~FdCapture() { Finish(); }

  std::string Finish() {
    std::string text;
    if (saved_out_ >= 0) {
      std::fflush(stdout);
      ::dup2(saved_out_, 1);
      ::close(saved_out_);
      saved_out_ = -1;
    }
    if (out_sink_ != nullptr) {
      std::fclose(out_sink_);
      out_sink_ = nullptr;
    }
    if (saved_ >= 0) {
      std::fflush(stderr);
      ::dup2(saved_, 2);
      ::close(saved_);
      saved_ = -1;
      std::rewind(sink_);
      char buf[4096];
      std::size_t n;
      while ((n = std::fread(buf, 1, sizeof buf, sink_)) > 0) text.append(buf, n);
    }
    if (sink_ != nullptr) {
      std::fclose(sink_);
      sink_ = nullptr;
    }
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
    return text;
  }

 private:
  std::lock_guard<std::mutex> lock_;
  std::FILE* sink_ = nullptr;
  std::FILE* out_sink_ = nullptr;
  int saved_ = -1;
  int saved_out_ = -1;
};

}  // namespace ellipsekit::python

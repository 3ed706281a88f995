#include "tools/eval/ellipse_io.h"

#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <numbers>
#include <sstream>
#include <utility>

#include "tools/eval/text_lines.h"

namespace ellipsekit::eval {
namespace {

bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

}  // namespace

double NormalizeAngle(double theta) {
  const double pi = std::numbers::pi;
  double t = std::fmod(theta + pi / 2, pi);
  if (t < 0) t += pi;
  t -= pi / 2;
  if (t >= pi / 2) t -= pi;  // rounding at the upper end
  return t;
}

Status ParseEllipses(std::string_view text, const std::string& name, std::vector<Ellipse>* out) {
  if (out == nullptr) return Status(StatusCode::kInvalidArgument, "ParseEllipses: null output");
  out->clear();
  return ForEachTextLine(text, [&](int line_number, const std::string& line) {
    double v[5];
    int count = 0;
    const char* p = line.c_str();
    while (true) {
      while (IsSpace(*p)) ++p;
      if (*p == '\0') break;
      if (count == 5) return LineError(name, line_number, "more than 5 values (expected: cx cy a b theta)");
      char* next = nullptr;
      errno = 0;
      const double value = std::strtod(p, &next);
      if (next == p || (*next != '\0' && !IsSpace(*next))) {
        std::string token(p, std::strcspn(p, " \t\r\v\f"));
        return LineError(name, line_number, "not a number: '" + token + "'");
      }
      if (!std::isfinite(value)) return LineError(name, line_number, "value is not finite");
      v[count++] = value;
      p = next;
    }
    if (count == 0) return Status::Ok();  // blank or comment-only line
    if (count != 5) {
      return LineError(name, line_number,
                   "expected 5 values (cx cy a b theta), got " + std::to_string(count));
    }
    Ellipse e;
    e.cx = v[0];
    e.cy = v[1];
    e.a = v[2];
    e.b = v[3];
    e.theta = v[4];
    if (!(e.a > 0) || !(e.b > 0)) return LineError(name, line_number, "semi-axes must be > 0");
    if (e.a < e.b) {
      std::swap(e.a, e.b);
      e.theta += std::numbers::pi / 2;
    }
    e.theta = NormalizeAngle(e.theta);
    out->push_back(e);
    return Status::Ok();
  });
}

Status ReadEllipses(const std::string& path, std::vector<Ellipse>* out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    return Status(StatusCode::kInvalidArgument, path + ": cannot open: " + std::strerror(errno));
  }
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) return Status(StatusCode::kInvalidArgument, path + ": read error");
  return ParseEllipses(buffer.str(), path, out);
}

std::string FormatEllipse(const Ellipse& e) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%.4f %.4f %.4f %.4f %.6f", e.cx, e.cy, e.a, e.b, e.theta);
  return buf;
}

Status WriteEllipses(const std::string& path, const std::vector<Ellipse>& ellipses) {
  std::string text;
  for (const Ellipse& e : ellipses) {
    text += FormatEllipse(e);
    text += '\n';
  }
  return WriteFileAtomically(path, text);
}

Status WriteFileAtomically(const std::string& path, std::string_view contents) {
  // Unique per process, so concurrent writers of the same path do not share a temporary file.
  const std::string tmp = path + ".tmp." + std::to_string(static_cast<long>(::getpid()));
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (f == nullptr) {
    return Status(StatusCode::kInternal, tmp + ": cannot create: " + std::strerror(errno));
  }
  const bool wrote = std::fwrite(contents.data(), 1, contents.size(), f) == contents.size();
  const bool closed = std::fclose(f) == 0;
  if (!wrote || !closed) {
    std::remove(tmp.c_str());
    return Status(StatusCode::kInternal, tmp + ": write failed");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(tmp.c_str());
    return Status(StatusCode::kInternal, path + ": cannot rename temporary file: " + why);
  }
  return Status::Ok();
}

}  // namespace ellipsekit::eval

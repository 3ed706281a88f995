// The line-oriented text files of tools/eval (ground truth, per-top metadata): one record per
// line, '#' starts a comment; each parser decides what a blank line means.
#pragma once

#include <string>
#include <string_view>

#include "ellipsekit/types.h"

namespace ellipsekit::eval {

// Calls visit(line_number, line) for each line of `text` (numbers from 1; the line without its
// '#' comment and newline, a std::string the visitor may modify). Returns the first status
// visit returns that is not ok, else ok.
template <typename Visit>
Status ForEachTextLine(std::string_view text, Visit visit) {
  int line_number = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string line(text.substr(pos, end - pos));
    pos = end + 1;
    ++line_number;
    if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    if (Status st = visit(line_number, line); !st.ok()) return st;
  }
  return Status::Ok();
}

// "<name>:<line>: <what>", kInvalidArgument.
inline Status LineError(const std::string& name, int line, const std::string& what) {
  return Status(StatusCode::kInvalidArgument, name + ":" + std::to_string(line) + ": " + what);
}

}  // namespace ellipsekit::eval

// Minimal JSON text helpers for the CLI's reports (no library dependency).
#pragma once

#include <string>
#include <string_view>

namespace ellipsekit::cli {

// A JSON string literal, quotes included, with control characters escaped.
std::string JsonString(std::string_view text);
// A JSON number with `digits` decimals; NaN and infinities become null.
std::string JsonNumber(double value, int digits = 6);

}  // namespace ellipsekit::cli

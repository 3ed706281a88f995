// Minimal JSON text helpers for the CLI's reports (no library dependency).
#pragma once

#include <string>
#include <string_view>

namespace ellipsekit::cli {

// A JSON string literal, quotes included, with control characters escaped.
std::string JsonString(std::string_view text);
// A JSON number with `digits` decimals; NaN and infinities become null.
std::string JsonNumber(double value, int digits = 6);
// A JSON number with 17 significant digits: read back, it is the same double, bit for bit.
std::string JsonExactNumber(double value);

}  // namespace ellipsekit::cli

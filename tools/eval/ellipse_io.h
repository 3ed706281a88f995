// The ground-truth text format of ../shared/datasets (see its README.md):
//
//   one ellipse per line:  cx cy a b theta
//
// cx, cy: centre, px (pixel centres at integer coordinates, x right, y down); a >= b: semi-axes,
// px; theta: major-axis angle, rad (OpenCV RotatedRect angle). Blank lines are skipped and '#'
// starts a comment that runs to the end of the line. A line with anything but exactly five
// finite numbers, or with a semi-axis <= 0, is an error naming the file and the line number.
// A line with a < b is accepted and normalised (axes swapped, theta + pi/2); theta is
// normalised to [-pi/2, pi/2) on reading.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "ellipsekit/types.h"

namespace ellipsekit::eval {

// Parses `text`; `name` (a file name) is used in error messages: "<name>:<line>: <problem>".
Status ParseEllipses(std::string_view text, const std::string& name, std::vector<Ellipse>* out);

// Reads and parses a file; a missing or unreadable file is an error naming it.
Status ReadEllipses(const std::string& path, std::vector<Ellipse>* out);

// Formats one ellipse as a line of the format (no newline), 4 decimals for px, 6 for rad.
std::string FormatEllipse(const Ellipse& e);

// Writes the ellipses in the format, through a temporary file renamed onto `path`.
Status WriteEllipses(const std::string& path, const std::vector<Ellipse>& ellipses);

// Writes `contents` to a temporary file beside `path` and renames it onto `path`, so a reader
// never sees a half-written file.
Status WriteFileAtomically(const std::string& path, std::string_view contents);

// theta mapped into [-pi/2, pi/2).
double NormalizeAngle(double theta);

}  // namespace ellipsekit::eval

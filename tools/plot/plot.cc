// ellipsekit_plot: draws a grouped bar chart as a PNG with OpenCV.
//
//   ellipsekit_plot INPUT.tsv OUTPUT.png
// INPUT: line 1 "title<TAB>y-axis label[<TAB>log]" (log: logarithmic y axis); then one line per bar "group<TAB>series<TAB>value".
// Groups are laid out left to right in order of first appearance; within a group one bar per
// series (same colour for a series in every group, with a legend). Values must be >= 0.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace {

std::vector<std::string> SplitTabs(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string f;
  while (std::getline(ss, f, '\t')) out.push_back(f);
  return out;
}

int IndexOf(std::vector<std::string>* v, const std::string& s) {
  auto it = std::find(v->begin(), v->end(), s);
  if (it != v->end()) return static_cast<int>(it - v->begin());
  v->push_back(s);
  return static_cast<int>(v->size()) - 1;
}

// A "nice" axis step (1, 2 or 5 times a power of ten) giving about `ticks` ticks up to vmax.
double NiceStep(double vmax, int ticks) {
  const double raw = vmax / ticks;
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * p >= raw) return m * p;
  return 10 * p;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s INPUT.tsv OUTPUT.png\n", argv[0]);
    return 2;
  }
  std::ifstream in(argv[1]);
  if (!in) { std::fprintf(stderr, "ellipsekit_plot: cannot read %s\n", argv[1]); return 1; }
  std::string line;
  std::string title, ylabel;
  bool log_axis = false;
  if (std::getline(in, line)) {
    const auto f = SplitTabs(line);
    if (!f.empty()) title = f[0];
    if (f.size() > 1) ylabel = f[1];
    log_axis = f.size() > 2 && f[2] == "log";
  }
  std::vector<std::string> groups, series;
  std::map<std::pair<int, int>, double> values;
  double vmax = 0, vmin_pos = 0;
  int lineno = 1;
  while (std::getline(in, line)) {
    ++lineno;
    if (line.empty()) continue;
    const auto f = SplitTabs(line);
    if (f.size() != 3) { std::fprintf(stderr, "ellipsekit_plot: line %d: need 3 tab-separated fields\n", lineno); return 1; }
    char* end = nullptr;
    const double v = std::strtod(f[2].c_str(), &end);
    if (end == f[2].c_str() || !std::isfinite(v) || v < 0) {
      std::fprintf(stderr, "ellipsekit_plot: line %d: bad value '%s'\n", lineno, f[2].c_str());
      return 1;
    }
    values[{IndexOf(&groups, f[0]), IndexOf(&series, f[1])}] = v;
    vmax = std::max(vmax, v);
    if (v > 0) vmin_pos = vmin_pos == 0 ? v : std::min(vmin_pos, v);
  }
  if (groups.empty()) { std::fprintf(stderr, "ellipsekit_plot: no data\n"); return 1; }
  if (vmax <= 0) vmax = 1;

  const int W = 1100, H = 620, left = 110, right = 200, top = 60, bottom = 80;
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  const int font = cv::FONT_HERSHEY_SIMPLEX;
  const cv::Scalar black(0, 0, 0), grid(220, 220, 220);
  const int pw = W - left - right, ph = H - top - bottom;
  const double step = NiceStep(vmax, 6);
  const double ymax = log_axis ? std::pow(10.0, std::ceil(std::log10(vmax))) : std::ceil(vmax / step) * step;
  const double ymin = log_axis ? std::pow(10.0, std::floor(std::log10(vmin_pos > 0 ? vmin_pos : 1.0))) : 0.0;
  auto ypix = [&](double v) {
    double f;
    if (log_axis) f = v <= ymin ? 0.0 : std::log10(v / ymin) / std::log10(ymax / ymin);
    else f = v / ymax;
    return top + ph - static_cast<int>(std::lround(f * ph));
  };

  // Grid lines and y tick labels.
  std::vector<double> ticks;
  if (log_axis) {
    for (double v = ymin; v <= ymax * 1.001; v *= 10) ticks.push_back(v);
  } else {
    for (double v = 0; v <= ymax + step * 0.5; v += step) ticks.push_back(v);
  }
  for (double v : ticks) {
    const int y = ypix(v);
    cv::line(img, {left, y}, {left + pw, y}, grid, 1);
    char buf[32];
    std::snprintf(buf, sizeof buf, log_axis ? "%g" : (step < 1 ? "%.2f" : "%.0f"), v);
    int base = 0;
    const cv::Size ts = cv::getTextSize(buf, font, 0.45, 1, &base);
    cv::putText(img, buf, {left - 8 - ts.width, y + ts.height / 2}, font, 0.45, black, 1, cv::LINE_AA);
  }
  // Bars.
  static const cv::Scalar palette[] = {{180, 119, 31}, {14, 127, 255}, {44, 160, 44}, {40, 39, 214},
                                       {189, 103, 148}, {75, 86, 140}, {194, 119, 227}, {127, 127, 127}};
  const int ng = static_cast<int>(groups.size()), ns = static_cast<int>(series.size());
  const double gw = static_cast<double>(pw) / ng;
  const double bw = gw * 0.8 / ns;
  for (int g = 0; g < ng; ++g) {
    const double gx = left + g * gw + gw * 0.1;
    for (int s = 0; s < ns; ++s) {
      auto it = values.find({g, s});
      if (it == values.end()) continue;
      const int x0 = static_cast<int>(gx + s * bw), x1 = static_cast<int>(gx + (s + 1) * bw) - 2;
      const int y0 = ypix(it->second);
      cv::rectangle(img, {x0, y0}, {x1, top + ph}, palette[s % 8], cv::FILLED);
      char buf[32];
      std::snprintf(buf, sizeof buf, it->second < 100 ? "%.3g" : "%.0f", it->second);
      int base = 0;
      const cv::Size ts = cv::getTextSize(buf, font, 0.35, 1, &base);
      cv::putText(img, buf, {(x0 + x1) / 2 - ts.width / 2, y0 - 4}, font, 0.35, black, 1, cv::LINE_AA);
    }
    int base = 0;
    const cv::Size ts = cv::getTextSize(groups[g], font, 0.55, 1, &base);
    cv::putText(img, groups[g], {static_cast<int>(left + g * gw + gw / 2 - ts.width / 2.0), top + ph + 25}, font,
                0.55, black, 1, cv::LINE_AA);
  }
  // Axes, title, y label, legend.
  cv::line(img, {left, top}, {left, top + ph}, black, 1);
  cv::line(img, {left, top + ph}, {left + pw, top + ph}, black, 1);
  int base = 0;
  const cv::Size tts = cv::getTextSize(title, font, 0.7, 2, &base);
  cv::putText(img, title, {W / 2 - tts.width / 2, 35}, font, 0.7, black, 2, cv::LINE_AA);
  cv::Mat label(30, ph, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Size lts = cv::getTextSize(ylabel, font, 0.55, 1, &base);
  cv::putText(label, ylabel, {ph / 2 - lts.width / 2, 21}, font, 0.55, black, 1, cv::LINE_AA);
  cv::rotate(label, label, cv::ROTATE_90_COUNTERCLOCKWISE);
  label.copyTo(img(cv::Rect(8, top, 30, ph)));
  for (int s = 0; s < ns; ++s) {
    const int y = top + 10 + s * 26;
    cv::rectangle(img, {left + pw + 20, y}, {left + pw + 38, y + 16}, palette[s % 8], cv::FILLED);
    cv::putText(img, series[s], {left + pw + 46, y + 13}, font, 0.5, black, 1, cv::LINE_AA);
  }
  if (!cv::imwrite(argv[2], img)) { std::fprintf(stderr, "ellipsekit_plot: cannot write %s\n", argv[2]); return 1; }
  return 0;
}

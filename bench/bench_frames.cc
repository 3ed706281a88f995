#include "bench/bench_frames.h"

#include <algorithm>
#include <string>
#include <utility>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "ellipsekit/options.h"
#include "kernels/edge_sign.h"
#include "kernels/gaussian.h"
#include "kernels/hysteresis.h"
#include "kernels/nms.h"
#include "kernels/sobel.h"

namespace ellipsekit::bench {

namespace ek = ellipsekit;

namespace {
std::vector<std::function<void()>>& Releases() {
  static std::vector<std::function<void()>> releases;
  return releases;
}
}  // namespace

void AtBenchEnd(std::function<void()> release) { Releases().push_back(std::move(release)); }

void ReleaseBenchResources() {
  auto& r = Releases();
  while (!r.empty()) {
    std::function<void()> release = std::move(r.back());
    r.pop_back();
    release();
  }
}

std::vector<std::filesystem::path> ImagesIn(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> out;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    const std::string ext = e.path().extension().string();
    if (ext == ".jpg" || ext == ".png" || ext == ".bmp" || ext == ".jpeg") out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::filesystem::path> PrasadImages() { return ImagesIn(kPrasadDir); }

cv::Mat LoadGray(const std::filesystem::path& p) { return cv::imread(p.string(), cv::IMREAD_GRAYSCALE); }

ek::ImageView View(const cv::Mat& m) {
  ek::ImageView v;
  v.data = m.data;
  v.width = m.cols;
  v.height = m.rows;
  v.stride = static_cast<std::ptrdiff_t>(m.step[0]);
  return v;
}


void PrepareFrom(const cv::Mat& frame, Prepared* p) {
  p->frame = frame.isContinuous() ? frame : frame.clone();
  const int w = p->w = frame.cols, h = p->h = frame.rows;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  p->blurred.resize(n); p->nms.resize(n); p->hyst.resize(n); p->edges.resize(n); p->scratch_u8.resize(n);
  p->dx.resize(n); p->dy.resize(n); p->mag.resize(n);
  p->hist.resize(ek::kMaxMagnitude + 1);
  p->stack.resize(n);
  const ek::Options o;
  ek::scalar::Gaussian(p->frame.data, w, w, h, p->blurred.data(), w);
  ek::scalar::Sobel(p->blurred.data(), w, w, h, p->dx.data(), p->dy.data(), p->mag.data(), w);
  p->tiles.Resize(w, h, o);
  ek::scalar::MagnitudeHistogram(p->mag.data(), w, h, w, p->tiles.shift, p->hist.data(), p->tiles.tile_max.data());
  ek::SelectThresholds(p->hist.data(), o, &p->tiles);
  p->th = p->tiles.frame;
  ek::scalar::Nms(p->dx.data(), p->dy.data(), p->mag.data(), w, h, w, p->tiles.view(), p->nms.data(), w);
  p->hyst = p->nms;
  ek::scalar::Hysteresis(p->hyst.data(), w, h, w, p->stack.data());
  ek::scalar::EdgeSign(p->hyst.data(), w, p->dx.data(), p->dy.data(), w, w, h, p->edges.data(), w);
}

void BlurCanny(const cv::Mat& frame, const CannyThresholds& th, cv::Mat* blurred, cv::Mat* edges) {
  cv::GaussianBlur(frame, *blurred, cv::Size(3, 3), 0, 0, cv::BORDER_REPLICATE);
  cv::Canny(*blurred, *edges, th.low, th.high, 3, false);
}

void SetRates(benchmark::State& st, std::int64_t pixels, std::int64_t bytes_per_iter) {
  st.SetItemsProcessed(st.iterations() * pixels);
  st.SetBytesProcessed(st.iterations() * bytes_per_iter);
}


}  // namespace ellipsekit::bench

// _ellipsekit: the compiled half of the `ellipsekit` Python package (pybind11).
//
// It wraps the public C++ API and nothing else: ellipsekit::Detector (options set through
// ellipsekit::SetOption, checked by ValidateOptions, so names, values and messages are the CLI's),
// the CLI's image loader (tools/cli/image_io.cc, compiled in), and the scoring of tools/eval.
// The pure-Python package (python/ellipsekit/) puts the user-facing classes on top.
//
// Contracts:
//   - detect() reads a 2-D uint8 array in place when its pixels are contiguous within a row (any
//     row stride >= width); otherwise it copies it once into a buffer the Detector keeps. A 3-channel
//     uint8 array is taken as BGR (OpenCV's order, which `ellipsekit detect` decodes to) and
//     converted with cv::cvtColor(COLOR_BGR2GRAY), exactly as the CLI does.
//   - The GIL is released while a frame is converted and detected and while an image is decoded.
//     A Detector serialises its own calls (a mutex), so sharing one between threads is safe but
//     does not scale; one Detector per thread does.
//   - The CLI's loader redirects fd 2 while it decodes (to turn decoder chatter into one message);
//     fd 2 is process-wide, so decoding is serialised by one process-wide mutex.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "ellipsekit/ellipsekit.h"
#include "python/src/fd2_capture.h"
#include "python/src/robot.h"
#include "tools/cli/image_io.h"
#include "tools/eval/dataset.h"
#include "tools/eval/ellipse_io.h"
#include "tools/eval/metrics.h"

namespace py = pybind11;

namespace ellipsekit::python {
namespace {

// A Status that is not ok, as the Python exception that fits it.
[[noreturn]] void Raise(const Status& st) {
  if (st.code() == StatusCode::kInvalidArgument) throw py::value_error(st.message());
  throw std::runtime_error(st.message());
}

std::string TypeName(const py::handle& h) { return py::str(py::type::of(h).attr("__name__")); }

std::string DescribeArray(const py::array& a) {
  std::string shape = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) shape += (i ? ", " : "") + std::to_string(a.shape(i));
  shape += a.ndim() == 1 ? ",)" : ")";
  return "an array of dtype " + std::string(py::str(a.dtype())) + " and shape " + shape;
}

py::dict TimingsDict(const StageTimings& t) {
  py::dict d;
  d["edges_ms"] = t.edges_ms;
  d["curves_ms"] = t.curves_ms;
  d["arcs_ms"] = t.arcs_ms;
  d["fit_ms"] = t.fit_ms;
  d["validate_ms"] = t.validate_ms;
  d["total_ms"] = t.total_ms;
  return d;
}

py::dict CountsDict(const DetectionResult& r) {
  py::dict d;
  d["edge_pixels"] = r.num_edge_pixels;
  d["curves"] = r.num_curves;
  d["arcs"] = r.num_arcs;
  d["pairs"] = r.num_pairs;
  d["triplets"] = r.num_triplets;
  d["candidates"] = r.num_candidates;
  d["noise_sigma"] = r.noise_sigma;
  d["denoise_passes"] = r.denoise_passes;
  return d;
}

py::list CapsList(unsigned caps) {
  py::list names;
  for (CapFlags flag : kAllCaps)
    if ((caps & flag) != 0) names.append(CapName(flag));
  return names;
}

// (N, 6) float64: cx, cy, a, b, theta, score per row, in the result's order.
py::array_t<double> EllipseArray(const std::vector<Ellipse>& ellipses) {
  py::array_t<double> out({static_cast<py::ssize_t>(ellipses.size()), static_cast<py::ssize_t>(6)});
  auto m = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < ellipses.size(); ++i) {
    const Ellipse& e = ellipses[i];
    const py::ssize_t r = static_cast<py::ssize_t>(i);
    m(r, 0) = e.cx;
    m(r, 1) = e.cy;
    m(r, 2) = e.a;
    m(r, 3) = e.b;
    m(r, 4) = e.theta;
    m(r, 5) = e.score;
  }
  return out;
}

std::vector<Ellipse> EllipsesFromArray(const py::array& obj, const char* what, int min_columns) {
  const py::array_t<double, py::array::c_style | py::array::forcecast> a(obj);
  if (a.ndim() != 2 || a.shape(1) < min_columns)
    throw py::type_error(std::string(what) + ": expected an (N, " + std::to_string(min_columns) +
                         ") or wider array of cx, cy, a, b, theta[, score], got " + DescribeArray(obj));
  std::vector<Ellipse> out(static_cast<std::size_t>(a.shape(0)));
  const auto v = a.unchecked<2>();
  for (py::ssize_t i = 0; i < a.shape(0); ++i) {
    Ellipse& e = out[static_cast<std::size_t>(i)];
    e.cx = v(i, 0);
    e.cy = v(i, 1);
    e.a = v(i, 2);
    e.b = v(i, 3);
    e.theta = v(i, 4);
    e.score = a.shape(1) > 5 ? v(i, 5) : 0.0;
  }
  return out;
}

// A gray cv::Mat handed to numpy without a copy: the capsule owns a heap copy of the Mat header
// (which holds the reference count of the pixels).
py::array_t<std::uint8_t> ArrayOfMat(const cv::Mat& gray) {
  auto* owner = new cv::Mat(gray);
  py::capsule free_mat(owner, [](void* p) { delete static_cast<cv::Mat*>(p); });
  return py::array_t<std::uint8_t>({static_cast<py::ssize_t>(gray.rows), static_cast<py::ssize_t>(gray.cols)},
                                   {static_cast<py::ssize_t>(gray.step[0]), static_cast<py::ssize_t>(1)},
                                   gray.ptr<std::uint8_t>(), free_mat);
}

// The CLI's loader. Returns (array or None, error message or "", note or "").
py::tuple LoadGray(const std::string& path) {
  cli::LoadedImage image;
  std::string error;
  bool ok;
  {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(Fd2Mutex());
    ok = cli::LoadImage(path, &image, &error);
  }
  if (!ok) return py::make_tuple(py::none(), error, "");
  return py::make_tuple(ArrayOfMat(image.gray), "", image.note);
}

class PyDetector {
 public:
  // `assignments`: "name=value" texts, applied in order with ellipsekit::SetOption.
  explicit PyDetector(const std::vector<std::string>& assignments) {
    Options options;
    for (const std::string& a : assignments) {
      const Status st = SetOption(a, &options);
      if (!st.ok()) Raise(st);
    }
    const Status valid = ValidateOptions(options);
    if (!valid.ok()) Raise(valid);
    detector_ = Detector(options);
    if (!detector_.status().ok()) Raise(detector_.status());
  }

  std::string backend_note() const { return detector_.backend_note(); }
  std::string backend() const { return BackendName(detector_.options().backend); }
  std::string simd_target() const { return detector_.options().simd_target; }

  // Returns (ellipses (N, 6) float64, figures dict).
  py::tuple Detect(const py::object& obj) {
    if (!py::isinstance<py::array>(obj))
      throw py::type_error("detect() expects a numpy array of dtype uint8, shape (H, W) or (H, W, 3); got " +
                           TypeName(obj));
    const py::array image = py::reinterpret_borrow<py::array>(obj);
    const py::dtype dt = image.dtype();
    const bool is_u8 = dt.kind() == 'u' && dt.itemsize() == 1;
    const bool gray = image.ndim() == 2;
    const bool color = image.ndim() == 3 && image.shape(2) == 3;
    if (!is_u8 || !(gray || color))
      throw py::type_error("detect() expects a uint8 array of shape (H, W) (gray) or (H, W, 3) (BGR); got " +
                           DescribeArray(image));
    const py::ssize_t h = image.shape(0), w = image.shape(1);
    if (h > INT32_MAX || w > INT32_MAX)
      throw py::value_error("image size " + std::to_string(w) + "x" + std::to_string(h) + " is too large");
    const auto* base = static_cast<const std::uint8_t*>(image.data());
    const py::ssize_t s0 = image.strides(0), s1 = image.strides(1);
    const py::ssize_t s2 = color ? image.strides(2) : 1;

    Status st;
    bool copied = false;
    // Held until the result is read below; taken only with the GIL released (no lock-order cycle).
    std::unique_lock<std::mutex> lock(mutex_, std::defer_lock);
    {
      py::gil_scoped_release release;
      lock.lock();
      ImageView view;
      view.width = static_cast<int>(w);
      view.height = static_cast<int>(h);
      const py::ssize_t pixel = color ? 3 : 1;
      // In place: pixels (and channels) contiguous in a row, rows at a positive stride that
      // does not make rows overlap. Anything else is gathered once into copy_.
      const bool in_place = h > 0 && w > 0 && s1 == pixel && s2 == 1 && s0 >= w * pixel;
      const std::uint8_t* data = base;
      std::ptrdiff_t stride = static_cast<std::ptrdiff_t>(s0);
      if (!in_place && h > 0 && w > 0) {
        copy_.resize(static_cast<std::size_t>(h * w * pixel));
        for (py::ssize_t y = 0; y < h; ++y)
          for (py::ssize_t x = 0; x < w; ++x)
            for (py::ssize_t c = 0; c < pixel; ++c)
              copy_[static_cast<std::size_t>((y * w + x) * pixel + c)] = base[y * s0 + x * s1 + c * s2];
        data = copy_.data();
        stride = static_cast<std::ptrdiff_t>(w * pixel);
        copied = true;
      }
      if (color && h > 0 && w > 0) {
        const cv::Mat bgr(static_cast<int>(h), static_cast<int>(w), CV_8UC3, const_cast<std::uint8_t*>(data),
                          static_cast<std::size_t>(stride));
        cv::cvtColor(bgr, gray_, cv::COLOR_BGR2GRAY);
        data = gray_.ptr<std::uint8_t>();
        stride = static_cast<std::ptrdiff_t>(gray_.step[0]);
      }
      view.data = (h > 0 && w > 0) ? data : base;
      view.stride = (h > 0 && w > 0) ? stride : static_cast<std::ptrdiff_t>(w);
      st = detector_.detect(view, &result_);
    }
    if (!st.ok()) Raise(st);
    py::dict figures;
    figures["timings"] = TimingsDict(result_.timings);
    figures["counts"] = CountsDict(result_);
    figures["caps_hit"] = CapsList(result_.caps_hit);
    figures["backend"] = BackendName(result_.backend);
    figures["simd_target"] = std::string(result_.simd_target ? result_.simd_target : "");
    figures["input_copied"] = copied;
    return py::make_tuple(EllipseArray(result_.ellipses), figures);
  }

 private:
  Detector detector_;
  DetectionResult result_;
  std::vector<std::uint8_t> copy_;
  cv::Mat gray_;
  std::mutex mutex_;
};

// Ground truth of ../shared/datasets' format (tools/eval/ellipse_io.h) as (N, 5): cx, cy, a, b, theta.
py::array_t<double> ReadEllipsesArray(const std::string& path) {
  std::vector<Ellipse> e;
  const Status st = eval::ReadEllipses(path, &e);
  if (!st.ok()) throw py::value_error(st.message());
  py::array_t<double> out({static_cast<py::ssize_t>(e.size()), static_cast<py::ssize_t>(5)});
  auto m = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < e.size(); ++i) {
    const py::ssize_t r = static_cast<py::ssize_t>(i);
    m(r, 0) = e[i].cx;
    m(r, 1) = e[i].cy;
    m(r, 2) = e[i].a;
    m(r, 3) = e[i].b;
    m(r, 4) = e[i].theta;
  }
  return out;
}

// `ellipsekit eval`'s per-image scoring: (detected, truth, correct) of eval::MatchEllipses.
py::tuple MatchCounts(const py::array& detections, const py::array& truth,
                      const std::vector<std::tuple<double, double, double, double>>& dont_care) {
  const std::vector<Ellipse> d = EllipsesFromArray(detections, "detections", 5);
  const std::vector<Ellipse> t = EllipsesFromArray(truth, "truth", 5);
  std::vector<eval::BoundingBox> boxes;
  for (const auto& [x0, y0, x1, y1] : dont_care) boxes.push_back({x0, y0, x1, y1});
  eval::MatchResult m;
  {
    py::gil_scoped_release release;
    m = eval::MatchEllipses(d, t, eval::kOverlapThreshold, boxes);
  }
  return py::make_tuple(m.counts.detected, m.counts.truth, m.counts.correct);
}

// border_boxes.txt (tools/eval/dataset.h) -> {stem: [(x0, y0, x1, y1), ...]}.
py::dict ReadDontCare(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw py::value_error(path + ": cannot read");
  std::stringstream text;
  text << file.rdbuf();
  std::map<std::string, std::vector<eval::BoundingBox>> boxes;
  const Status st = eval::ParseDontCareBoxes(text.str(), path, &boxes);
  if (!st.ok()) throw py::value_error(st.message());
  py::dict out;
  for (const auto& [stem, list] : boxes) {
    py::list l;
    for (const eval::BoundingBox& b : list) l.append(py::make_tuple(b.x0, b.y0, b.x1, b.y1));
    out[py::str(stem)] = l;
  }
  return out;
}

}  // namespace
}  // namespace ellipsekit::python

PYBIND11_MODULE(_ellipsekit, m) {
  using namespace ellipsekit::python;
  m.doc() = "Compiled core of the ellipsekit package; use the names re-exported by `ellipsekit`.";

  py::class_<PyDetector>(m, "Detector")
      .def(py::init<const std::vector<std::string>&>(), py::arg("assignments"),
           "Detector from 'name=value' option assignments (ellipsekit::SetOption), then ValidateOptions.")
      .def("detect", &PyDetector::Detect, py::arg("image"),
           "detect(image) -> (ellipses (N, 6) float64, figures dict); releases the GIL.")
      .def_property_readonly("backend_note", &PyDetector::backend_note)
      .def_property_readonly("backend", &PyDetector::backend)
      .def_property_readonly("simd_target", &PyDetector::simd_target);

  m.def("load_gray", &LoadGray, py::arg("path"),
        "The CLI's loader: (array or None, error or '', note or ''); releases the GIL while decoding.");
  m.def("read_ellipses", &ReadEllipsesArray, py::arg("path"),
        "Ground-truth file (cx cy a b theta per line) -> (N, 5) float64; ValueError naming file and line.");
  m.def("match_counts", &MatchCounts, py::arg("detections"), py::arg("truth"),
        py::arg("dont_care") = std::vector<std::tuple<double, double, double, double>>{},
        "`ellipsekit eval`'s scoring of one image: (detected, truth, correct) at Jaccard > 0.8.");
  m.def("read_dont_care", &ReadDontCare, py::arg("path"),
        "border_boxes.txt -> {image stem: [(x0, y0, x1, y1), ...]}.");
  m.def("is_image_extension", [](const std::string& ext) { return ellipsekit::eval::IsImageExtension(ext); }, py::arg("ext"),
        "True for the extensions `ellipsekit eval` lists in a dataset (.png .jpg .jpeg .bmp, any case).");
  m.def("prf", [](int detected, int truth, int correct) {
          namespace eval = ellipsekit::eval;
          const eval::MatchCounts c{detected, truth, correct};
          const double p = eval::Precision(c), r = eval::Recall(c);
          return py::make_tuple(p, r, eval::FMeasure(p, r));
        }, py::arg("detected"), py::arg("truth"), py::arg("correct"),
        "`ellipsekit eval`'s precision, recall and F-measure of summed counts.");
  RegisterRobot(m);
}

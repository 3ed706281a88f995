// The robot adapter's pieces a Python script needs (include/ellipsekit/robot/): the camera model, the
// circle pose from one ellipse, and `ellipsekit track` over a sequence directory.
#include "python/src/robot.h"

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <unistd.h>

#include <cstdio>
#include <mutex>
#include <string>
#include <vector>

#include "ellipsekit/robot/camera_model.h"
#include "ellipsekit/robot/circle_pose.h"
#include "python/src/fd2_capture.h"
#include "tools/cli/args.h"
#include "tools/cli/commands.h"

namespace py = pybind11;

namespace ellipsekit::python {
namespace {

using robot::CameraModel;
using robot::CirclePose;

Ellipse EllipseOf(const std::vector<double>& v) {
  if (v.size() < 5)
    throw py::value_error("ellipse: expected cx, cy, a, b, theta[, score], got " + std::to_string(v.size()) + " numbers");
  Ellipse e;
  e.cx = v[0];
  e.cy = v[1];
  e.a = v[2];
  e.b = v[3];
  e.theta = v[4];
  e.score = v.size() > 5 ? v[5] : 0.0;
  return e;
}

py::dict PoseDict(const CirclePose& p) {
  py::dict d;
  d["centre"] = p.centre;
  d["normal"] = p.normal;
  d["centre_pixel"] = p.centre_pixel;
  return d;
}

template <class T>
const T& Value(const robot::Result<T>& r) {
  if (!r.ok()) throw py::value_error(r.status.message());
  return r.value;
}

}  // namespace

void RegisterRobot(py::module_& m) {
  py::class_<CameraModel>(m, "CameraModel",
                          "Pinhole camera with plumb_bob / rational_polynomial distortion "
                          "(include/ellipsekit/robot/camera_model.h).\n\n"
                          "Camera optical frame: x right, y down, z forward, metres; pixel centres at integers.")
      .def(py::init([](double fx, double fy, double cx, double cy, const std::vector<double>& d, int width,
                       int height) {
             if (!(fx > 0) || !(fy > 0)) throw py::value_error("CameraModel: fx and fy must be > 0");
             if (!(d.size() <= 5 || d.size() == 8))
               throw py::value_error("CameraModel: d must have up to 5 (plumb_bob) or 8 (rational_polynomial) "
                                     "coefficients, got " + std::to_string(d.size()));
             return CameraModel::FromIntrinsics(fx, fy, cx, cy, d, width, height);
           }),
           py::arg("fx"), py::arg("fy"), py::arg("cx"), py::arg("cy"), py::arg("d") = std::vector<double>{},
           py::arg("width") = 0, py::arg("height") = 0,
           "CameraModel(fx, fy, cx, cy, d=(), width=0, height=0): intrinsics in pixels; d = k1, k2, t1, t2, k3 "
           "(shorter is padded with zeros) or 8 rational coefficients.")
      .def_property_readonly("fx", &CameraModel::fx)
      .def_property_readonly("fy", &CameraModel::fy)
      .def_property_readonly("cx", &CameraModel::cx)
      .def_property_readonly("cy", &CameraModel::cy)
      .def_property_readonly("width", &CameraModel::width)
      .def_property_readonly("height", &CameraModel::height)
      .def_property_readonly("has_distortion", &CameraModel::has_distortion)
      .def_property_readonly("K", &CameraModel::K, "3x3 intrinsic matrix (pixels).")
      .def("project", [](const CameraModel& c, const Eigen::Vector3d& p) { return Value(c.Project(p)); },
           py::arg("point"), "Camera-frame point (metres, z > 0) -> raw pixel (u, v); ValueError for z <= 0.")
      .def("pixel_to_ray", &CameraModel::PixelToRay, py::arg("pixel"),
           "Raw pixel (u, v) -> unit ray in the camera frame (z > 0).")
      .def("undistort_pixel", &CameraModel::UndistortPixel, py::arg("pixel"),
           "Raw pixel -> undistorted normalised coordinates (x/z, y/z).")
      .def("__repr__", [](const CameraModel& c) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "CameraModel(fx=%g, fy=%g, cx=%g, cy=%g, distortion=%s)", c.fx(), c.fy(),
                      c.cx(), c.cy(), c.has_distortion() ? "True" : "False");
        return std::string(buf);
      });

  m.def("circle_pose_candidates",
        [](const std::vector<double>& ellipse, double radius, const CameraModel& camera) {
          const auto both = Value(robot::CirclePoseCandidates(EllipseOf(ellipse), radius, camera));
          return py::make_tuple(PoseDict(both[0]), PoseDict(both[1]));
        },
        py::arg("ellipse"), py::arg("radius"), py::arg("camera"));
  m.def("circle_pose_by_normal",
        [](const std::vector<double>& ellipse, double radius, const CameraModel& camera, const Eigen::Vector3d& n) {
          return PoseDict(Value(robot::CirclePoseByNormal(EllipseOf(ellipse), radius, camera, n)));
        },
        py::arg("ellipse"), py::arg("radius"), py::arg("camera"), py::arg("expected_normal"));
  m.def("circle_pose_by_depth",
        [](const std::vector<double>& ellipse, double radius, const CameraModel& camera, double z) {
          return PoseDict(Value(robot::CirclePoseByDepth(EllipseOf(ellipse), radius, camera, z)));
        },
        py::arg("ellipse"), py::arg("radius"), py::arg("camera"), py::arg("depth_z"));

  // `ellipsekit track` itself (tools/cli/track_command.cc, compiled in): same loader, detector, tracker
  // and output. Returns (exit status, what it printed on stderr).
  m.def("run_track", [](const std::vector<std::string>& args) {
    int rc = 0;
    std::string err;
    {
      py::gil_scoped_release release;
      FdCapture capture;
      try {
        rc = cli::RunTrack(args);
      } catch (const cli::UsageError& e) {
        std::fprintf(stderr, "%s\n", e.what());
        rc = 2;
      }
      err = capture.Finish();
    }
    return py::make_tuple(rc, err);
  });
}

}  // namespace ellipsekit::python

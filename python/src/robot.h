// Registers the robot adapter's bindings (robot.cc) in the _ellipsekit module.
#pragma once

#include <pybind11/pybind11.h>

namespace ellipsekit::python {

void RegisterRobot(pybind11::module_& m);

}  // namespace ellipsekit::python

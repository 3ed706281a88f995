// Umbrella header of the robot adapter (library target ellipsekit_robot).
#pragma once

#include "ellipsekit/robot/camera_model.h"
#include "ellipsekit/robot/circle_pose.h"
#include "ellipsekit/robot/conic.h"
#include "ellipsekit/robot/conveyor.h"
#include "ellipsekit/robot/depth_sampling.h"
#include "ellipsekit/robot/frame_loop.h"
#include "ellipsekit/robot/grasp.h"
#include "ellipsekit/robot/hungarian.h"
#include "ellipsekit/robot/kalman.h"
#include "ellipsekit/robot/messages.h"
#include "ellipsekit/robot/rim_centre.h"
#include "ellipsekit/robot/ros_adapters.h"
#include "ellipsekit/robot/stacking.h"
#include "ellipsekit/robot/tracker.h"

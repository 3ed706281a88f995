// Umbrella header for the ellipsekit public API.
#pragma once

#include "ellipsekit/detector.h"
#include "ellipsekit/options.h"
#include "ellipsekit/stream.h"
#include "ellipsekit/types.h"

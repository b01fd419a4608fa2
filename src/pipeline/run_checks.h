// The checks Simulate makes of a run before anything is allocated, in the
// order it makes them.
#pragma once

#include <string>

#include "fss/core/image.h"
#include "fss/model/code.h"
#include "fss/pipeline/geometry.h"
#include "fss/pipeline/simulation_options.h"

namespace fss {

// Valid options, a code the mode can use, a dark charge double precision
// resolves (the checks that need no image).
void check_run_settings(const SimulationOptions& options, const ShutterCode& code);

// check_run_settings, then 1 or 3 channels.
void check_inputs(const SimulationOptions& options, const Image& input, const ShutterCode& code);

// "" unless the restore velocity's blur is the larger and does not fit an
// image `width` wide; then "over L slots of dt D spans N pixels, more than
// the image width W".
std::string restore_blur_excess(const SimulationOptions& options, int width, int code_length);

// The |velocity| whose blur sets a run's geometry: the larger of |v| (under a velocity
// distribution, the largest |v| of its support) and |v_r|.
double geometry_velocity(const SimulationOptions& options);

// The geometry of a run (docs/method.md §4): the blur length B covers both
// velocities (under a velocity distribution, geometry_velocity's, §13). Throws a usage
// fss::Error for an image too narrow.
Geometry run_geometry(const SimulationOptions& options, int width, const ShutterCode& code);

// check_run_settings, then run_geometry and its metric windows.
Geometry checked_geometry(const SimulationOptions& options, int width, const ShutterCode& code);

}  // namespace fss

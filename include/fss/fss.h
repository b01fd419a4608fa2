// fss, the flutter shutter camera simulator library: this header includes every public header;
// each also compiles alone.
//
// Conventions every function follows (the API's one statement of them):
//  - Layout: images are planar doubles, channel c, row y, column x at
//    data[(c * height + y) * width + x]; rows are the direction of motion.
//  - Scale: 0..255, as an 8-bit image (a 16-bit sample s reads as s / 257); nothing is clamped
//    inside the pipeline, only 8-bit encoding rounds and clamps.
//  - Channels: 1 (gray) or 3 (RGB), always processed independently; alpha is dropped on reading.
//  - Ranges: column ranges are half-open [first, end).
//  - Threads: a `threads` argument or field of 0 means all hardware threads; no result depends
//    on it: the same inputs and seed give the same bytes.
//  - Errors: every failure throws fss::Error (core/error.h), one line naming the field, file or
//    value and what was expected; its kind tells usage, runtime and memory-limit errors apart.
//  - Options: plain structs with defaults at the declaration and
//    `bool IsValid(std::string* error) const`; one call runs the work
//    (SimulationOptions -> Simulate() -> SimulationReport::FullReport()).
//  - Names follow the paper (Tendero, IPOL 2012) and docs/method.md, cited as §N.
#pragma once

#include "fss/campaign/check.h"
#include "fss/campaign/figures.h"
#include "fss/campaign/gaps.h"
#include "fss/campaign/results.h"
#include "fss/campaign/run.h"
#include "fss/campaign/spec.h"
#include "fss/campaign/table.h"
#include "fss/core/error.h"
#include "fss/core/image.h"
#include "fss/design/analyze.h"
#include "fss/design/generate.h"
#include "fss/design/optimize.h"
#include "fss/io/image_io.h"
#include "fss/io/outputs.h"
#include "fss/io/plot.h"
#include "fss/io/png_io.h"
#include "fss/io/report_json.h"
#include "fss/io/simulate_to_folder.h"
#include "fss/io/tiff_io.h"
#include "fss/model/code.h"
#include "fss/model/kernel.h"
#include "fss/model/restoration.h"
#include "fss/model/sensor.h"
#include "fss/model/transfer.h"
#include "fss/model/velocity_distribution.h"
#include "fss/pipeline/geometry.h"
#include "fss/pipeline/memory_estimate.h"
#include "fss/pipeline/metrics.h"
#include "fss/pipeline/option_rules.h"
#include "fss/pipeline/prediction.h"
#include "fss/pipeline/simulate.h"
#include "fss/pipeline/simulation_options.h"

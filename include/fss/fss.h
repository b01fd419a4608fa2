// fss: the flutter shutter camera simulator library. Including this header
// gives the whole public API; each header below can also be included alone.
//
// Conventions every function follows (stated here once; core/image.h holds
// the same list next to the image type):
//  - Layout: images are planar doubles, channel c, row y, column x at
//    data[(c * height + y) * width + x]; rows are the direction of motion.
//  - Scale: values on the 0..255 scale of an 8-bit image; nothing is clamped
//    inside the pipeline, only 8-bit encoding rounds and clamps.
//  - Channels: 1 (gray) or 3 (RGB), always processed independently.
//  - Ranges: column ranges are half-open [first, end).
//  - Threads: a `threads` argument or field of 0 means all hardware threads;
//    no result ever depends on it, and the same inputs and seed give the
//    same bytes.
//  - Errors: every failure throws fss::Error (core/error.h), one line naming
//    the field, file or value and what was expected; its kind tells usage
//    from runtime and memory-limit errors.
//  - Options: plain structs with defaults at the declaration and
//    `bool IsValid(std::string* error) const`; one call runs the work
//    (SimulationOptions -> Simulate() -> SimulationReport::FullReport()).
//
// Naming: functions and types are named after the paper (Tendero, IPOL 2012)
// and docs/method.md, whose section numbers the comments cite (§N).
//
// Domains: core/ (image, errors, FFT, threads), model/ (codes, transfer
// function, kernel analysis, photon noise), pipeline/ (geometry, observation,
// restoration, metrics, prediction, Simulate), design/ (generating,
// analysing and optimizing codes), io/ (PNG, plots, a run's output files),
// campaign/ (images x codes x settings: resumable runs, shards, checks).
#pragma once

#include "fss/campaign/check.h"
#include "fss/campaign/figures.h"
#include "fss/campaign/results.h"
#include "fss/campaign/run.h"
#include "fss/campaign/sha256.h"
#include "fss/campaign/spec.h"
#include "fss/core/error.h"
#include "fss/core/fft.h"
#include "fss/core/image.h"
#include "fss/core/number_text.h"
#include "fss/core/parallel.h"
#include "fss/design/analyze.h"
#include "fss/design/generate.h"
#include "fss/design/optimize.h"
#include "fss/io/html_report.h"
#include "fss/io/observed_png8.h"
#include "fss/io/output_set.h"
#include "fss/io/outputs.h"
#include "fss/io/plot.h"
#include "fss/io/png_io.h"
#include "fss/io/report_json.h"
#include "fss/io/run_files.h"
#include "fss/io/run_plots.h"
#include "fss/io/run_text.h"
#include "fss/io/sheet.h"
#include "fss/model/code.h"
#include "fss/model/kernel.h"
#include "fss/model/noise.h"
#include "fss/model/sensor.h"
#include "fss/model/transfer.h"
#include "fss/pipeline/geometry.h"
#include "fss/pipeline/metrics.h"
#include "fss/pipeline/noise_weights.h"
#include "fss/pipeline/observe.h"
#include "fss/pipeline/option_rules.h"
#include "fss/pipeline/prediction.h"
#include "fss/pipeline/restore.h"
#include "fss/pipeline/simulate.h"

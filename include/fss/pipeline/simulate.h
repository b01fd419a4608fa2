// One call runs the whole simulator: SimulationOptions -> Simulate() -> SimulationReport.
// Conventions: fss/fss.h.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "fss/core/image.h"
#include "fss/model/code.h"
#include "fss/model/kernel.h"
#include "fss/model/sensor.h"
#include "fss/pipeline/geometry.h"
#include "fss/pipeline/memory_estimate.h"
#include "fss/pipeline/prediction.h"
#include "fss/pipeline/simulation_options.h"

namespace fss {

struct Metrics {
  double rmse = 0.0;
  double psnr = 0.0;
  double rmse_ci = 0.0;
  double psnr_ci = 0.0;
  // SSIM over the RMSE window less 5 rows and columns at each side (docs/method.md §5); empty
  // when no pixel is left.
  std::optional<double> ssim;
};

struct TrialStatistics {
  int n = 0;
  double rmse_mean = 0.0;
  double rmse_sd = 0.0;  // sample standard deviation, 0 for one trial
  double rmse_ci_mean = 0.0;
  double rmse_ci_sd = 0.0;
  std::optional<double> ssim_mean;  // empty when Metrics::ssim is
  std::optional<double> ssim_sd;
  // Under a velocity distribution: the mean and sample deviation of the trials' MSE (RMSE^2), to
  // compare with Prediction::mse; empty otherwise.
  std::optional<double> mse_mean;
  std::optional<double> mse_sd;
};

// The restoration a run applied (docs/method.md §12).
struct RestorationSummary {
  RestorationOptions options;  // as asked
  // Tikhonov: the lambda applied (the one minimising the exact expected error when asked for
  // "optimal").
  std::optional<double> regularization;
  // Wiener: the prior's level c in gray levels^2 per radian/pixel (power-law: estimated from the
  // calibration observation) and the per-pixel noise variance the filter assumed (oracle: the
  // model's exact mean over the observed crop; power-law: estimated).
  std::optional<double> prior_level;
  std::optional<double> noise_variance;
};

struct SimulationReport {
  SimulationOptions options;
  std::string code_name;
  std::vector<double> gains;
  int width = 0;
  int height = 0;
  int channels = 0;

  Geometry geometry;
  int rmse_first = 0;  // RMSE window [rmse_first, rmse_end) of the output
  int rmse_end = 0;
  int rmse_ci_first = 0;  // RMSE_CI window
  int rmse_ci_end = 0;

  // The kernel that is inverted: the code at the restore velocity (the true
  // velocity unless options.restore_velocity_px_per_slot is set). Under a velocity
  // distribution, the first trial's, like zero_bins, metrics and the images.
  KernelAnalysis kernel;
  double observed_divisor = 1.0;  // K(0), or dt max |alpha| when K(0) vanishes
  int zero_bins = 0;              // deconvolution bins where K vanishes, left at 0
  RestorationSummary restoration;

  Metrics metrics;         // of the first trial
  TrialStatistics trials;  // over all trials
  // Each trial's metrics, trial t (seed + t) at index t; without noise every
  // trial is the one noise-free run.
  std::vector<Metrics> trial_metrics;
  // Under a velocity distribution: each trial's velocity, trial t at index t; empty otherwise.
  std::vector<double> trial_velocities;
  Prediction prediction;
  std::vector<std::string> warnings;

  // Wo x H outputs of the first trial, on the 0..255 scale (not rounded), aligned with input
  // columns [output_first_column(), + Wo); the ground truth and the residual are not kept
  // (groundtruth_image, residual_image).
  Image observed;  // divided by observed_divisor; empty (0 x 0) when Simulate had a sink
  Image restored;

  int output_first_column() const { return 3 * geometry.half_blur; }

  // Human-readable summary of everything above but the images.
  std::string FullReport() const;
};

class PlanCore;  // the plan's filters and weights (internal)

// The part of a run that depends only on the code, the mode, the velocities, dt, the image width
// and the RMSE margin, not on the image's rows, snr, seed, trials or threads: geometry, kernel
// analysis and warnings, filters and the prediction's M and W(j) (docs/method.md §6b). Built once
// and given to each Simulate call of one code for several snrs, seeds or images of one width, it
// gives the same bytes as a plan per call.
class SimulationPlan {
 public:
  // Throws the usage fss::Error Simulate would for these options and code on
  // an image `width` pixels wide (invalid options, a code the mode cannot
  // use, an image too narrow).
  SimulationPlan(const SimulationOptions& options, int width, const ShutterCode& code);

  // True when a run of `options` with `code` on an image `width` wide can use
  // this plan: same code (name and gains), mode, velocities, dt, width and
  // margin, and W(j) at hand when the run has noise.
  bool fits(const SimulationOptions& options, int width, const ShutterCode& code) const;

  const Geometry& geometry() const;
  // The kernel at the restore velocity, as SimulationReport::kernel (under a velocity
  // distribution, at the restore velocity or 1: each trial has its own).
  const KernelAnalysis& kernel() const;
  const std::vector<std::string>& warnings() const;
  // Memory the plan holds, in bytes (filters, inverse filter, weights).
  std::size_t bytes() const;

  const PlanCore& core() const { return *core_; }

 private:
  std::shared_ptr<const PlanCore> core_;
};

// Runs the simulation of `code` on `input`. Throws a usage fss::Error for a combination that
// cannot run (invalid options, analog gains outside [0, 1], an all-zero code, an image too narrow
// for the RMSE window), a kLimit one over options.max_memory_bytes. With an `observed_sink`, the
// first trial's observed rows go to it and SimulationReport::observed stays empty.
SimulationReport Simulate(const SimulationOptions& options, const Image& input,
                          const ShutterCode& code, ObservedRowSink* observed_sink = nullptr);

// The same run with the kernel part of `plan`, which must fit these options, code and image width
// (SimulationPlan::fits; a usage fss::Error otherwise): the same report, byte for byte.
SimulationReport Simulate(const SimulationPlan& plan, const SimulationOptions& options,
                          const Image& input, const ShutterCode& code,
                          ObservedRowSink* observed_sink = nullptr);

// The velocity of the report's images: options.velocity_px_per_slot, or under a velocity
// distribution the first trial's, trial_velocity(distribution, seed, 0)
// (SimulationReport::trial_velocities[0]). The outputs that show one velocity (the spectrum)
// show this one.
double first_trial_velocity(const SimulationOptions& options);

// The ground truth aligned with report.restored: input columns
// [output_first_column(), output_first_column() + Wo).
Image groundtruth_image(const Image& input, const SimulationReport& report);

// groundtruth - restored, stretched affinely to [0, 255] (metrics.h).
Image residual_image(const Image& input, const SimulationReport& report);

}  // namespace fss

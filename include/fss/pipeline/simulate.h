// One call runs the whole simulator: SimulationOptions -> Simulate() ->
// SimulationReport. Conventions: image.h.
#pragma once

#include <cstdint>
#include <functional>
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
#include "fss/pipeline/observe.h"
#include "fss/pipeline/option_rules.h"
#include "fss/pipeline/prediction.h"
#include "fss/pipeline/restore.h"

namespace fss {

// Photon noise (docs/method.md §3): kPoisson draws every frame (the paper's
// sampler), kNone observes the expectation, kAggregated (numerical mode only,
// §6c) draws each pixel's normal-branch frames as one normal of the same
// mean and variance.
enum class NoiseModel { kPoisson, kNone, kAggregated };
std::string to_string(NoiseModel noise);
std::optional<NoiseModel> noise_model_from_string(std::string_view text);

// Receives the observed rows of the first trial as Simulate computes them,
// for a caller that stores them in its own form (fssim encodes them to 8 bits:
// ObservedPng8, io/outputs.h) instead of a Wo x H x C image of doubles.
// consume_row is called once per row, with the Wo values
// SimulationReport::observed would hold, from the worker threads (the
// calling thread when there is one), concurrently for different rows.
class ObservedRowSink {
 public:
  virtual ~ObservedRowSink() = default;
  virtual void consume_row(int channel, int row, std::span<const double> values) = 0;
};

struct SimulationOptions {
  ShutterMode mode = ShutterMode::kNumerical;
  double velocity_px_per_slot = 1.0;  // any real; the sign is the direction along rows
  // Velocity assumed by the restoration, to measure the cost of a wrong
  // velocity estimate; empty means the true velocity. The blur length B
  // covers both velocities, so a restore velocity equal to the true one is
  // exactly a normal run.
  std::optional<double> restore_velocity_px_per_slot;
  double dt = 1.0;     // time slot length, in [kMinScale, kMaxScale]
  double snr = 100.0;  // in [kMinScale, kMaxScale]
  std::uint64_t seed = 0;
  NoiseModel noise = NoiseModel::kPoisson;
  // Read noise, dark current, full well and ADC (docs/method.md §10); all off
  // by default: the paper's photon noise, every output bit unchanged.
  SensorModel sensor;
  // Columns left out at each side of the output for the RMSE; -1 means 3 B.
  int rmse_margin_columns = -1;
  // Independent noise realizations, seeds seed, seed + 1, ...; images and the
  // headline metrics are those of the first.
  int trials = 1;
  int threads = 0;  // 0: all hardware threads; never changes the results
  // Refuse, before allocating, a run whose estimated peak memory
  // (estimate_working_memory_bytes) exceeds this; 0 means no limit.
  std::size_t max_memory_bytes = 0;
  // Called after each trial with (done, total); may be empty. Not kept in
  // the report.
  std::function<void(int, int)> trial_callback;

  // False, with a message naming the field, its value and the rule
  // (option_rules.h), when an option is out of range on its own (image and
  // code checks are in Simulate).
  bool IsValid(std::string* error) const;
};

struct Metrics {
  double rmse = 0.0;
  double psnr = 0.0;
  double rmse_ci = 0.0;
  double psnr_ci = 0.0;
};

struct TrialStatistics {
  int n = 0;
  double rmse_mean = 0.0;
  double rmse_sd = 0.0;  // sample standard deviation, 0 for one trial
  double rmse_ci_mean = 0.0;
  double rmse_ci_sd = 0.0;
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
  // velocity unless options.restore_velocity_px_per_slot is set).
  KernelAnalysis kernel;
  double observed_divisor = 1.0;  // K(0), or dt max |alpha| when K(0) vanishes
  int zero_bins = 0;              // deconvolution bins where K vanishes, left at 0

  Metrics metrics;         // of the first trial
  TrialStatistics trials;  // over all trials
  // Each trial's metrics, trial t (seed + t) at index t; without noise every
  // trial is the one noise-free run.
  std::vector<Metrics> trial_metrics;
  Prediction prediction;
  std::vector<std::string> warnings;

  // Wo x H outputs of the first trial, on the 0..255 scale (not rounded),
  // aligned with input columns [output_first_column(), + Wo). The ground
  // truth and the residual display are derived from the input on demand
  // (groundtruth_image, residual_image) rather than kept: for a large image
  // each of them would be as big as the input.
  Image observed;  // divided by observed_divisor; empty (0 x 0) when Simulate had a sink
  Image restored;

  int output_first_column() const { return 3 * geometry.half_blur; }

  // Human-readable summary of everything above but the images.
  std::string FullReport() const;
};

// The part of a run that depends only on the code, the mode, the velocity,
// the restore velocity, dt, the image width and the RMSE margin, not on the
// image's rows, snr, seed, trials or threads: the geometry and metric
// windows, the kernel analysis and its warnings, the observation filters,
// the inverse filter, and the prediction's M and W(j) (docs/method.md §6,
// §6b). Simulate builds one per call unless given one; a caller that runs
// one code at one velocity for several snr values, seeds or images of one
// width (a campaign) builds it once and gives it to each call: the results
// are the same bytes.
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

  const Geometry& geometry() const { return geometry_; }
  const MetricWindows& windows() const { return windows_; }
  // The kernel at the restore velocity, as SimulationReport::kernel.
  const KernelAnalysis& kernel() const { return kernel_; }
  double observed_divisor() const { return observed_divisor_; }
  const std::vector<std::string>& warnings() const { return warnings_; }
  // The observer (at the snr of the options it was made with; the
  // pipeline takes the run's snr) and the restorer of the row pipeline.
  const RowObserver& observer() const { return observer_; }
  const RowRestorer& restorer() const { return restorer_; }
  // M (infinite when not invertible) and W(j) (empty without noise or when
  // not invertible), for predict.
  double m_amplification() const { return m_amplification_; }
  const std::vector<double>& noise_weights() const { return noise_weights_; }
  // Memory the plan holds, in bytes (filters, inverse filter, weights).
  std::size_t bytes() const;

 private:
  std::string code_name_;
  std::vector<double> gains_;
  ShutterMode mode_;
  double velocity_;
  double restore_velocity_;
  double dt_;
  int margin_;
  bool noisy_;
  Geometry geometry_;
  MetricWindows windows_;
  KernelAnalysis kernel_;
  double observed_divisor_ = 1.0;
  std::vector<std::string> warnings_;
  RowObserver observer_;
  RowRestorer restorer_;
  double m_amplification_ = 0.0;
  std::vector<double> noise_weights_;
};

// Throws the usage fss::Error Simulate would for a code the mode cannot use:
// no gains, more than kMaxCodeLength, only zero gains, a largest |gain|
// outside [1e-100, 1e100] (scale_rule: sums and |K| must stay finite), or
// (analog) a gain outside [0, 1]. The one check of a code: simulate, sweep,
// campaign, code analyze and the plots (spectra) apply it.
void check_code_for_mode(const ShutterCode& code, ShutterMode mode);

// Runs the simulation of `code` on `input`. Throws a usage fss::Error for a
// combination that cannot run (invalid options, analog gains outside [0, 1],
// an all-zero code, an image too narrow for the RMSE window). With an
// `observed_sink`, the first trial's observed rows go to it and
// SimulationReport::observed stays empty, saving a Wo x H x C image of
// doubles.
SimulationReport Simulate(const SimulationOptions& options, const Image& input,
                          const ShutterCode& code, ObservedRowSink* observed_sink = nullptr);

// The same run with the kernel part of `plan`, built for these options,
// code and image width (SimulationPlan::fits; a usage fss::Error
// otherwise): the same report, byte for byte.
SimulationReport Simulate(const SimulationPlan& plan, const SimulationOptions& options,
                          const Image& input, const ShutterCode& code,
                          ObservedRowSink* observed_sink = nullptr);

// Memory of the process before any image: code, libraries (PLplot, cairo,
// Fontconfig), stacks. fssim on a 600 x 8 image peaks at 22.4 MiB with its
// plots (10.9 MiB without); counted in estimate_working_memory_bytes.
inline constexpr std::size_t kBaselineMemoryBytes = std::size_t{32} << 20;

// Estimated peak memory of Simulate plus write_outputs, in bytes, the input
// image and kBaselineMemoryBytes included: the input, the observed (as doubles, or as 8-bit samples
// when its rows go to an `observed_sink`, as Simulate's) and restored outputs (one more restoration
// buffer when trials > 1), and the larger of the RMSE_CI scratch (16 or 20 bytes a pixel of one
// channel's window and the sorter's buffers, metrics.h) and the PNG encoding buffers. Rows in
// flight are a few kilobytes a thread and are not counted, nor are the exact prediction's
// variance sums (at most 64 rows of W - B doubles, docs/method.md §6b). Outputs beyond the
// default ones add `extra_encoding_bytes_per_sample` bytes a sample of the output crop to the
// encoding buffers (outputs.h: output_encoding_bytes_per_sample).
std::size_t estimate_working_memory_bytes(int width, int height, int channels,
                                          const Geometry& geometry, int trials,
                                          const ObservedRowSink* observed_sink = nullptr,
                                          std::size_t extra_encoding_bytes_per_sample = 0);

// The same for a run of `options` (its trials) with a code of `code_length`
// gains, its noise model's memory included: aggregated noise with trials > 1
// keeps each row's recorded plan (M, V and its Knuth-branch pixels) for the
// later trials. The estimate Simulate checks options.max_memory_bytes against.
std::size_t estimate_working_memory_bytes(int width, int height, int channels,
                                          const Geometry& geometry,
                                          const SimulationOptions& options, int code_length,
                                          const ObservedRowSink* observed_sink = nullptr,
                                          std::size_t extra_encoding_bytes_per_sample = 0);

// The ground truth aligned with report.restored: input columns
// [output_first_column(), output_first_column() + Wo).
Image groundtruth_image(const Image& input, const SimulationReport& report);

// groundtruth - restored, stretched affinely to [0, 255] (metrics.h).
Image residual_image(const Image& input, const SimulationReport& report);

}  // namespace fss

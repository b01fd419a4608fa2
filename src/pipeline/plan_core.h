// The part of a run that does not depend on the image's rows, snr, seed,
// trials or threads (SimulationPlan, simulate.h, is its handle): the
// geometry and metric windows, the kernel analysis and its warnings, the
// observation filters, the inverse filter, and the prediction's M and W(j)
// (docs/method.md §6, §6b).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "fss/model/code.h"
#include "fss/model/kernel.h"
#include "fss/pipeline/geometry.h"
#include "fss/pipeline/simulate.h"
#include "fss/pipeline/simulation_options.h"
#include "pipeline/observe.h"
#include "pipeline/restore.h"

namespace fss {

class PlanCore {
 public:
  // Throws the usage fss::Error Simulate would (run_checks.h). Under a velocity distribution
  // (docs/method.md §13) the plan holds the geometry (that of the support's largest |v|), the
  // windows, the observed divisor and its warning, but no observer or restorer: each trial and
  // each velocity of the prediction has its own (the constructor below).
  PlanCore(const SimulationOptions& options, int width, const ShutterCode& code);
  // The kernel part of one velocity of a run under a velocity distribution: `options` at that
  // velocity (velocity_px_per_slot and the restore velocity; no distribution), on the run's
  // `geometry` instead of its own. A trial's analyses its kernel (kernel(), warnings()) and holds
  // the restorer only; a prediction's holds M and W(j) too but no kernel analysis (kernel() is
  // empty and taken as invertible: the caller checked the support, docs/method.md §13). The
  // options and the code are not checked again (the run's were).
  enum class VelocityPart { kTrial, kPrediction };
  PlanCore(const SimulationOptions& options, const Geometry& geometry, const ShutterCode& code,
           VelocityPart part);

  bool fits(const SimulationOptions& options, int width, const ShutterCode& code) const;

  const Geometry& geometry() const { return geometry_; }
  const MetricWindows& windows() const { return windows_; }
  const KernelAnalysis& kernel() const { return kernel_; }
  double observed_divisor() const { return observed_divisor_; }
  const std::vector<std::string>& warnings() const { return warnings_; }
  // The observer (at the snr of the options it was made with; the
  // pipeline takes the run's snr) and the restorer of the row pipeline: null
  // when the restoration depends on the image (fitted_restoration.h).
  // Not under a velocity distribution (the first constructor).
  const RowObserver& observer() const { return *observer_; }
  const RowRestorer* restorer() const { return restorer_ ? &*restorer_ : nullptr; }
  // With a restorer: M (mean |H|^2; infinite for the inverse filter of a code
  // that is not invertible) and W(j) (empty without noise or when M is
  // infinite), for predict; without prediction parts, M is 0 and W(j) empty.
  double m_amplification() const { return m_amplification_; }
  const std::vector<double>& noise_weights() const { return noise_weights_; }
  // The restoration's summary as far as the plan knows it (the lambda of a
  // fixed Tikhonov filter).
  const RestorationSummary& restoration() const { return restoration_; }
  std::size_t bytes() const;

 private:
  PlanCore(const SimulationOptions& options, const Geometry& geometry, const ShutterCode& code);
  void analyze(const ShutterCode& code);
  void set_observed_divisor(const ShutterCode& code);
  void plan_filter(const ShutterCode& code, bool prediction_parts);

  std::string code_name_;
  std::vector<double> gains_;
  ShutterMode mode_;
  double velocity_;
  double restore_velocity_;
  double dt_;
  int margin_;
  bool noisy_;
  RestorationOptions restoration_options_;
  std::optional<VelocityDistribution> distribution_;
  Geometry geometry_;
  MetricWindows windows_;
  KernelAnalysis kernel_;
  double observed_divisor_ = 1.0;
  std::vector<std::string> warnings_;
  std::optional<RowObserver> observer_;
  std::optional<RowRestorer> restorer_;
  RestorationSummary restoration_;
  double m_amplification_ = 0.0;
  std::vector<double> noise_weights_;
};

}  // namespace fss

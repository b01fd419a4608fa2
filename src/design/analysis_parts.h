// The pieces of analyze_code (design/analyze.h) that its form under a velocity distribution
// (velocity_analysis.cpp) shares, so that both compute a velocity's figures with the same
// operations; not part of the public interface.
#pragma once

#include <span>
#include <vector>

#include "design/numerics.h"
#include "fss/design/analyze.h"

namespace fss::design_detail {

// Usage errors for a non-finite velocity, dt <= 0, snr <= 0 or a grid outside
// [0, kMaxAnalysisGridPoints] (the code itself is checked by check_code_for_mode).
void check_analysis_setting(double velocity, double dt, double snr, int grid);

// The setting checks analyze_code makes besides the velocity: the code for the mode, dt, snr,
// grid, the sensor, the restoration, and a DFT grid only with the inverse filter.
void check_analysis_inputs(const ShutterCode& code, double velocity, double dt, double snr,
                           ShutterMode mode, int grid, const SensorModel& sensor,
                           const RestorationOptions& restoration);

// M of `gains` at `velocity` on the grid of `a` (its dt and grid: midpoint rule or DFT grid).
double mean_inverse_on_grid(std::span<const double> gains, double velocity, const CodeAnalysis& a);

// The sums of `g` and the kernel's figures at a->velocity.
void describe_gains(const std::vector<double>& g, CodeAnalysis* a);

// Q_eff of `gains` (docs/method.md §10): V snr^2 / 10^4, V the variance of the level-100
// observation; the photon noise's Q itself for a default sensor.
double effective_noise_gain(std::span<const double> gains, double dt, ShutterMode mode, double snr,
                            const SensorModel& sensor);

// The sensor's figures of `a` (its gains `g`): readouts, v_r, Q_eff and Q_eff a->m.
void describe_sensor(std::span<const double> g, CodeAnalysis* a);

// E = (100 / s)^2 of an SNR at level 100 s; infinite for s = 0.
inline double error_of_level100_snr(double s) {
  return s > 0.0 ? (100.0 / s) * (100.0 / s) : kInfinity;
}

// An analysis of `code` with its setting filled in and every figure at its default.
inline CodeAnalysis analysis_of_setting(const ShutterCode& code, double velocity, double dt,
                                        double snr, ShutterMode mode, int grid,
                                        const SensorModel& sensor,
                                        const RestorationOptions& restoration) {
  CodeAnalysis a;
  a.length = static_cast<int>(code.gains.size());
  a.mode = mode;
  a.velocity = velocity;
  a.dt = dt;
  a.snr = snr;
  a.grid = grid;
  a.sensor = sensor;
  a.restoration = restoration;
  return a;
}

// A usage error naming the code and the setting when a figure of `a` left double precision.
void check_analysis_finite(const ShutterCode& code, const CodeAnalysis& a);

}  // namespace fss::design_detail

#include "pipeline/observe.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/scaled_math.h"
#include "core/vectorize.h"
#include "fss/core/error.h"
#include "fss/model/transfer.h"

namespace fss {

RowObserver::RowObserver(int width, std::span<const double> gains, ShutterMode mode,
                         const ObservationParams& params)
    : width_(width),
      gains_(gains.begin(), gains.end()),
      mode_(mode),
      snr_(params.snr),
      fft_(RowFFT::for_size(width)),
      aggregate_(params.aggregate_noise && mode == ShutterMode::kNumerical),
      groups_(gain_groups(gains)) {
  fft_.prepare();  // both directions are used for every row
  set_noise(params);
  auto filters = std::make_shared<std::vector<std::vector<Complex>>>();
  if (mode == ShutterMode::kAnalog) {
    for (std::size_t k = 0; k < gains_.size(); ++k) {
      if (!(gains_[k] >= 0.0 && gains_[k] <= 1.0)) {
        throw_usage_error("analog mode needs gains in [0, 1], but gain " + std::to_string(k) +
                          " is " + std::to_string(gains_[k]));
      }
    }
    filters->push_back(transfer_function_bins(gains_, params.velocity, params.dt, width));
    filters_ = std::move(filters);
    return;
  }
  const double s = params.velocity * params.dt;
  shift_ = std::nearbyint(s) == s && std::abs(s) < 1e9;
  if (shift_) {
    step_ = static_cast<long long>(s);
    filters->push_back(slot_transfer_function_bins(0, params.velocity, params.dt, width));
  } else {
    for (std::size_t k = 0; k < gains_.size(); ++k) {
      filters->push_back(gains_[k] == 0.0
                             ? std::vector<Complex>()
                             : slot_transfer_function_bins(static_cast<int>(k), params.velocity,
                                                           params.dt, width));
    }
  }
  filters_ = std::move(filters);
}

RowObserver RowObserver::with_noise(const ObservationParams& params) const {
  RowObserver copy = *this;
  copy.snr_ = params.snr;
  copy.aggregate_ = params.aggregate_noise && mode_ == ShutterMode::kNumerical;
  copy.set_noise(params);
  return copy;
}

void RowObserver::set_noise(const ObservationParams& params) {
  sensor_ = params.sensor.enabled();
  sensor_linear_ = params.sensor.linear();
  // One readout: a frame of dt (numerical) or the whole exposure L dt (analog).
  const double exposure = readout_exposure_slots(gains_.size(), params.dt, mode_);
  readout_ = sensor_readout(params.sensor, exposure);
  readout_variance_ = readout_variance_electrons2(params.sensor, exposure);
  frame_readout_ = readout_;
  sum_read_noise_ = mode_ == ShutterMode::kNumerical && sensor_linear_ &&
                    params.sensor.read_noise_electrons != 0.0;
  summed_read_sd_ = 0.0;
  if (sum_read_noise_) {
    double sum_squares = 0.0;
    for (const double alpha : gains_) sum_squares += alpha * alpha;
    summed_read_sd_ = params.sensor.read_noise_electrons * std::sqrt(sum_squares);
    frame_readout_.read_noise_electrons = 0.0;
  }
  clipping_first_ = std::clamp(params.clipping_first_column, 0, width_);
  clipping_end_ = params.clipping_end_column < 0
                      ? width_
                      : std::clamp(params.clipping_end_column, clipping_first_, width_);
}

RowObserver::Scratch::Scratch(const RowObserver& observer)
    : workspace(observer.width_),
      spectrum(static_cast<std::size_t>(observer.width_ / 2 + 1)),
      sampler(observer.snr_),
      aggregated(observer.snr_, observer.gains_) {}

void RowObserver::load_row(const double* row, Scratch& scratch) const {
  std::copy(row, row + width_, scratch.workspace.real().begin());
  fft_.forward(scratch.workspace);
  std::copy(scratch.workspace.spectrum().begin(), scratch.workspace.spectrum().end(),
            scratch.spectrum.begin());
}

void RowObserver::load_spectrum(const Complex* bins, Scratch& scratch) const {
  std::copy(bins, bins + width_ / 2 + 1, scratch.spectrum.begin());
}

std::span<const double> RowObserver::filtered(const std::vector<Complex>& filter,
                                              Scratch& scratch) const {
  std::copy(scratch.spectrum.begin(), scratch.spectrum.end(), scratch.workspace.spectrum().begin());
  fft_.inverse_filtered(scratch.workspace, filter);
  return scratch.workspace.real();
}

namespace {

// Var(o) of the noise-free pass, sum_k alpha_k^2 V(e_k) with V(e) =
// Var(PoissonSNR(e)) (poisson_snr_variance, docs/method.md §6b), into a row
// the caller gives; every call does nothing without an expectation or for an
// empty row. A slot drawn exactly (a grouped frame of the aggregated noise,
// docs/method.md §6c) has V(e) = max(e, 0) / lambda2, no rounding term.
// With integer v dt (shifts), V(e_0) is computed once and slot k adds it
// shifted like its exposure; otherwise each slot adds V of its own exposure.
//
// A sensor (docs/method.md §10) adds `readout_variance` electrons^2 per
// readout, and its dark charge d moves the branch test to lambda + d >= 50;
// both are 0 without one (x + 0 is x: the same bits).
class VarianceRow {
 public:
  VarianceRow(bool no_expectation, double snr, std::span<double> variance,
              std::vector<double>& unit, std::vector<double>& exact_unit, double dark_electrons,
              double readout_variance)
      : active_(!no_expectation && !variance.empty()),
        lambda2_(active_ ? PoissonSNR(snr).lambda2() : 0.0),
        dark_(dark_electrons),
        readout_(active_ ? detail::divide_by_square(readout_variance, lambda2_) : 0.0),
        variance_(variance),
        unit_(unit),
        exact_unit_(exact_unit) {
    if (active_) std::fill(variance_.begin(), variance_.end(), 0.0);
  }

  // From now on the exact slots (grouped frames of the aggregated noise) add nothing: their
  // variance, summed over a group's frames, is alpha_g^2 Lambda_g / lambda2^2 from the intensity
  // the aggregated sampler sums while it draws them (no sensor), added by add_groups().
  void take_groups_from_sampler() { groups_from_sampler_ = active_; }
  // variance += alpha_g^2 Lambda_g / lambda2^2 for each group drawn since the sampler's last
  // finish(), when take_groups_from_sampler() was called.
  void add_groups(AggregatedRowSampler& sampler) {
    if (groups_from_sampler_) sampler.add_group_variances(variance_, 1.0 / (lambda2_ * lambda2_));
  }

  // Slot k's exposure e_k (or the analog exposure, weight 1), `exact` when
  // drawn without rounding. With shifts (shift.e0 not empty), unit = V(e_0)
  // is computed at the first slot of its kind and each slot adds it shifted
  // by its offset.
  void add_slot(std::span<const double> e, std::span<const double> e0, std::size_t offset,
                double weight, bool exact = false) {
    if (!active_ || (exact && groups_from_sampler_)) return;
    if (e0.empty()) {
      add(e, weight, variance_, exact);
      return;
    }
    bool& ready = exact ? exact_unit_ready_ : unit_ready_;
    std::vector<double>& unit = exact ? exact_unit_ : unit_;
    if (!ready) {
      unit.assign(e0.size(), 0.0);
      add(e0, 1.0, unit, exact);
      ready = true;
    }
    add_shifted(unit, offset, weight);
  }

 private:
  // variance[x] += weight * unit[(x - offset) mod W], offset in [0, W).
  void add_shifted(const std::vector<double>& unit, std::size_t offset, double weight) {
    detail::run_vectorized([&]() __attribute__((always_inline)) {
      const std::size_t n = unit.size();
      const std::size_t o = offset;
      const double w = weight;
      const double* __restrict from = unit.data();
      double* __restrict sum = variance_.data();
      for (std::size_t x = 0; x < o; ++x) sum[x] += w * from[x + n - o];
      for (std::size_t x = o; x < n; ++x) sum[x] += w * from[x - o];
    });
  }

  // into[x] += weight * V(e[x]): poisson_snr_variance's formula and branch
  // test, inline so that the loop vectorizes, and with a product by 1 / lambda2
  // instead of its division (equal within an ulp; a division per slot and
  // pixel would cost about as much as the slot's exposure). With a sensor:
  //   V = max(e, 0) / lambda2 + (lambda + d >= 50 ? 1 / (12 lambda2^2) : 0)
  //       + v_r / lambda2^2,
  // without the rounding term when `exact`.
  void add(std::span<const double> e, double weight, std::span<double> into, bool exact) const {
    detail::run_vectorized([&]() __attribute__((always_inline)) {
      const double lambda2 = lambda2_;
      const double inverse = 1.0 / lambda2;
      const double rounding = exact ? 0.0 : 1.0 / (12.0 * lambda2 * lambda2);
      const double dark = dark_;
      const double readout = readout_;
      const double w = weight;
      const std::size_t n = e.size();
      const double* __restrict exposure = e.data();
      double* __restrict sum = into.data();
      for (std::size_t x = 0; x < n; ++x) {
        const double signal = std::max(exposure[x], 0.0);
        sum[x] += w * (signal * inverse +
                       (signal * lambda2 + dark >= kKnuthLimit ? rounding : 0.0) + readout);
      }
    });
  }

  bool active_;
  bool unit_ready_ = false;
  bool exact_unit_ready_ = false;
  bool groups_from_sampler_ = false;
  double lambda2_;
  double dark_;
  double readout_;  // v_r / lambda2^2 (0 without a sensor, also where lambda2^2 underflows)
  std::span<double> variance_;
  std::vector<double>& unit_;
  std::vector<double>& exact_unit_;  // V(e_0) without the rounding term
};

// The expectation of one readout of a sensor with a full well or an ADC, the
// mean charge clipped: (min(max(e, 0) lambda2 + d, clip) - d) / lambda2;
// `clipping` counts the clipped readouts of columns [first, end).
void add_clipped_expectation(std::span<const double> e, double alpha, double lambda2,
                             const SensorReadout& readout, int first, int end,
                             std::span<double> out, ReadoutClipping& clipping) {
  const double clip = readout.clip_electrons();
  const double sigma2 = readout.read_noise_electrons * readout.read_noise_electrons;
  for (std::size_t x = 0; x < e.size(); ++x) {
    const double charge = std::max(e[x], 0.0) * lambda2 + readout.dark_electrons;
    out[x] += alpha * (std::min(charge, clip) - readout.dark_electrons) / lambda2;
    const auto column = static_cast<int>(x);
    if (column < first || column >= end) continue;
    if (readout.saturates(charge)) ++clipping.saturated;
    if (readout.adc() && charge < 3.0 * std::sqrt(charge + sigma2)) ++clipping.near_zero;
  }
}

}  // namespace

ReadoutClipping RowObserver::observe(bool noisy, std::uint64_t seed, int channel, int row,
                                     Scratch& scratch, std::span<double> out,
                                     std::span<double> variance) const {
  return noisy ? observe(seed, channel, row, scratch, Outputs{out, {}, {}})
               : observe(seed, channel, row, scratch, Outputs{{}, out, variance});
}

ReadoutClipping RowObserver::observe(std::uint64_t seed, int channel, int row, Scratch& scratch,
                                     const Outputs& outputs) const {
  const auto c = static_cast<std::uint64_t>(channel);
  const auto y = static_cast<std::uint64_t>(row);
  const std::span<double> noisy = outputs.noisy;
  const std::span<double> expected = outputs.expectation;
  std::fill(noisy.begin(), noisy.end(), 0.0);
  std::fill(expected.begin(), expected.end(), 0.0);
  scratch.intensities_ready = false;
  // the exact prediction's per-pixel variance
  VarianceRow var(expected.empty(), snr_, outputs.variance, scratch.unit_variance,
                  scratch.exact_unit_variance, readout_.dark_electrons, readout_variance_);
  // The grouped frames' variance from the sampler's sums when it draws them without a sensor.
  if (aggregate_ && !noisy.empty() && !sensor_) var.take_groups_from_sampler();
  ReadoutClipping clipping;
  const double lambda2 = scratch.aggregated.lambda2();
  if (mode_ == ShutterMode::kAnalog) {
    const std::span<const double> e = filtered((*filters_)[0], scratch);
    if (!noisy.empty()) {
      const RowNoiseId id{seed, c, 0, y};
      sensor_ ? scratch.sampler.accumulate_readout(e, id, 1.0, readout_, noisy)
              : scratch.sampler.accumulate(e, id, 1.0, noisy);  // o = PoissonSNR(e)
    }
    if (expected.empty()) return clipping;
    if (sensor_linear_) {
      for (int x = 0; x < width_; ++x) expected[x] = std::max(e[x], 0.0);  // E[o] = max(e, 0)
    } else {
      add_expectation(e, 1.0, lambda2, expected, clipping);
    }
    var.add_slot(e, {}, 0, 1.0);
    return clipping;
  }
  // o = sum_k alpha_k PoissonSNR(e_k), and its expectation sum_k alpha_k max(e_k, 0)
  for_each_slot(scratch, [&](std::size_t k, std::span<const double> e, const SlotShift& shift) {
    if (!noisy.empty()) add_noisy_slot(k, e, shift, seed, c, y, scratch, noisy);
    if (expected.empty()) return;
    add_expectation(e, gains_[k], lambda2, expected, clipping);
    // A grouped frame of the aggregated noise is drawn exactly (docs/method.md §6c).
    var.add_slot(e, shift.e0, shift.offset, gains_[k] * gains_[k],
                 aggregate_ && groups_[k] != kSingleFrame);
  });
  if (noisy.empty()) return clipping;
  var.add_groups(scratch.aggregated);
  // The aggregated normal-branch frames: one normal per pixel.
  if (aggregate_) scratch.aggregated.finish({seed, c, 0, y}, noisy);
  // The frames' read noise, summed: sigma_r sqrt(sum alpha_k^2) N / lambda2.
  if (!aggregate_ && sum_read_noise_) {
    scratch.sampler.add_read_noise({seed, c, 0, y}, summed_read_sd_ / lambda2, noisy);
  }
  return clipping;
}

namespace {
// v = v v: a row twice over, so that its circular shifts are windows of it.
void repeat_twice(std::vector<double>& v) {
  const std::size_t n = v.size();
  v.resize(2 * n);
  std::copy_n(v.begin(), n, v.begin() + static_cast<std::ptrdiff_t>(n));
}
}  // namespace

void RowObserver::add_noisy_slot(std::size_t k, std::span<const double> e, const SlotShift& shift,
                                 std::uint64_t seed, std::uint64_t channel, std::uint64_t row,
                                 Scratch& scratch, std::span<double> noisy) const {
  const double alpha = gains_[k];
  const RowNoiseId id{seed, channel, k, row};
  if (shift.e0.empty() || (sensor_ && !aggregate_)) {
    if (aggregate_) {
      scratch.aggregated.add_frame(e, id, alpha, noisy, sensor_ ? &readout_ : nullptr);
    } else if (sensor_) {
      scratch.sampler.accumulate_readout(e, id, alpha, frame_readout_, noisy);
    } else {
      scratch.sampler.accumulate(e, id, alpha, noisy);
    }
    return;
  }
  // Shifts: every slot's intensities are a window of e_0's, computed once a
  // row (e_k = doubled[W - offset + x]).
  const std::size_t w = shift.e0.size();
  const std::size_t first = w - shift.offset;
  const auto window = [&](const std::vector<double>& v) {
    return std::span<const double>(v).subspan(first, w);
  };
  if (aggregate_) {
    auto& rows = scratch.frame_intensities;
    if (!scratch.intensities_ready) {
      scratch.normal_pixels = scratch.aggregated.intensities_of(
          shift.e0, sensor_ ? readout_.dark_electrons : 0.0, rows);
      for (auto* v : {&rows.lambda, &rows.mean_part, &rows.variance_part}) repeat_twice(*v);
      scratch.intensities_ready = true;
    }
    scratch.aggregated.add_frame(
        AggregatedRowSampler::FrameIntensities{window(rows.lambda), window(rows.mean_part),
                                               window(rows.variance_part), scratch.normal_pixels},
        id, alpha, noisy, sensor_ ? &readout_ : nullptr);
    return;
  }
  if (!scratch.intensities_ready) {
    scratch.knuth_pixels =
        scratch.sampler.intensities_of(shift.e0, 0.0, scratch.lambda, scratch.root);
    repeat_twice(scratch.lambda);
    repeat_twice(scratch.root);
    scratch.intensities_ready = true;
  }
  scratch.sampler.accumulate(
      PoissonRowSampler::Intensities{window(scratch.lambda), window(scratch.root),
                                     scratch.knuth_pixels},
      id, alpha, noisy);
}

void RowObserver::add_expectation(std::span<const double> e, double alpha, double lambda2,
                                  std::span<double> out, ReadoutClipping& clipping) const {
  if (sensor_linear_) {
    detail::run_vectorized([&]() __attribute__((always_inline)) {
      const auto n = static_cast<std::size_t>(width_);
      const double a = alpha;
      const double* __restrict exposure = e.data();
      double* __restrict sum = out.data();
      for (std::size_t x = 0; x < n; ++x) sum[x] += a * std::max(exposure[x], 0.0);
    });
  } else {
    add_clipped_expectation(e, alpha, lambda2, readout_, clipping_first_, clipping_end_, out,
                            clipping);
  }
}

void RowObserver::record_plan(AggregatedRowPlan* plan, Scratch& scratch) const {
  scratch.aggregated.record_next_row(plan, static_cast<std::size_t>(width_));
}

void RowObserver::replay(const AggregatedRowPlan& plan, std::uint64_t seed, int channel, int row,
                         Scratch& scratch, std::span<double> out) const {
  std::fill(out.begin(), out.end(), 0.0);
  scratch.aggregated.replay(
      plan, {seed, static_cast<std::uint64_t>(channel), 0, static_cast<std::uint64_t>(row)}, out);
}

template <typename PerSlot>
void RowObserver::for_each_slot(Scratch& scratch, const PerSlot& per_slot) const {
  if (!shift_) {
    for (std::size_t k = 0; k < gains_.size(); ++k) {
      if (gains_[k] != 0.0) per_slot(k, filtered((*filters_)[k], scratch), SlotShift{});
    }
    return;
  }
  const std::span<const double> e0 = filtered((*filters_)[0], scratch);
  // e_k(x) = e_0((x - s k) mod W) = doubled[W - offset + x], doubled = e_0 e_0:
  // each slot's exposure is a window of one buffer, no copy per slot.
  const auto w = static_cast<std::size_t>(width_);
  scratch.doubled.assign(e0.begin(), e0.end());
  repeat_twice(scratch.doubled);
  const std::span<const double> first_period(scratch.doubled.data(), w);
  for (std::size_t k = 0; k < gains_.size(); ++k) {
    if (gains_[k] == 0.0) continue;
    long long offset = (step_ * static_cast<long long>(k)) % width_;
    if (offset < 0) offset += width_;
    const auto o = static_cast<std::size_t>(offset);
    per_slot(k, std::span<const double>(scratch.doubled.data() + (w - o), w),
             SlotShift{first_period, o});
  }
}

}  // namespace fss

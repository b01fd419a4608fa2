// The row pipeline of Simulate (docs/method.md §2-§4): each row of the input
// goes DFT -> observation (one noise realization, or its expectation) ->
// observed crop, mirror extension, inverse filter -> restored row, so that
// the working memory beyond the outputs is a few rows per thread. Rows are
// independent: the results do not depend on the thread count. Internal to
// the library.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "fss/core/image.h"
#include "fss/model/code.h"
#include "fss/pipeline/geometry.h"
#include "fss/pipeline/simulation_options.h"
#include "pipeline/noise_free_run.h"
#include "pipeline/observe.h"
#include "pipeline/restore.h"

namespace fss {

// The observation parameters of a run: its velocity, dt, snr, noise model and
// sensor, with the sensor's clipping checked over the observed crop
// [h, h + Wa), the readouts that reach the restoration.
ObservationParams observation_params(const SimulationOptions& options, const Geometry& geometry);

// An ObservedRowSink that stores the rows in a Wo x H x C image
// (SimulationReport::observed when the caller gives no sink).
class ImageRowSink : public ObservedRowSink {
 public:
  explicit ImageRowSink(Image& image) : image_(image) {}
  void consume_row(int channel, int row, std::span<const double> values) override;

 private:
  Image& image_;
};

class RowPipeline {
 public:
  // Observes `input` through `code` at the options' velocity, dt, snr and
  // mode, and restores with the kernel at the restore velocity (the true one
  // unless set). Observed rows are divided by `observed_divisor`.
  RowPipeline(const Image& input, const ShutterCode& code, const SimulationOptions& options,
              const Geometry& geometry, double observed_divisor);
  // The same with the observer and the restorer of a SimulationPlan: the
  // observer takes the options' snr and noise model.
  RowPipeline(const Image& input, const RowObserver& observer, const RowRestorer& restorer,
              const SimulationOptions& options, const Geometry& geometry, double observed_divisor);

  // An upper bound of the bytes of the rows' recorded plans of a run of
  // `options` on a width x height x channels image with a code of
  // `code_length` gains of which `groups` groups share a gain (gain_groups;
  // 0 when no plan is recorded): per row, M and V (16 bytes a pixel), the
  // Knuth-branch pixels (12 bytes each, at most a width of them), each
  // group's Lambda (8 bytes a pixel) and at most min(L, W) frames' records
  // with their allocations.
  static std::size_t plan_bytes(int width, int height, int channels,
                                const SimulationOptions& options, int code_length, int groups);

  // Frequencies of the deconvolution grid where K = 0, left at 0.
  int zero_bins() const { return restorer_.zero_bins(); }

  // Observes every row, with the noise of `noise_seed` or, when it is empty,
  // the expectation E[o], and restores it into `restored` (Wo x H x C). When
  // `observed` is not null, it receives each observed row: observation
  // columns [3h, 3h + Wo) divided by the observed divisor. False when an
  // observed value is not finite.
  // A noise-free run also counts its clipped readouts (ReadoutClipping,
  // observe.h) into `clipping` when it is not null.
  bool restore_all(std::optional<std::uint64_t> noise_seed, Image& restored,
                   ObservedRowSink* observed, ReadoutClipping* clipping = nullptr) const;

  // The first trial of a noisy run and its noise-free pass, in one pass over
  // the rows (each row loaded and its exposures computed once for both):
  // restores the noise of `noise_seed` into `restored` and sends the observed
  // rows to `observed` as restore_all() does, and returns the noise-free
  // pass: RMSE_0, the RMSE of the noise-free restoration over output columns
  // [first, end), and S(j), the sums over rows and channels of the
  // observation noise's variance at observed-crop column j (docs/method.md
  // §6b), computed as the rows stream by, without storing the noise-free
  // restoration. Each row's squared error (row_squared_error, metrics.h) is
  // kept and the rows are summed in order, so the bits are rmse()'s; S is
  // summed over fixed blocks of rows in row order, then over the blocks in
  // order: the same bits for any thread count. `observed_finite` is false
  // when an observed value is not finite.
  struct FirstTrial {
    NoiseFreeRun noise_free;
    bool observed_finite = true;
  };
  FirstTrial first_trial(std::uint64_t noise_seed, int first, int end, Image& restored,
                         ObservedRowSink* observed) const;

  // The noise-free pass alone, as first_trial() makes it (the same rows, blocks and order of
  // sums, so the same bits): RMSE_0 over output columns [first, end), S(j) when `variances`
  // (empty otherwise) and the clipped readouts, without a noisy observation or a restored
  // image (the prediction at one velocity of a distribution, docs/method.md §13).
  NoiseFreeRun noise_free_pass(int first, int end, bool variances) const;

 private:
  class Worker;

  // per_item(worker, i) for every i in [0, count), on the threads, each
  // thread with its own Worker taking the next unclaimed item: a thread
  // slowed by other work (the plots are drawn meanwhile) takes fewer items.
  // Items are independent, so results do not depend on who takes which.
  template <typename PerItem>
  void for_each_item(int count, const PerItem& per_item) const;

  // The rows of the noise-free pass in fixed blocks: per_row(worker, c, y, block sums,
  // block clipping) for each row, the rows of a block in order; then RMSE_0 from the rows'
  // squared errors, which per_row returns, and S(j) from the blocks' sums when `variances`.
  template <typename PerRow>
  NoiseFreeRun noise_free_blocks(int first, int end, bool variances, const PerRow& per_row) const;

  const Image& input_;
  Geometry geometry_;
  int threads_;
  double observed_divisor_;
  RowObserver observer_;
  RowRestorer restorer_;

  // Aggregated noise with trials > 1 on at most kMaxPlannedSamples samples
  // (W H C): each row's plan, recorded by the first trial and replayed by
  // the others, so that a later trial costs its variates, the restoration
  // and the metrics only. At most 28 + 8 G bytes a sample for a code of G
  // groups (M, V, a width's worth of Knuth-branch pixel frames, 12 bytes
  // each, and the groups' Lambda; a row with more is not recorded and is
  // drawn from its frames every trial).
  static constexpr std::size_t kMaxPlannedSamples = std::size_t{1} << 21;
  // Whether a run records the rows' plans: the rule of the constructor and
  // of plan_bytes.
  static bool records_plans(bool aggregates_noise, int trials, std::size_t samples) {
    return aggregates_noise && trials > 1 && samples <= kMaxPlannedSamples;
  }
  mutable std::vector<AggregatedRowPlan> plans_;  // one per row, written by that row's worker
};

}  // namespace fss

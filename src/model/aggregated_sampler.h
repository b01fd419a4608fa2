// The numerical mode's photon noise aggregated (docs/method.md §6c, `--noise
// aggregated`): frames with equal gains drawn as one exact Poisson variate of
// their summed intensity, the normal-branch frames of the others as one normal.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "fss/model/sensor.h"
#include "model/noise_stream.h"

namespace fss {

// Frames with equal gains (docs/method.md §6c): gain_groups(gains)[k] is
// frame k's group, the index of its gain among the nonzero gains that at
// least two frames share, numbered in the order of their first frames; or
// kSingleFrame for a zero gain or a gain no other frame has.
inline constexpr int kSingleFrame = -1;
std::vector<int> gain_groups(std::span<const double> gains);
// The number of groups of gain_groups(gains).
int gain_group_count(std::span<const double> gains);

// The numerical mode's observation of one row,
//   o[x] = sum_k alpha_k PoissonSNR(e_k[x]),
// aggregated (docs/method.md §6c). The frames of a group g (gain_groups,
// gain alpha_g) are exact: each pixel gets ONE variate
//   out[x] += alpha_g P_g[x] / lambda2,  P_g ~ Poisson(Lambda_g[x]),
//   Lambda_g = sum_{k in g} lambda_k,  lambda_k = max(e_k[x], 0) lambda2,
// a sum of independent Poissons being one Poisson (exact_poisson_variate,
// from the row's kGroupPoisson lane of frame coordinate g, in pixel order).
// The other frames (single frames: a gain no other frame has) are
// aggregated as before: for each pixel, the single frames with
// lambda_k >= 50 are replaced by ONE normal
//   A[x] = M[x] + sqrt(V[x]) N[x],   M = sum alpha_k lambda_k,
//                                    V = sum alpha_k^2 (lambda_k + 1/12),
// added as A[x] / lambda2, not rounded; the frames with lambda_k < 50 are
// drawn one by one by Knuth's method, as PoissonRowSampler does. One normal
// per pixel and row instead of one per pixel and frame. Each pixel's mean is
// the per-frame sampler's, and so is its variance but for the grouped
// frames, which have no rounding term (the prediction follows, observe.h);
// what differs beyond them is in docs/method.md §6c. The variates come from
// the kAggregate and kGroupPoisson lanes, so the aggregated and per-frame
// observations of one seed are independent draws.
// N comes from box_muller_portable: A is not rounded, so N's bits must not
// depend on the processor (docs/method.md §3).
//
// Use, per row: add_frame() for each frame with a nonzero gain, then
// finish(). Each single frame has its own Knuth stream, so the frames' order
// (or skipping a zero gain) changes no variate, only the rounding of the
// sums; the observer adds them in k order, as for the per-frame sampler. The
// single frames' Knuth-branch pixels go straight into `out`; their
// normal-branch ones are summed into two row-sized accumulators, M and V,
// and each group's intensities into Lambda_g; finish() draws the groups in
// g order, then the normal, and resets them for the next row: no frame's
// row is kept.
// Holds scratch buffers: one sampler per thread.
//
// Trials: everything but the variates is the same for every seed. A row's
// AggregatedRowPlan (M, V, the Knuth-branch frames' pixels and
// intensities, each group's Lambda_g), recorded while the row is drawn once,
// lets replay() draw the row again for any seed without its frames: the same
// bytes as add_frame() for each frame then finish().
struct AggregatedRowPlan {
  struct KnuthFrame {
    std::uint64_t frame = 0;
    double gain = 0.0;
    std::vector<std::uint32_t> pixels;  // in pixel order
    std::vector<double> lambdas;        // their intensities, lambda < 50
  };
  bool recorded = false;
  std::vector<double> mean;      // M; empty when no pixel had a normal-branch frame
  std::vector<double> variance;  // V
  std::vector<KnuthFrame> knuth;
  std::size_t knuth_pixels = 0;  // total over the frames
  struct Group {
    std::uint64_t group = 0;
    double gain = 0.0;
    std::vector<double> lambda;  // Lambda_g, one per pixel
  };
  std::vector<Group> groups;  // in g order
};

class AggregatedRowSampler {
 public:
  // `gains`: the code's, whose groups (gain_groups) are drawn exactly; none:
  // every frame is a single frame.
  explicit AggregatedRowSampler(double snr, std::span<const double> gains = {});
  double lambda2() const { return lambda2_; }
  // Frame id.frame of row (id.seed, id.channel, id.row): a grouped frame's
  // lambda added to its group's Lambda_g (gain is the group's); a single
  // frame's out[x] += gain * PoissonSNR(e[x]) where lambda < 50,
  // accumulated into M and V otherwise. e and out have the row's width, the same for every frame.
  // With a `readout` (a linear sensor: dark current and read noise only,
  // docs/method.md §10), aggregated exactly: each lambda gains the dark
  // charge (a sum of Poissons is one Poisson), and every pixel's
  // M -= alpha dark (the dark-frame correction) and V += alpha^2 sigma_r^2
  // (a sum of independent normals is one normal); the full well and the ADC
  // are not applied (Simulate refuses them with aggregated noise).
  void add_frame(std::span<const double> e, const RowNoiseId& id, double gain,
                 std::span<double> out, const SensorReadout* readout = nullptr);

  // A frame's intensities as add_frame() computes them from e first:
  // lambda[x] = max(e[x], 0) lambda2 + dark, its normal-branch parts
  // (lambda and lambda + 1/12 where lambda >= 50, 0 elsewhere) and the count
  // of normal-branch pixels. A row whose frames are circular shifts of one
  // exposure computes them once (intensities_of) and gives each frame a
  // window of them (the count is the same for every shift).
  struct FrameIntensities {
    std::span<const double> lambda;
    std::span<const double> mean_part;
    std::span<const double> variance_part;
    std::size_t normal_pixels = 0;
  };
  struct IntensityRows {
    std::vector<double> lambda;
    std::vector<double> mean_part;
    std::vector<double> variance_part;
  };
  // Fills `rows` (resized to e's size) for exposure e; returns the count.
  std::size_t intensities_of(std::span<const double> e, double dark, IntensityRows& rows) const;
  // The same as add_frame(e, ...) for the exposure whose intensities these are.
  // A grouped frame's frame.lambda is read when the row is drawn (finish() or
  // add_group_variances()), with the group's other frames: it must stay valid
  // and unchanged until then.
  void add_frame(const FrameIntensities& frame, const RowNoiseId& id, double gain,
                 std::span<double> out, const SensorReadout* readout = nullptr);
  // For each group g with frames since the last finish():
  //   variance[x] += alpha_g^2 Lambda_g[x] scale,
  // with scale = 1 / lambda2^2 the exact variance of the group's term of
  // the observation (no sensor: Lambda_g = lambda2 sum_k max(e_k, 0)).
  void add_group_variances(std::span<double> variance, double scale);
  // For each group g with frames, in g order: out[x] += alpha_g P_g[x] /
  // lambda2; then out[x] += (M[x] + sqrt(V[x]) N[x]) / lambda2 with N from
  // the row's kAggregateNormal lane (id.frame is ignored), then M = V = 0.
  // Draws no normal when no pixel had a normal-branch frame.
  void finish(const RowNoiseId& id, std::span<double> out);

  // Records the row's plan during the next add_frame() calls and finish()
  // into `plan` (which must outlive them); finish() marks it recorded unless
  // its Knuth-branch pixel frames exceeded `max_knuth_pixels`, or its arrays
  // (M and V, 12 bytes a Knuth-branch pixel, 8 bytes a pixel per group)
  // exceed 28 + 8 G bytes times `max_knuth_pixels` for the code's G groups
  // (RowPipeline::plan_bytes; then it is left empty and not recorded: that
  // row is drawn from its frames).
  void record_next_row(AggregatedRowPlan* plan, std::size_t max_knuth_pixels);
  // The row of a recorded plan with the noise of (id.seed, id.channel,
  // id.row): out[x] += what add_frame() for each of its frames, then
  // finish(), would add.
  void replay(const AggregatedRowPlan& plan, const RowNoiseId& id, std::span<double> out);

 private:
  // A linear sensor's frame of gain alpha: M -= alpha dark, V += alpha^2 sigma_r^2.
  void add_readout_terms(double gain, const SensorReadout& readout);
  // The frame's pixels on Knuth's branch (lambda < 50, `knuth_pixels` of
  // them): out += gain P / lambda2, recorded into the plan being recorded.
  void add_knuth_branch(std::span<const double> lambda, std::size_t knuth_pixels,
                        const RowNoiseId& id, double gain, std::span<double> out);
  // add_frame(frame, ...), `lasting` when frame.lambda stays valid and
  // unchanged until the row is drawn.
  void add_frame(const FrameIntensities& frame, const RowNoiseId& id, double gain,
                 std::span<double> out, const SensorReadout* readout, bool lasting);
  // Group g's frame: Lambda_g += lambda, now, or when the row is drawn if the
  // frame's lambda is `lasting`.
  void add_group_frame(int group, std::span<const double> lambda, bool lasting);
  // Adds group g's pending frames to Lambda_g, in their order.
  void sum_pending_frames(std::size_t g);
  // out += alpha_g P_g / lambda2 for each group with frames, recorded.
  void draw_groups(const RowNoiseId& id, std::span<double> out);
  // out += (M + sqrt(V) N) / lambda2, N from the row's kAggregateNormal lane.
  void add_normals(std::span<const double> mean, std::span<const double> variance,
                   const RowNoiseId& id, std::span<double> out);

  double lambda2_;
  std::vector<int> group_of_;                      // per frame, gain_groups
  std::vector<double> group_gain_;                 // alpha_g
  std::vector<std::vector<double>> group_lambda_;  // Lambda_g, in photons
  std::vector<char> group_used_;                   // group g had a frame since the last finish()
  std::vector<char> group_summed_;                 // Lambda_g holds frames of this row
  AggregatedRowPlan* plan_ = nullptr;              // being recorded
  // Per group, the lasting frames' intensities not yet added to Lambda_g.
  std::vector<std::vector<std::span<const double>>> group_pending_;
  std::size_t max_knuth_pixels_ = 0;
  bool has_frame_ = false;   // add_frame() was called since the last finish()
  bool has_normal_ = false;  // and some pixel of some frame was on the normal branch
  IntensityRows intensities_;
  std::vector<double> mean_;      // M, in photons
  std::vector<double> variance_;  // V, in photons^2
  std::vector<double> u1_;
  std::vector<double> u2_;
  std::vector<double> normals_;
};

}  // namespace fss

// The numerical mode's aggregated photon noise (aggregated_sampler.h).
// Compiled with the samplers' flags (CMakeLists.txt), so that its row loops
// vectorize.
#include "model/aggregated_sampler.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "core/vectorize.h"
#include "model/exact_poisson.h"
#include "model/poisson_sampler.h"

namespace fss {

std::vector<int> gain_groups(std::span<const double> gains) {
  std::map<double, int> frames;  // nonzero gain -> its count of frames
  for (const double alpha : gains) {
    if (alpha != 0.0 && !std::isnan(alpha)) ++frames[alpha];
  }
  std::map<double, int> number;  // shared gain -> its group, in the order of first frames
  std::vector<int> group(gains.size(), kSingleFrame);
  for (std::size_t k = 0; k < gains.size(); ++k) {
    if (gains[k] == 0.0 || std::isnan(gains[k]) || frames.at(gains[k]) < 2) continue;
    group[k] = number.try_emplace(gains[k], static_cast<int>(number.size())).first->second;
  }
  return group;
}

int gain_group_count(std::span<const double> gains) {
  const std::vector<int> group = gain_groups(gains);
  return group.empty() ? 0 : *std::max_element(group.begin(), group.end()) + 1;
}

AggregatedRowSampler::AggregatedRowSampler(double snr, std::span<const double> gains)
    : lambda2_(checked_lambda2(snr)), group_of_(gain_groups(gains)) {
  for (std::size_t k = 0; k < gains.size(); ++k) {
    const int g = group_of_[k];
    if (g != kSingleFrame && static_cast<std::size_t>(g) == group_gain_.size()) {
      group_gain_.push_back(gains[k]);
    }
  }
  group_lambda_.resize(group_gain_.size());
  group_used_.assign(group_gain_.size(), 0);
  group_summed_.assign(group_gain_.size(), 0);
  group_pending_.resize(group_gain_.size());
}

std::size_t AggregatedRowSampler::intensities_of(std::span<const double> e, double dark,
                                                 IntensityRows& rows) const {
  const std::size_t n = e.size();
  rows.lambda.resize(n);
  rows.mean_part.resize(n);
  rows.variance_part.resize(n);
  std::size_t normal_pixels = 0;
  detail::run_vectorized([&]() __attribute__((always_inline)) {
    // Locals, not the captured references, so that the loop vectorizes.
    const double* __restrict intensity = e.data();
    double* __restrict lambda = rows.lambda.data();
    double* __restrict mean = rows.mean_part.data();
    double* __restrict variance = rows.variance_part.data();
    const double lambda2 = lambda2_;
    const double dark_electrons = dark;
    std::size_t count = 0;
    for (std::size_t x = 0; x < n; ++x) {
      lambda[x] = std::max(intensity[x], 0.0) * lambda2 + dark_electrons;
      const bool normal = lambda[x] >= kKnuthLimit;
      mean[x] = normal ? lambda[x] : 0.0;
      variance[x] = normal ? lambda[x] + 1.0 / 12.0 : 0.0;
      count += normal ? 1 : 0;
    }
    normal_pixels = count;
  });
  return normal_pixels;
}

void AggregatedRowSampler::add_frame(std::span<const double> e, const RowNoiseId& id, double gain,
                                     std::span<double> out, const SensorReadout* readout) {
  const double dark = readout != nullptr ? readout->dark_electrons : 0.0;
  if (id.frame < group_of_.size() && group_of_[id.frame] != kSingleFrame) {
    // A grouped frame needs lambda only (intensities_of's expression).
    std::vector<double>& lambda = intensities_.lambda;
    lambda.resize(e.size());
    detail::run_vectorized([&]() __attribute__((always_inline)) {
      const std::size_t n = e.size();
      const double* __restrict intensity = e.data();
      double* __restrict to = lambda.data();
      const double lambda2 = lambda2_;
      const double dark_electrons = dark;
      for (std::size_t x = 0; x < n; ++x) {
        to[x] = std::max(intensity[x], 0.0) * lambda2 + dark_electrons;
      }
    });
    // lambda is this frame's only: summed now, not when the row is drawn.
    add_frame(FrameIntensities{lambda, {}, {}, 0}, id, gain, out, readout, /*lasting=*/false);
    return;
  }
  const std::size_t normal_pixels = intensities_of(e, dark, intensities_);
  add_frame(FrameIntensities{intensities_.lambda, intensities_.mean_part,
                             intensities_.variance_part, normal_pixels},
            id, gain, out, readout);
}

void AggregatedRowSampler::add_frame(const FrameIntensities& frame, const RowNoiseId& id,
                                     double gain, std::span<double> out,
                                     const SensorReadout* readout) {
  add_frame(frame, id, gain, out, readout, /*lasting=*/true);
}

void AggregatedRowSampler::add_frame(const FrameIntensities& frame, const RowNoiseId& id,
                                     double gain, std::span<double> out,
                                     const SensorReadout* readout, bool lasting) {
  const std::size_t n = frame.lambda.size();
  if (!has_frame_) {  // the row's first frame
    mean_.assign(n, 0.0);
    variance_.assign(n, 0.0);
    has_frame_ = true;
  }
  const int group = id.frame < group_of_.size() ? group_of_[id.frame] : kSingleFrame;
  if (group != kSingleFrame) {
    add_group_frame(group, frame.lambda, lasting);
    if (readout != nullptr) add_readout_terms(gain, *readout);
    return;
  }
  // Normal branch: M += alpha lambda, V += alpha^2 (lambda + 1/12); the
  // parts are 0 on Knuth's branch, and alpha 0 or alpha^2 0 adds a zero that
  // leaves every sum's bits as they are.
  detail::run_vectorized([&]() __attribute__((always_inline)) {
    const double* __restrict mean_part = frame.mean_part.data();
    const double* __restrict variance_part = frame.variance_part.data();
    double* __restrict mean = mean_.data();
    double* __restrict variance = variance_.data();
    const double alpha = gain;
    const double alpha_squared = gain * gain;
    for (std::size_t x = 0; x < n; ++x) {
      mean[x] += alpha * mean_part[x];
      variance[x] += alpha_squared * variance_part[x];
    }
  });
  if (frame.normal_pixels > 0) has_normal_ = true;
  if (readout != nullptr) add_readout_terms(gain, *readout);
  if (frame.normal_pixels == n) return;
  add_knuth_branch(frame.lambda, n - frame.normal_pixels, id, gain, out);
}

void AggregatedRowSampler::add_knuth_branch(std::span<const double> lambda,
                                            std::size_t knuth_pixels, const RowNoiseId& id,
                                            double gain, std::span<double> out) {
  // Drawn now: out += gain P / lambda2, uniforms in pixel order.
  RandomStream knuth_stream = lane_stream(id, id.frame, NoiseLane::kAggregateKnuth);
  const double scale = gain / lambda2_;
  AggregatedRowPlan::KnuthFrame* recorded = nullptr;
  if (plan_ != nullptr && plan_->knuth_pixels + knuth_pixels <= max_knuth_pixels_) {
    plan_->knuth_pixels += knuth_pixels;
    recorded = &plan_->knuth.emplace_back();
    recorded->frame = id.frame;
    recorded->gain = gain;
    recorded->pixels.reserve(knuth_pixels);
    recorded->lambdas.reserve(knuth_pixels);
  } else if (plan_ != nullptr) {
    plan_->knuth_pixels = max_knuth_pixels_ + 1;  // too many: the row is not recorded
  }
  for (std::size_t x = 0; x < lambda.size(); ++x) {
    if (lambda[x] < kKnuthLimit) {
      out[x] += scale * poisson_variate(lambda[x], knuth_stream);
      if (recorded != nullptr) {
        recorded->pixels.push_back(static_cast<std::uint32_t>(x));
        recorded->lambdas.push_back(lambda[x]);
      }
    }
  }
}

namespace {

// Columns summed together: a chunk of Lambda_g stays in the L1 cache while
// every frame of the group is added to it (a fast path measured in
// CONTRIBUTING.md, "Hand-written fast paths").
constexpr std::size_t kGroupChunk = 512;

// to[x] = (((to[x] + a[x]) + b[x]) + c[x]) + d[x] for x < n: four frames'
// additions in their order, one load and store of `to`.
__attribute__((always_inline)) inline void add_four(const double* __restrict a,
                                                    const double* __restrict b,
                                                    const double* __restrict c,
                                                    const double* __restrict d,
                                                    double* __restrict to, std::size_t n) {
  for (std::size_t x = 0; x < n; ++x) to[x] = (((to[x] + a[x]) + b[x]) + c[x]) + d[x];
}

__attribute__((always_inline)) inline void add_one(const double* __restrict a,
                                                   double* __restrict to, std::size_t n) {
  for (std::size_t x = 0; x < n; ++x) to[x] += a[x];
}

}  // namespace

void AggregatedRowSampler::add_group_frame(int group, std::span<const double> lambda,
                                           bool lasting) {
  const auto g = static_cast<std::size_t>(group);
  if (group_used_[g] == 0) {  // the group's first frame of the row
    group_used_[g] = 1;
    group_summed_[g] = 0;
    group_pending_[g].clear();
  }
  // A lasting frame is summed when the row is drawn, with the group's other frames; any other
  // frame now, its lambda being overwritten by the next frame's.
  group_pending_[g].push_back(lambda);
  if (!lasting) sum_pending_frames(g);
}

void AggregatedRowSampler::sum_pending_frames(std::size_t g) {
  std::vector<std::span<const double>>& pending = group_pending_[g];
  if (pending.empty()) return;
  std::vector<double>& sum = group_lambda_[g];
  const std::size_t n = pending.front().size();
  std::size_t first = 0;        // the first frame added to the sum
  if (group_summed_[g] == 0) {  // Lambda_g = lambda of the first frame
    sum.assign(pending.front().begin(), pending.front().end());
    first = 1;
  }
  // Lambda_g[x] += lambda_k[x] for the frames in their order, chunk by chunk:
  // each column's additions are those of the frames one at a time, so the
  // bits are the same.
  const std::size_t frames = pending.size();
  detail::run_vectorized([&]() __attribute__((always_inline)) {
    for (std::size_t x0 = 0; x0 < n; x0 += kGroupChunk) {
      const std::size_t len = std::min(kGroupChunk, n - x0);
      double* to = sum.data() + x0;
      std::size_t k = first;
      for (; k + 4 <= frames; k += 4) {
        add_four(pending[k].data() + x0, pending[k + 1].data() + x0, pending[k + 2].data() + x0,
                 pending[k + 3].data() + x0, to, len);
      }
      for (; k < frames; ++k) add_one(pending[k].data() + x0, to, len);
    }
  });
  group_summed_[g] = 1;
  pending.clear();
}

void AggregatedRowSampler::add_group_variances(std::span<double> variance, double scale) {
  for (std::size_t g = 0; g < group_used_.size(); ++g) {
    if (group_used_[g] == 0) continue;
    sum_pending_frames(g);
    detail::run_vectorized([&]() __attribute__((always_inline)) {
      const std::size_t n = variance.size();
      const double* __restrict lambda = group_lambda_[g].data();
      double* __restrict sum = variance.data();
      const double weight = group_gain_[g] * group_gain_[g] * scale;
      for (std::size_t x = 0; x < n; ++x) sum[x] += weight * lambda[x];
    });
  }
}

void AggregatedRowSampler::draw_groups(const RowNoiseId& id, std::span<double> out) {
  for (std::size_t g = 0; g < group_used_.size(); ++g) {
    if (group_used_[g] == 0) continue;
    sum_pending_frames(g);
    group_used_[g] = 0;
    RandomStream stream = lane_stream(id, g, NoiseLane::kGroupPoisson);
    add_exact_poisson_row(group_lambda_[g], stream, group_gain_[g] / lambda2_, out);
    if (plan_ != nullptr) plan_->groups.push_back({g, group_gain_[g], group_lambda_[g]});
  }
}

void AggregatedRowSampler::add_readout_terms(double gain, const SensorReadout& readout) {
  // Every pixel: M -= alpha dark (dark-frame correction), V += alpha^2 sigma_r^2.
  const double read_variance = readout.read_noise_electrons * readout.read_noise_electrons;
  for (std::size_t x = 0; x < mean_.size(); ++x) {
    mean_[x] -= gain * readout.dark_electrons;
    variance_[x] += gain * gain * read_variance;
  }
  has_normal_ = true;
}

void AggregatedRowSampler::add_normals(std::span<const double> mean_photons,
                                       std::span<const double> variance_photons,
                                       const RowNoiseId& id, std::span<double> out) {
  const std::size_t n = mean_photons.size();
  draw_normals(lane_stream(id, 0, NoiseLane::kAggregateNormal), n, u1_, u2_, normals_,
               /*portable=*/true);
  // out += (M + sqrt(V) N) / lambda2
  detail::run_vectorized([&]() __attribute__((always_inline)) {
    const double* __restrict mean = mean_photons.data();
    const double* __restrict variance = variance_photons.data();
    const double* __restrict normal = normals_.data();
    double* __restrict sum = out.data();
    const double lambda2 = lambda2_;
    for (std::size_t x = 0; x < n; ++x) {
      sum[x] += (mean[x] + std::sqrt(variance[x]) * normal[x]) / lambda2;
    }
  });
}

void AggregatedRowSampler::finish(const RowNoiseId& id, std::span<double> out) {
  draw_groups(id, out);
  if (has_normal_) add_normals(mean_, variance_, id, out);
  if (plan_ != nullptr) {
    // Within the bound RowPipeline::plan_bytes assumes: M, V, max_knuth_pixels
    // Knuth-branch pixels (an index and an intensity each) and each group's
    // Lambda_g: 28 + 8 G bytes a column of max_knuth_pixels columns.
    const std::size_t width = mean_.size();
    const std::size_t bytes = 12 * plan_->knuth_pixels + (has_normal_ ? 16 * width : 0) +
                              8 * width * plan_->groups.size();
    const std::size_t budget = (28 + 8 * group_gain_.size()) * max_knuth_pixels_;
    if (plan_->knuth_pixels <= max_knuth_pixels_ && bytes <= budget) {
      if (has_normal_) {
        plan_->mean = mean_;
        plan_->variance = variance_;
      }
      plan_->recorded = true;
    } else {
      *plan_ = AggregatedRowPlan();
    }
    plan_ = nullptr;
  }
  has_frame_ = false;
  has_normal_ = false;
}

void AggregatedRowSampler::record_next_row(AggregatedRowPlan* plan, std::size_t max_knuth_pixels) {
  *plan = AggregatedRowPlan();
  plan_ = plan;
  max_knuth_pixels_ = max_knuth_pixels;
}

void AggregatedRowSampler::replay(const AggregatedRowPlan& plan, const RowNoiseId& id,
                                  std::span<double> out) {
  // The Knuth-branch frames in their order, each from its own lane and in
  // pixel order, then the groups, then the normal: add_frame()'s and
  // finish()'s operations.
  for (const AggregatedRowPlan::KnuthFrame& frame : plan.knuth) {
    RandomStream knuth_stream = lane_stream(id, frame.frame, NoiseLane::kAggregateKnuth);
    const double scale = frame.gain / lambda2_;
    for (std::size_t i = 0; i < frame.pixels.size(); ++i) {
      out[frame.pixels[i]] += scale * poisson_variate(frame.lambdas[i], knuth_stream);
    }
  }
  for (const AggregatedRowPlan::Group& group : plan.groups) {
    RandomStream stream = lane_stream(id, group.group, NoiseLane::kGroupPoisson);
    add_exact_poisson_row(group.lambda, stream, group.gain / lambda2_, out);
  }
  if (!plan.mean.empty()) add_normals(plan.mean, plan.variance, id, out);
}

}  // namespace fss

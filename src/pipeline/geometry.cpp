#include "fss/pipeline/geometry.h"

#include <algorithm>
#include <cmath>

#include "fss/core/error.h"
#include "fss/pipeline/option_rules.h"

namespace fss {

namespace {

// Fills *g; returns why the image has no output, or "".
std::string compute_geometry(int width, int code_length, double velocity, double dt, Geometry* g) {
  if (code_length < 1) return "the code must have at least one gain";
  // B = max(L, ceil(|v| dt L))
  const double motion = std::ceil(std::abs(velocity) * dt * code_length);
  if (!(motion < static_cast<double>(width))) {
    return "the blur of velocity " + format_exact(velocity) + " over " +
           std::to_string(code_length) + " slots of dt " + format_exact(dt) + " spans " +
           format_exact(motion) + " pixels, more than the image width " + std::to_string(width);
  }
  g->width = width;
  g->blur_length = std::max(code_length, static_cast<int>(motion));
  g->half_blur = g->blur_length / 2;
  g->observed_width = width - g->blur_length;
  g->mirror_width = 2 * g->observed_width;
  g->output_width = width - 3 * g->blur_length;
  if (g->output_width >= 1) return {};
  const int b = g->blur_length;
  return "image width " + std::to_string(width) +
         " is too narrow for blur length B = " + std::to_string(b) +
         ": any output needs a width of at least 3B + 1 = " + std::to_string(3 * b + 1) +
         ", the measurement windows at least 5B + 1 = " + std::to_string(5 * b + 1) +
         " (9B + 1 = " + std::to_string(9 * b + 1) + " with the default RMSE margin)";
}

// Fills *w; returns why a window is empty, or "".
std::string compute_windows(const Geometry& g, int margin_columns, MetricWindows* w) {
  const int b = g.blur_length;
  const int margin = rmse_margin(g, margin_columns);
  *w = {margin, g.output_width - margin, b, g.output_width - b};
  // The RMSE_CI window [B, Wo - B) needs W > 5B whatever the margin.
  if (w->ci_first >= w->ci_end) {
    return "image width " + std::to_string(g.width) +
           " is too narrow for blur length B = " + std::to_string(b) +
           ": the contrast-invariant RMSE window [B, W - 4B) needs a width of at least " +
           std::to_string(5 * b + 1) + " (5B + 1), which no --rmse-margin can change";
  }
  if (w->rmse_first >= w->rmse_end) {
    const long long needed = 3LL * b + 2LL * margin + 1;
    return "image width " + std::to_string(g.width) +
           " is too narrow for the RMSE window: blur length B = " + std::to_string(b) +
           " and margin " + std::to_string(margin) + " need a width of at least " +
           std::to_string(needed) + " (3B + 2 margin + 1); choose a margin below " +
           std::to_string((g.output_width + 1) / 2) + " with --rmse-margin, or --rmse-margin auto";
  }
  return {};
}

}  // namespace

// auto: 3B while the window [3B, Wo - 3B) keeps a column (W >= 9B + 1, the paper's rule and
// bytes), else floor((Wo - B) / 2), whose window is B or B + 1 columns; a width with an RMSE_CI
// window (Wo >= 2B + 1) always has one.
int rmse_margin(const Geometry& geometry, int margin_columns) {
  const int b = geometry.blur_length;
  if (margin_columns == kRmseMarginDefault) return 3 * b;
  if (margin_columns != kRmseMarginAuto) return margin_columns;
  const int wo = geometry.output_width;
  if (wo - 6 * b >= 1) return 3 * b;
  return std::max(0, (wo - b) / 2);
}

Geometry Geometry::compute(int width, int code_length, double velocity, double dt) {
  Geometry g;
  const std::string reason = compute_geometry(width, code_length, velocity, dt, &g);
  if (!reason.empty()) throw_usage_error(reason);
  return g;
}

MetricWindows metric_windows(const Geometry& geometry, int margin_columns) {
  MetricWindows w;
  const std::string reason = compute_windows(geometry, margin_columns, &w);
  if (!reason.empty()) throw_usage_error(reason);
  return w;
}

std::string too_narrow_reason(int width, int code_length, double velocity, double dt,
                              int margin_columns, int* blur_length) {
  Geometry g;
  g.blur_length = -1;
  std::string reason = compute_geometry(width, code_length, velocity, dt, &g);
  if (blur_length != nullptr) *blur_length = g.blur_length;
  if (!reason.empty()) return reason;
  MetricWindows unused;
  return compute_windows(g, margin_columns, &unused);
}

}  // namespace fss

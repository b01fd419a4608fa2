// Every width and window of a simulation, computed in one place (docs/method.md §4, §5).
// Conventions: fss/fss.h.
#pragma once

#include <string>

namespace fss {

struct Geometry {
  int width = 0;           // W, input and observation width
  int blur_length = 0;     // B = max(L, ceil(|v| dt L))
  int half_blur = 0;       // h = floor(B / 2)
  int observed_width = 0;  // Wa = W - B, observed crop [h, h + Wa)
  int mirror_width = 0;    // 2 Wa, the deconvolution grid
  int output_width = 0;    // Wo = W - 3 B

  // Throws a usage fss::Error when the image is too narrow for any output.
  static Geometry compute(int width, int code_length, double velocity, double dt);
};

// The measurement windows, in output columns: RMSE [margin, Wo - margin) (margin 3B by default)
// and RMSE_CI [B, Wo - B).
struct MetricWindows {
  int rmse_first = 0;
  int rmse_end = 0;
  int ci_first = 0;
  int ci_end = 0;
};

// The RMSE margin a run uses, in columns: margin_columns itself, 3B for kRmseMarginDefault, and
// for kRmseMarginAuto 3B where the image is wide enough for it, else the largest margin that
// leaves an RMSE window of B columns (option_rules.h; docs/method.md §5).
int rmse_margin(const Geometry& geometry, int margin_columns);

// The windows with rmse_margin(geometry, margin_columns). Throws a usage fss::Error, giving the
// width needed, when a window is empty.
MetricWindows metric_windows(const Geometry& geometry, int margin_columns);

// Why a run cannot have its outputs and both windows: the message Simulate would throw from
// Geometry::compute or metric_windows, "" when it can. `velocity`: the larger of |v| and |v_r|.
// *blur_length (when not null) receives B, or -1 when the blur is wider than the image or the
// code is empty.
std::string too_narrow_reason(int width, int code_length, double velocity, double dt,
                              int margin_columns, int* blur_length = nullptr);

}  // namespace fss

#include "fss/io/outputs.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "fss/core/error.h"
#include "fss/io/html_report.h"
#include "fss/model/kernel.h"
#include "fss/pipeline/metrics.h"
#include "fss/core/parallel.h"
#include "fss/io/plot.h"
#include "fss/io/png_io.h"
#include "fss/model/transfer.h"

namespace fss {

std::string format_spectrum_txt(const std::vector<double>& gains, double velocity, double dt) {
  std::ostringstream out;  // default stream format: 6 significant digits
  for (int j = 0; j < 100; ++j) {
    const double xi = -M_PI + j * (2.0 * M_PI / 100.0);
    out << xi << ' ' << std::abs(transfer_function(gains, velocity, dt, xi)) << '\n';
  }
  return out.str();
}

namespace {
// JSON has no infinity: an infinite or NaN value is written as null.
nlohmann::json finite_or_null(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}
}  // namespace

nlohmann::json report_json(const SimulationReport& r, const std::string& input_path) {
  nlohmann::json j;
  j["input"] = {
      {"path", input_path}, {"width", r.width}, {"height", r.height}, {"channels", r.channels}};
  j["parameters"] = {{"code", r.code_name},
                     {"code_length", r.gains.size()},
                     {"mode", to_string(r.options.mode)},
                     {"velocity", r.options.velocity_px_per_slot},
                     {"restore_velocity", r.options.restore_velocity_px_per_slot.value_or(
                                              r.options.velocity_px_per_slot)},
                     {"dt", r.options.dt},
                     {"snr", r.options.snr},
                     {"seed", r.options.seed},
                     {"noise", to_string(r.options.noise)},
                     {"trials", r.options.trials}};
  j["code"] = {{"name", r.code_name},
               {"gains", r.gains},
               {"sum", gain_sum(r.gains)},
               {"square_sum", gain_square_sum(r.gains)},
               {"normalized_l1", normalized_l1(r.gains)}};
  j["geometry"] = {{"blur_length", r.geometry.blur_length},
                   {"observed_width", r.geometry.observed_width},
                   {"mirror_width", r.geometry.mirror_width},
                   {"output_width", r.geometry.output_width},
                   {"output_first_input_column", 3 * r.geometry.half_blur},
                   {"rmse_columns", {r.rmse_first, r.rmse_end}},
                   {"rmse_ci_columns", {r.rmse_ci_first, r.rmse_ci_end}}};
  j["metrics"] = {{"rmse", finite_or_null(r.metrics.rmse)},
                  {"psnr", finite_or_null(r.metrics.psnr)},
                  {"rmse_ci", finite_or_null(r.metrics.rmse_ci)},
                  {"psnr_ci", finite_or_null(r.metrics.psnr_ci)}};
  j["kernel"] = {{"k0", r.kernel.k0},
                 {"min_abs", r.kernel.min_abs},
                 {"min_abs_xi", r.kernel.min_abs_xi},
                 {"invertible", r.kernel.invertible},
                 {"observed_divisor", r.observed_divisor},
                 {"zero_bins", r.zero_bins}};
  j["prediction"] = {{"finite", r.prediction.finite},
                     {"rmse_noise_free", finite_or_null(r.prediction.rmse_noise_free)},
                     {"sigma", finite_or_null(r.prediction.sigma)},
                     {"rmse", finite_or_null(r.prediction.rmse)},
                     {"snr_level100", finite_or_null(r.prediction.snr_level100)},
                     {"window_mean", r.prediction.window_mean},
                     {"q", r.prediction.q},
                     {"m", finite_or_null(r.prediction.m_amplification)}};
  j["trials"] = {{"n", r.trials.n},
                 {"rmse_mean", finite_or_null(r.trials.rmse_mean)},
                 {"rmse_sd", finite_or_null(r.trials.rmse_sd)},
                 {"rmse_ci_mean", finite_or_null(r.trials.rmse_ci_mean)},
                 {"rmse_ci_sd", finite_or_null(r.trials.rmse_ci_sd)}};
  j["warnings"] = r.warnings;
  return j;
}

std::vector<std::string> output_file_names(const OutputOptions& options) {
  std::vector<std::string> names = {"observed.png", "restored.png", "groundtruth.png",
                                    "residual.png", "code.txt",     "spectrum.txt",
                                    "report.json"};
  if (options.plots) {
    names.push_back("code.png");
    names.push_back("spectrum.png");
  }
  if (options.sheet) names.push_back("sheet.png");
  if (options.html_report) names.push_back("report.html");
  return names;
}

ObservedPng8::ObservedPng8(int height, int channels) : height_(height), channels_(channels) {
  if (height <= 0 || (channels != 1 && channels != 3)) {
    throw_usage_error("ObservedPng8 needs a height > 0 and 1 or 3 channels, got height " +
                      std::to_string(height) + " and " + std::to_string(channels) + " channels");
  }
  stored_ = std::vector<std::atomic<bool>>(static_cast<std::size_t>(height) * channels);
}

void ObservedPng8::store_row(int channel, int row, std::span<const double> values) {
  std::call_once(allocated_, [&] {
    width_ = static_cast<int>(values.size());
    samples_.resize(values.size() * static_cast<std::size_t>(height_) * channels_);
  });
  if (channel < 0 || channel >= channels_ || row < 0 || row >= height_ ||
      values.size() != static_cast<std::size_t>(width_)) {
    throw_usage_error("ObservedPng8: row " + std::to_string(row) + " of channel " +
                      std::to_string(channel) + " with " + std::to_string(values.size()) +
                      " values does not fit a " + std::to_string(width_) + " x " +
                      std::to_string(height_) + " x " + std::to_string(channels_) + " image");
  }
  if (stored_[static_cast<std::size_t>(channel) * height_ + row].exchange(true)) {
    throw_usage_error("ObservedPng8: row " + std::to_string(row) + " of channel " +
                      std::to_string(channel) + " was stored twice");
  }
  // Interleaved as PNG stores them: sample (row, x, channel).
  std::uint8_t* out =
      samples_.data() + static_cast<std::size_t>(row) * width_ * channels_ + channel;
  for (const double v : values) {
    *out = png8_sample(v);
    out += channels_;
  }
  ++rows_stored_;
}

std::vector<std::uint8_t> ObservedPng8::encode() const {
  if (rows_stored_ != height_ * channels_) {
    throw_usage_error("observed.png: " + std::to_string(rows_stored_) + " of " +
                      std::to_string(height_ * channels_) + " observed rows were collected");
  }
  return encode_png8_samples(width_, height_, channels_, samples_);
}

RunPlots render_run_plots(const ShutterCode& code, const SimulationOptions& options) {
  RunPlots plots;
  plots.code_name = code.name;
  plots.gains = code.gains;
  plots.velocity_px_per_slot = options.velocity_px_per_slot;
  plots.restore_velocity_px_per_slot =
      options.restore_velocity_px_per_slot.value_or(options.velocity_px_per_slot);
  plots.dt = options.dt;
  plots.code_png = plot_code_png(code.gains, code.name);
  // The curve at the true velocity; the minimum marked is that of the
  // kernel the restoration inverts (SimulationReport::kernel).
  plots.spectrum_png =
      plot_spectrum_png(code.gains, code.name, plots.velocity_px_per_slot, plots.dt,
                        analyze_kernel(code.gains, plots.restore_velocity_px_per_slot, plots.dt));
  return plots;
}

namespace {

const RunPlots& check_plots_match(const RunPlots& plots, const SimulationReport& report) {
  const SimulationOptions& o = report.options;
  const double restore_velocity = o.restore_velocity_px_per_slot.value_or(o.velocity_px_per_slot);
  std::string problem;
  if (plots.code_name != report.code_name) {
    problem = "code '" + plots.code_name + "', the run's is '" + report.code_name + "'";
  } else if (plots.gains != report.gains) {
    problem = "other gains of code '" + plots.code_name + "'";
  } else if (plots.velocity_px_per_slot != o.velocity_px_per_slot) {
    problem = "velocity " + format_number(plots.velocity_px_per_slot) + ", the run's is " +
              format_number(o.velocity_px_per_slot);
  } else if (plots.restore_velocity_px_per_slot != restore_velocity) {
    problem = "restore velocity " + format_number(plots.restore_velocity_px_per_slot) +
              ", the run's is " + format_number(restore_velocity);
  } else if (plots.dt != o.dt) {
    problem = "dt " + format_number(plots.dt) + ", the run's is " + format_number(o.dt);
  }
  if (!problem.empty()) {
    throw_usage_error("the plots given to write_outputs are not for the report's run: drawn for " +
                      problem);
  }
  return plots;
}

}  // namespace

std::vector<std::uint8_t> figure_sheet_png(const SimulationReport& r, const Image& input) {
  if (r.observed.data.empty()) {
    throw_usage_error("sheet.png needs the observed image: run Simulate without an ObservedRowSink");
  }
  char parameters[160];
  std::snprintf(parameters, sizeof parameters,
                "%s, v = %g, dt = %g, snr = %g: RMSE %.4g, RMSE_CI %.4g",
                to_string(r.options.mode).c_str(), r.options.velocity_px_per_slot, r.options.dt,
                r.options.snr, r.metrics.rmse, r.metrics.rmse_ci);
  const Image residual = residual_image(input, r);
  return figure_sheet_png(
      {{&r.observed, "observed"}, {&r.restored, "restored"}, {&residual, "residual (stretched)"}},
      r.code_name + " — " + parameters);
}

namespace {

// Creates a new file next to `target`, under a name no other file has
// (O_EXCL: nothing existing is ever replaced or removed), writes `bytes` into
// it and returns its path. On failure, removes it and throws a runtime fss::Error.
std::filesystem::path stage(const std::filesystem::path& target, const std::string& bytes) {
  const std::filesystem::path dir = target.parent_path();
  const std::string prefix =
      std::string(".") + target.filename().string() + ".fssim-" + std::to_string(::getpid()) + "-";
  for (int attempt = 0;; ++attempt) {
    std::filesystem::path temporary = dir / (prefix + std::to_string(attempt) + ".tmp");
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) {
      if (errno == EEXIST && attempt < 100) continue;
      throw_runtime_error("cannot write output '" + target.string() +
                          "': cannot create a file in '" + dir.string() +
                          "': " + std::strerror(errno));
    }
    const char* data = bytes.data();
    std::size_t left = bytes.size();
    int error = 0;
    while (left > 0) {
      const ssize_t written = ::write(fd, data, left);
      if (written < 0 && errno == EINTR) continue;
      if (written <= 0) {
        error = written < 0 ? errno : EIO;
        break;
      }
      data += written;
      left -= static_cast<std::size_t>(written);
    }
    if (::close(fd) != 0 && error == 0) error = errno;
    if (error != 0) {
      ::unlink(temporary.c_str());
      throw_runtime_error("cannot write output '" + target.string() + "': " + std::strerror(error));
    }
    return temporary;
  }
}

std::string as_string(const std::vector<std::uint8_t>& bytes) {
  return {bytes.begin(), bytes.end()};
}

// Renames every staged file into place, in order; on a failure, removes the
// temporary files not yet moved and throws.
void rename_all(
    const std::vector<std::pair<std::filesystem::path, std::filesystem::path>>& staged) {
  std::error_code ec;
  for (std::size_t i = 0; i < staged.size(); ++i) {
    std::filesystem::rename(staged[i].first, staged[i].second, ec);
    if (ec) {
      const std::string message = "cannot move '" + staged[i].first.string() + "' to '" +
                                  staged[i].second.string() + "': " + ec.message();
      for (std::size_t j = i; j < staged.size(); ++j) {
        std::filesystem::remove(staged[j].first, ec);
      }
      throw_runtime_error(message);
    }
  }
}

}  // namespace

void write_outputs(const std::filesystem::path& outdir, const SimulationReport& report,
                   const Image& input, const std::string& input_path,
                   const OutputOptions& options) {
  if (outdir.empty()) throw_usage_error("the output directory must not be an empty path");
  // Everything is encoded in memory first: a failure there writes nothing.
  // The ground truth and the residual are encoded straight from the input
  // and the restoration, row by row.
  const double velocity = report.options.velocity_px_per_slot, dt = report.options.dt;
  const std::vector<std::string> names = output_file_names(options);
  const int offset = report.output_first_column();
  const int wo = report.restored.width;
  const ResidualRange range = residual_range(input, offset, report.restored);
  // How to make each file of `names`.
  const std::vector<std::pair<std::string, std::function<std::string()>>> makers = {
      {"observed.png",
       [&] {
         if (!report.observed.data.empty()) return as_string(encode_png8(report.observed));
         if (const ObservedPng8* observed = options.observed_png8) {
           if (observed->width() != report.restored.width ||
               observed->height() != report.restored.height ||
               observed->channels() != report.restored.channels) {
             throw_usage_error(
                 "observed.png: OutputOptions::observed_png8 holds a " +
                 std::to_string(observed->width()) + " x " + std::to_string(observed->height()) +
                 " x " + std::to_string(observed->channels()) +
                 " image, the report's outputs are " + std::to_string(report.restored.width) +
                 " x " + std::to_string(report.restored.height) + " x " +
                 std::to_string(report.restored.channels));
           }
           return as_string(observed->encode());
         }
         throw_usage_error(
             "observed.png: the report keeps no observed image (its rows went to an ObservedRowSink) and "
             "OutputOptions::observed_png8 is not set");
       }},
      {"restored.png", [&] { return as_string(encode_png8(report.restored)); }},
      {"groundtruth.png",
       [&] {
         return as_string(
             encode_png8(wo, input.height, input.channels, [&](int c, int y, double* row) {
               std::copy(input.row(c, y) + offset, input.row(c, y) + offset + wo, row);
             }));
       }},
      {"residual.png",
       [&] {
         return as_string(
             encode_png8(wo, input.height, input.channels, [&](int c, int y, double* row) {
               const double* truth = input.row(c, y) + offset;
               const double* restored = report.restored.row(c, y);
               for (int x = 0; x < wo; ++x) row[x] = range.stretch(truth[x] - restored[x]);
             }));
       }},
      {"code.txt",
       [&] {
         return format_code_txt({report.code_name, report.gains});
       }},
      {"spectrum.txt", [&] { return format_spectrum_txt(report.gains, velocity, dt); }},
      // Paths are bytes: one that is not UTF-8 is kept in report.json with
      // U+FFFD in place of its invalid bytes rather than failing the run.
      {"report.json",
       [&] {
         return report_json(report, input_path)
                    .dump(2, ' ', false, nlohmann::json::error_handler_t::replace) +
                "\n";
       }},
      {"code.png",
       [&] {
         if (options.rendered_plots) {
           return as_string(check_plots_match(*options.rendered_plots, report).code_png);
         }
         return as_string(plot_code_png(report.gains, report.code_name));
       }},
      {"spectrum.png",
       [&] {
         if (options.rendered_plots) {
           return as_string(check_plots_match(*options.rendered_plots, report).spectrum_png);
         }
         return as_string(
             plot_spectrum_png(report.gains, report.code_name, velocity, dt, report.kernel));
       }},
      {"sheet.png", [&] { return as_string(figure_sheet_png(report, input)); }},
      {"report.html", [&] { return html_report(report, input_path, names); }},
  };
  std::vector<std::pair<std::string, std::string>> contents(names.size());
  parallel_for(static_cast<int>(names.size()), report.options.threads, [&](int begin, int end) {
    for (int i = begin; i < end; ++i) {
      const auto maker = std::find_if(makers.begin(), makers.end(),
                                      [&](const auto& m) { return m.first == names[i]; });
      contents[i] = {names[i], maker->second()};
    }
  });

  std::error_code ec;
  if (std::filesystem::exists(outdir, ec) && !std::filesystem::is_directory(outdir, ec)) {
    throw_runtime_error("output directory '" + outdir.string() + "' exists and is not a directory");
  }
  std::filesystem::create_directories(outdir, ec);
  if (ec) {
    throw_runtime_error("cannot create output directory '" + outdir.string() +
                        "': " + ec.message());
  }
  std::vector<std::string> inputs = options.other_inputs;
  inputs.insert(inputs.begin(), input_path);
  for (const auto& [name, bytes] : contents) {
    const auto target = outdir / name;
    for (const std::string& protected_input : inputs) {
      if (std::filesystem::exists(target, ec) && std::filesystem::exists(protected_input, ec) &&
          std::filesystem::equivalent(target, protected_input, ec)) {
        throw_runtime_error("refusing to overwrite the input '" + protected_input +
                            "' with output '" + target.string() + "': choose another --outdir");
      }
    }
    if (std::filesystem::is_directory(target, ec)) {
      throw_runtime_error("cannot write output '" + target.string() + "': it is a directory");
    }
  }

  // Stage every file, then rename them into place: a failure before the
  // renames leaves the directory as it was.
  std::vector<std::pair<std::filesystem::path, std::filesystem::path>> staged;  // temporary, target
  staged.reserve(contents.size());
  try {
    for (const auto& [name, bytes] : contents) {
      std::filesystem::path target = outdir / name;
      std::filesystem::path temporary = stage(target, bytes);
      staged.emplace_back(std::move(temporary), std::move(target));
    }
  } catch (...) {
    for (const auto& file : staged) std::filesystem::remove(file.first, ec);
    throw;
  }
  rename_all(staged);
}

void write_file_atomically(const std::filesystem::path& path, const std::string& bytes) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw_runtime_error("cannot write '" + path.string() + "': it is a directory");
  }
  const std::filesystem::path target = path.has_parent_path() ? path : "./" / path;
  rename_all({{stage(target, bytes), target}});
}

}  // namespace fss

#include "fss/outputs.h"

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

#include "fss/error.h"
#include "fss/html_report.h"
#include "fss/metrics.h"
#include "fss/parallel.h"
#include "fss/plot.h"
#include "fss/png_io.h"
#include "fss/transfer.h"

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

std::vector<std::uint8_t> figure_sheet_png(const SimulationReport& r, const Image& input) {
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

struct StagedFile {
  std::filesystem::path temporary;
  std::filesystem::path target;
};

void write_file(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file) {
    throw_runtime_error("cannot create '" + path.string() + "': " + std::strerror(errno));
  }
  file.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  file.close();
  if (!file) throw_runtime_error("cannot write '" + path.string() + "' (disk full?)");
}

std::string as_string(const std::vector<std::uint8_t>& bytes) {
  return {bytes.begin(), bytes.end()};
}

}  // namespace

void write_outputs(const std::filesystem::path& outdir, const SimulationReport& report,
                   const Image& input, const std::string& input_path,
                   const OutputOptions& options) {
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
      {"observed.png", [&] { return as_string(encode_png8(report.observed)); }},
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
      {"report.json", [&] { return report_json(report, input_path).dump(2) + "\n"; }},
      {"code.png", [&] { return as_string(plot_code_png(report.gains, report.code_name)); }},
      {"spectrum.png",
       [&] {
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
  for (const auto& [name, bytes] : contents) {
    const auto target = outdir / name;
    if (std::filesystem::exists(target, ec) && std::filesystem::exists(input_path, ec) &&
        std::filesystem::equivalent(target, input_path, ec)) {
      throw_runtime_error("refusing to overwrite the input '" + input_path + "' with output '" +
                          target.string() + "': choose another --outdir");
    }
    if (std::filesystem::is_directory(target, ec)) {
      throw_runtime_error("cannot write output '" + target.string() + "': it is a directory");
    }
  }

  std::vector<StagedFile> staged;
  const std::string suffix = ".fssim-tmp-" + std::to_string(::getpid());
  try {
    for (const auto& [name, bytes] : contents) {
      StagedFile file{outdir / ("." + name).append(suffix), outdir / name};
      staged.push_back(file);
      write_file(file.temporary, bytes);
    }
  } catch (...) {
    for (const auto& file : staged) std::filesystem::remove(file.temporary, ec);
    throw;
  }
  for (std::size_t i = 0; i < staged.size(); ++i) {
    std::filesystem::rename(staged[i].temporary, staged[i].target, ec);
    if (ec) {
      const std::string message = "cannot move '" + staged[i].temporary.string() + "' to '" +
                                  staged[i].target.string() + "': " + ec.message();
      for (std::size_t j = i; j < staged.size(); ++j)
        std::filesystem::remove(staged[j].temporary, ec);
      throw_runtime_error(message);
    }
  }
}

void write_file_atomically(const std::filesystem::path& path, const std::string& bytes) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw_runtime_error("cannot write '" + path.string() + "': it is a directory");
  }
  std::filesystem::path temporary = path;
  std::string name = path.filename().string();
  name.insert(0, 1, '.');
  name += ".fssim-tmp-" + std::to_string(::getpid());
  temporary.replace_filename(name);
  try {
    write_file(temporary, bytes);
  } catch (...) {
    std::filesystem::remove(temporary, ec);
    throw;
  }
  std::filesystem::rename(temporary, path, ec);
  if (ec) {
    const std::string message =
        "cannot move '" + temporary.string() + "' to '" + path.string() + "': " + ec.message();
    std::filesystem::remove(temporary, ec);
    throw_runtime_error(message);
  }
}

}  // namespace fss

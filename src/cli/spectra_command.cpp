#include "spectra_command.h"

#include <cstdint>
#include <cstdio>

#include "cli_common.h"
#include "fss/model/code.h"
#include "fss/model/kernel.h"

namespace fssim {

SpectraCommand::SpectraCommand(CLI::App& parent)
    : Command(parent, "spectra",
              "plot |K| of several codes on one picture (no simulation): fssim "
              "spectra --output FILE CODE...") {
  CLI::App& spectra = app();
  spectra.add_option("codes", codes_, "built-in code names or code files (1 to 8)")->required();
  spectra.add_option("-o,--output", output_, "PNG file to write (-: standard output)")->required();
  spectra.add_option("-v,--velocity", velocity_, "velocity in pixels per time slot")
      ->check(finite())
      ->capture_default_str();
  spectra.add_option("--dt", dt_, "time slot length, > 0")->check(scale())->capture_default_str();
  spectra.add_flag("--linear", linear_, "linear |K| axis (default: logarithmic)");
  spectra.add_option("--width", plot_.width, "plot width in pixels")
      ->check(CLI::Range(fss::kPlotMinSide, fss::kPlotMaxSide))
      ->capture_default_str();
  spectra.add_option("--height", plot_.height, "plot height in pixels")
      ->check(CLI::Range(fss::kPlotMinSide, fss::kPlotMaxSide))
      ->capture_default_str();
  spectra.add_option("--title", plot_.title, "plot title (default: made from the data)");
}

int SpectraCommand::Run() const {
  return run_reporting_errors([this] { return Plot(); });
}

int SpectraCommand::Plot() const {
  std::vector<fss::ShutterCode> codes;
  for (const std::string& name : codes_) codes.push_back(fss::load_code(name));
  const std::vector<std::uint8_t> png =
      fss::plot_spectra_overlay_png(codes, velocity_, dt_, !linear_, plot_);
  write_output(output_, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()),
               codes_);
  // With the PNG on stdout, the summary goes to stderr.
  std::FILE* info = is_stdout(output_) ? stderr : stdout;
  for (const fss::ShutterCode& code : codes) {
    const fss::KernelAnalysis k = fss::analyze_kernel(code.gains, velocity_, dt_);
    std::fprintf(info, "%s: min |K| %g at xi %g%s\n", code.name.c_str(), k.min_abs, k.min_abs_xi,
                 k.invertible ? "" : " (not invertible)");
  }
  std::fprintf(info, "Plot: %s\n", output_.c_str());
  return kExitSuccess;
}

}  // namespace fssim

// The one binding of fss::SimulationOptions to command-line flags, used by
// every command that simulates (the main command, sweep). The values are
// checked by the library's rules (fss/pipeline/option_rules.h).
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "fss/pipeline/simulate.h"

namespace fssim {

class SimulationFlags {
 public:
  // Each adds one flag to `app`, writing into this object, which must outlive
  // the parse.
  void AddCode(CLI::App& app);             // -c,--code
  void AddMode(CLI::App& app);             // -m,--mode
  void AddVelocity(CLI::App& app);         // -v,--velocity
  void AddRestoreVelocity(CLI::App& app);  // --restore-velocity
  // --velocity-distribution (docs/method.md §13): refused with -v/--velocity when this object
  // added that flag, and with a restoration fitted to one velocity.
  void AddVelocityDistribution(CLI::App& app);
  void AddDt(CLI::App& app);          // --dt
  void AddSnr(CLI::App& app);         // --snr
  void AddSeed(CLI::App& app);        // --seed
  void AddNoise(CLI::App& app);       // --noise
  void AddRmseMargin(CLI::App& app);  // --rmse-margin
  void AddTrials(CLI::App& app);      // --trials
  void AddThreads(CLI::App& app);     // --threads
  void AddMaxMemory(CLI::App& app);   // --max-memory
  // --read-noise, --dark-current, --full-well, --adc-bits, --adc-gain
  // (docs/method.md §10); all off by default.
  void AddSensor(CLI::App& app);
  // --restoration, --regularization, --prior (docs/method.md §12); default the inverse filter.
  void AddRestoration(CLI::App& app);

  // All of the above, in this order.
  void AddAll(CLI::App& app);

  // The code the user named (a built-in name or a file).
  const std::string& code_name() const { return code_name_; }
  // With AddVelocityDistribution: the file the distribution was read from, "" for none (a
  // distribution given as uniform:LO:HI or normal:...); an input, never written over.
  std::string velocity_distribution_file(const fss::SimulationOptions& options) const;

  // The options the flags give, after a successful parse. With AddMaxMemory
  // the memory limit is --max-memory, or half of the physical memory when it
  // is not given; throws a usage fss::Error naming --max-memory when its value
  // is not a size.
  fss::SimulationOptions Options() const;

 private:
  // With AddSensor: sets the full well and checks the sensor flags by the
  // library's rule, throwing a usage fss::Error naming the flag.
  void check_sensor(fss::SimulationOptions& options) const;
  // With AddRestoration: the restoration flags into `options`, checked by the library's rules,
  // throwing a usage fss::Error naming the flag.
  void read_restoration(fss::SimulationOptions& options) const;
  // With AddVelocityDistribution: the distribution into `options` (load_velocity_distribution),
  // refused with --velocity or a restoration fitted to one velocity.
  void read_velocity_distribution(fss::SimulationOptions& options) const;

 private:
  fss::SimulationOptions options_;
  std::string code_name_ = "raskar";
  std::string mode_ = "numerical";
  std::string noise_ = "poisson";
  CLI::Option* velocity_option_ = nullptr;
  double restore_velocity_ = 0.0;
  CLI::Option* restore_velocity_option_ = nullptr;
  std::string velocity_distribution_;
  CLI::Option* velocity_distribution_option_ = nullptr;
  std::string max_memory_;
  CLI::Option* max_memory_option_ = nullptr;
  double full_well_ = 0.0;
  CLI::Option* full_well_option_ = nullptr;
  CLI::Option* adc_bits_option_ = nullptr;
  CLI::Option* adc_gain_option_ = nullptr;
  std::string restoration_ = "inverse";
  std::string regularization_ = "optimal";
  std::string prior_ = "power-law:2";
  CLI::Option* restoration_option_ = nullptr;
  CLI::Option* regularization_option_ = nullptr;
  CLI::Option* prior_option_ = nullptr;
};

}  // namespace fssim

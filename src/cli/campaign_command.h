// `fssim campaign`: images x codes x settings into a directory of tidy
// results (fss/campaign/run.h), `campaign merge` of shards, `campaign
// check` of results against expectations and `campaign table` of results for
// a paper.
#pragma once

#include <string>
#include <vector>

#include "command.h"
#include "fss/campaign/spec.h"
#include "fss/pipeline/option_rules.h"

namespace fssim {

class CampaignCommand : public Command {
 public:
  // Adds `campaign`, with `merge`, `check` and `table` under it, to `parent`.
  explicit CampaignCommand(CLI::App& parent);
  int Run() const override;

 private:
  void AddSpecOptions();
  fss::CampaignSpec Spec() const;
  // The fixed sensor options given on the command line, over `sensor`.
  void ApplySensorOptions(fss::SensorModel& sensor) const;
  int RunCampaign() const;
  int Merge() const;
  int Check() const;
  void AddTableCommand();
  int Table() const;
  // What settings that cannot run do to the exit status: fail it, not (--skip-unrunnable), or
  // not and say that the merge will (a shard).
  enum class GapExit { kFail, kSkip, kShard };
  int ReportGaps(const fss::ResolvedCampaign& campaign,
                 const std::vector<std::vector<std::string>>& rows, const std::string& what,
                 GapExit exit) const;
  void DrawFigures(const fss::ResolvedCampaign& campaign,
                   const std::vector<std::vector<std::string>>& rows, const std::string& dir) const;

  CLI::App* merge_ = nullptr;
  CLI::App* check_ = nullptr;
  CLI::App* table_ = nullptr;

  // campaign
  std::string file_;
  std::vector<std::string> inputs_, codes_, modes_;
  std::string velocity_ = "1", restore_velocity_, snr_ = "100", dt_ = "1";
  int trials_ = 1;
  std::uint64_t seed_ = 0;
  std::string noise_ = "poisson";
  int rmse_margin_ = fss::kRmseMarginAuto;
  bool per_trial_ = false;
  std::string read_noise_ = "0";
  std::vector<std::string> restorations_, regularization_, priors_;
  std::vector<std::string> velocity_distributions_;
  double dark_current_ = 0.0, full_well_ = 0.0, adc_gain_ = 1.0;
  int adc_bits_ = 0;
  int threads_ = 0;
  std::string output_;
  std::string shard_ = "1/1";
  bool figures_ = false;
  bool skip_unrunnable_ = false;
  bool progress_ = true;

  // merge
  std::string merge_output_;
  std::vector<std::string> parts_;
  bool merge_figures_ = false;
  bool merge_skip_unrunnable_ = false;

  // check
  std::string results_, expected_, junit_;
  std::vector<std::string> check_columns_;
  double abs_tolerance_ = 0.0, rel_tolerance_ = 0.0, k_se_ = 0.0;
  bool predicted_ = false;
  bool exact_ = false;

  // table
  std::string table_results_, table_format_ = "markdown", table_output_ = "-";
  std::vector<std::string> table_columns_;
  int table_digits_ = 2;
};

}  // namespace fssim

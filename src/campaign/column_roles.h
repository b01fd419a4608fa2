// The role of each column of a campaign's results (docs/campaign.md, "Regression checks"):
// what selects a row, what is a mean over noisy trials with a standard error, what is
// deterministic, what follows another column, what only records provenance. `campaign check`
// chooses its comparisons from it; a new results column is given its role here, once.
#pragma once

#include <string_view>
#include <vector>

namespace fss::column_roles {

enum class Role {
  kSetting,     // selects the row (image, code, snr, ...)
  kStatistic,   // a mean over the trials: its standard error from `partner` (the sd) and trials
  kSpread,      // the sd of a statistic (`partner`: the statistic)
  kTrials,      // the number of trials of each statistic
  kExact,       // a deterministic output: equal up to floating-point round-off
  kDerived,     // a function of `partner`, its base (psnr_mean of rmse_mean)
  kProvenance,  // where the row comes from (seed, digests, message, version): not compared
};

struct ColumnRole {
  std::string_view name;
  Role role;
  std::string_view partner;  // kStatistic: its sd; kSpread: its statistic; kDerived: its base
  // kExact only: drawn from the noise, so set by the seed, where the row fits its restoration
  // to a noisy observation (fits_to_noise).
  bool fitted = false;
};

// Every column of results.csv, schemas 3 and 4, in the schema's order.
const std::vector<ColumnRole>& all();

// The role of column `name`; nullptr for a name that is not a results column.
const ColumnRole* find(std::string_view name);

// The role's name as the check's summary shows it ("statistic", "exact", ...).
std::string_view role_name(Role role);

// Whether a row with this restoration and prior fits its filter to a noisy observation, so
// that its `fitted` outputs depend on its seed.
bool fits_to_noise(std::string_view restoration, std::string_view prior);

}  // namespace fss::column_roles

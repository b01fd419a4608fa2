#include "campaign/column_roles.h"

namespace fss::column_roles {

namespace {

constexpr Role kSetting = Role::kSetting;
constexpr Role kExact = Role::kExact;
constexpr Role kProvenance = Role::kProvenance;

}  // namespace

// The columns of results.cpp's all_columns(), each with its role. The statistics are the means
// over the trials whose sd the row carries; every output computed without noise (the geometry,
// the predictions, the restoration's parameters) is exact, but those Wiener's power-law prior
// fits to a calibration observation drawn from the noise (docs/method.md §12), which are set by
// the seed (`fitted`).
const std::vector<ColumnRole>& all() {
  static const std::vector<ColumnRole> roles = {
      {"image", kSetting, ""},
      {"image_sha256", kProvenance, ""},
      {"code", kSetting, ""},
      {"code_sha256", kProvenance, ""},
      {"code_normalized_l1", kExact, ""},
      {"mode", kSetting, ""},
      {"velocity", kSetting, ""},
      {"restore_velocity", kSetting, ""},
      {"snr", kSetting, ""},
      {"dt", kSetting, ""},
      {"read_noise", kSetting, ""},
      {"dark_current", kSetting, ""},
      {"full_well", kSetting, ""},
      {"adc_bits", kSetting, ""},
      {"adc_gain", kSetting, ""},
      {"restoration", kSetting, ""},
      {"regularization", kSetting, ""},
      {"prior", kSetting, ""},
      {"noise", kSetting, ""},
      {"rmse_margin", kSetting, ""},
      {"seed", kProvenance, ""},
      {"trials", Role::kTrials, ""},
      {"blur_length", kExact, ""},
      {"rmse_mean", Role::kStatistic, "rmse_sd"},
      {"rmse_sd", Role::kSpread, "rmse_mean"},
      {"rmse_ci_mean", Role::kStatistic, "rmse_ci_sd"},
      {"rmse_ci_sd", Role::kSpread, "rmse_ci_mean"},
      {"psnr_mean", Role::kDerived, "rmse_mean"},  // 20 log10(255 / rmse_mean)
      {"ssim_mean", Role::kStatistic, "ssim_sd"},
      {"ssim_sd", Role::kSpread, "ssim_mean"},
      {"predicted_rmse", kExact, "", true},
      {"predicted_rmse_noise_free", kExact, "", true},
      {"predicted_sigma", kExact, "", true},
      {"snr_level100", kExact, ""},
      {"predicted_exact", kExact, ""},
      {"regularization_applied", kExact, ""},
      {"prior_level", kExact, "", true},
      {"noise_variance", kExact, "", true},
      {"invertible", kExact, ""},
      {"status", kExact, ""},
      {"message", kProvenance, ""},
      {"fssim_version", kProvenance, ""},
      // Schema 4 (velocity distributions, docs/method.md §13).
      {"velocity_distribution", kSetting, ""},
      {"mse_mean", Role::kStatistic, "mse_sd"},
      {"mse_sd", Role::kSpread, "mse_mean"},
      {"predicted_mse", kExact, "", true},
  };
  return roles;
}

const ColumnRole* find(std::string_view name) {
  for (const ColumnRole& c : all()) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

std::string_view role_name(Role role) {
  switch (role) {
    case Role::kSetting:
      return "setting";
    case Role::kStatistic:
      return "statistic";
    case Role::kSpread:
      return "spread";
    case Role::kTrials:
      return "trials";
    case Role::kExact:
      return "exact";
    case Role::kDerived:
      return "derived";
    case Role::kProvenance:
      return "provenance";
  }
  return "";
}

// Wiener's power-law prior is fitted to one calibration observation with the row's seed; the
// oracle prior, Tikhonov's lambda (found on the noise-free observation) and the inverse filter
// are not.
bool fits_to_noise(std::string_view restoration, std::string_view prior) {
  return restoration == "wiener" && prior.substr(0, 9) == "power-law";
}

}  // namespace fss::column_roles

// The sensor and restoration keywords of fss.analyze_code and fss.optimize_code as the library's
// options, in plain C++ (no interpreter), checked as `fssim code analyze | optimize` checks
// --read-noise, --dark-current, --adc-bits, --adc-gain, --full-well, --restoration, --prior and
// --regularization, each refusal a usage fss::Error of one line naming the Python keyword.
#pragma once

#include <optional>
#include <string>

#include "fss/model/restoration.h"
#include "fss/model/sensor.h"

namespace fss::python {

struct DesignSensorArguments {
  double read_noise = 0.0;
  double dark_current = 0.0;
  long long adc_bits = 0;
  std::optional<double> adc_gain;   // empty: not given (1 electron per count)
  std::optional<double> full_well;  // refused when given: the figure of merit is linear
};

// The sensor of a code design (docs/method.md §10).
fss::SensorModel design_sensor(const DesignSensorArguments& arguments);

struct DesignRestorationArguments {
  std::string method = "inverse";
  std::optional<double> regularization;  // Tikhonov's lambda
  bool regularization_optimal = false;   // regularization='optimal'
  std::optional<std::string> prior;      // Wiener's, "power-law[:GAMMA[:C]]"
};

// The restoration the figure of merit assumes (docs/method.md §12).
fss::RestorationOptions design_restoration(const DesignRestorationArguments& arguments);

// Refuses a DFT grid (grid > 0) with a restoration other than the inverse filter, as
// `fssim code analyze --grid` does.
void check_design_grid(int grid, const fss::RestorationOptions& restoration);

// `message` of a library check (OptimizeOptions::IsValid, SensorModel::IsValid, ...) with the
// sensor's and restoration's fields named as the keywords.
std::string design_field_names(const std::string& message);

}  // namespace fss::python

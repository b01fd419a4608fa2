// The checks that a run's results stay in double precision: an error naming the settings,
// never a silent NaN or infinity. Internal to the library.
#pragma once

#include <string>

#include "fss/model/code.h"
#include "fss/pipeline/simulate.h"

namespace fss {

// "the gains of code 'c' (|gain| from a to b), dt x, snr y and read noise z e-": the settings
// whose scales multiply in a run's numbers (the sensor's parts that are on).
std::string scale_settings(const SimulationOptions& options, const ShutterCode& code);

// Extreme gains (1e-320, 1e308), dt, snr or sensor can leave the range of doubles: a usage
// fss::Error when a metric, a trial statistic, an observed value (`observed_finite` false) or a
// restored value is not finite.
void check_finite(const SimulationReport& report, const ShutterCode& code, bool observed_finite);

// The prediction of an invertible code is finite (docs/method.md §6): a usage fss::Error naming
// the settings where its terms leave double precision although the simulation did not.
void check_prediction_finite(const SimulationReport& report, const ShutterCode& code);

}  // namespace fss

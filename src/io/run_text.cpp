#include "io/run_text.h"

#include <cmath>
#include <sstream>

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

}  // namespace fss

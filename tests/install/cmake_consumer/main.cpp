// A consumer of the installed fss found with find_package(fss): loads the
// raskar code (built in, and from the installed code file given as argv[1]),
// checks its sums and K(0), and compares a measured RMSE with its prediction.
// Usage: cmake_consumer PREFIX/share/fssim/codes/raskar.txt
#include <cmath>
#include <complex>
#include <cstdio>
#include <exception>

#include "fss/core/error.h"
#include "fss/core/image.h"
#include "fss/model/code.h"
#include "fss/model/transfer.h"
#include "fss/pipeline/simulate.h"

namespace {

int failures = 0;

void check(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "cmake_consumer: FAILED: %s\n", what);
    ++failures;
  }
}

// The paper's raskar code: 26 open slots of 52, so sum alpha = 26 and, at
// v = 1, dt = 1, K(0) = dt sum alpha = 26.
void check_raskar(const char* installed_file) {
  const fss::ShutterCode raskar = fss::load_code("raskar");
  const fss::ShutterCode from_file = fss::load_code(installed_file);
  const double sum = fss::gain_sum(raskar.gains);
  const double k0 = std::abs(fss::transfer_function(raskar.gains, 1.0, 1.0, 0.0));
  std::printf("raskar: L = %d, sum of gains %g, |K(0)| %g\n", raskar.length(), sum, k0);
  check(raskar.length() == 52, "raskar has 52 gains");
  check(sum == 26.0, "raskar's gains sum to 26");
  check(k0 == 26.0, "|K(0)| of raskar is 26");
  check(from_file.gains == raskar.gains, "the installed raskar.txt holds the built-in gains");
}

// A constant landscape at level 100 through the snapshot code with Poisson
// noise: the restoration's error is the amplified noise alone, and its
// measured RMSE must match the prediction sqrt(m Q (100 / snr^2) M).
void check_prediction() {
  const fss::Image landscape(600, 32, 1, 100.0);
  fss::SimulationOptions options;
  options.seed = 7;
  options.threads = 2;
  const fss::SimulationReport report =
      fss::Simulate(options, landscape, *fss::builtin_code("snapshot"));
  const double measured = report.metrics.rmse;
  const double predicted = report.prediction.rmse;
  std::printf("snapshot, constant 100, snr 100: RMSE %.4f, predicted %.4f\n", measured, predicted);
  check(report.prediction.finite, "the snapshot's prediction is finite");
  check(report.prediction.rmse_noise_free < 1e-9, "no error without noise on a constant image");
  check(std::abs(measured / predicted - 1.0) < 0.1, "measured RMSE within 10% of the prediction");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: cmake_consumer PREFIX/share/fssim/codes/raskar.txt\n");
    return 2;
  }
  try {
    check_raskar(argv[1]);
    check_prediction();
  } catch (const fss::Error& error) {
    std::fprintf(stderr, "cmake_consumer: fss::Error: %s\n", error.what());
    return 1;
  }
  std::printf("cmake_consumer: %s\n", failures == 0 ? "ok" : "FAILED");
  return failures == 0 ? 0 : 1;
}

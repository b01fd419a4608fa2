// The transfer function of a flutter shutter code (docs/method.md §1).
#pragma once

#include <complex>
#include <span>
#include <vector>

namespace fss {

using Complex = std::complex<double>;

// sinc_h(theta) = sin(theta / 2) / (theta / 2), sinc_h(0) = 1.
double sinc_h(double theta);

// K(xi) = dt * sinc_h(theta) * sum_k alpha_k exp(-i theta (k + 1/2)),
// theta = xi * v * dt.
Complex transfer_function(std::span<const double> gains, double velocity, double dt, double xi);

// Frequency in radians per pixel of half-spectrum bin i of an N-point DFT,
// standard layout: frequency i for i < N/2, i - N otherwise (so the Nyquist
// bin of an even N is -pi).
double bin_frequency(int i, int n);

// K at the bins 0 .. N/2 of an N-point real DFT (FFTW r2c layout).
std::vector<Complex> transfer_function_bins(std::span<const double> gains, double velocity,
                                            double dt, int n);

// K_k of the elementary exposure of slot k (gain 1 at k, 0 elsewhere) at the
// same bins: dt * sinc_h(theta) * exp(-i theta (k + 1/2)).
std::vector<Complex> slot_transfer_function_bins(int k, double velocity, double dt, int n);

}  // namespace fss

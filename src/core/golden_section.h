// Golden-section search for the minimum of a unimodal function on an interval: the minimum of
// |K| (model/kernel.cpp), the Tikhonov lambda and the power-law prior's level
// (pipeline/fitted_restoration.cpp, design/restoration_figure.cpp). Internal to the library.
#pragma once

#include <cmath>
#include <utility>

namespace fss {

// (x, f(x)) of the smaller of the two inner points after at most `steps` steps, stopping once
// the bracket [a, b] is at most `tolerance` wide; each step keeps the part of the bracket that
// holds the smaller inner point and evaluates f once.
template <typename F>
std::pair<double, double> golden_section_minimum(const F& f, double a, double b, int steps,
                                                 double tolerance) {
  const double ratio = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = b - ratio * (b - a);
  double x2 = a + ratio * (b - a);
  double f1 = f(x1);
  double f2 = f(x2);
  for (int step = 0; step < steps && b - a > tolerance; ++step) {
    if (f1 <= f2) {
      b = x2;
      x2 = x1;
      f2 = f1;
      x1 = b - ratio * (b - a);
      f1 = f(x1);
    } else {
      a = x1;
      x1 = x2;
      f1 = f2;
      x2 = a + ratio * (b - a);
      f2 = f(x2);
    }
  }
  return f1 <= f2 ? std::make_pair(x1, f1) : std::make_pair(x2, f2);
}

}  // namespace fss

// The text files of a run in the reference program's formats: code.txt is
// format_code_txt (model/code.h), spectrum.txt is format_spectrum_txt.
#pragma once

#include <string>
#include <vector>

namespace fss {

// |K(xi)| for xi = -pi + j 2 pi / 100, j = 0 .. 99, "xi |K|" per line (the
// reference program's spectrum.txt; K is docs/method.md §1).
std::string format_spectrum_txt(const std::vector<double>& gains, double velocity, double dt);

}  // namespace fss

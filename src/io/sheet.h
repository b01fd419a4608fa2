// sheet.png of a run: its observed, restored and residual images in one
// picture.
#pragma once

#include <cstdint>
#include <vector>

#include "fss/core/image.h"
#include "fss/pipeline/simulate.h"

namespace fss {

// sheet.png: the observed, restored and residual images side by side under a
// title naming the code, the parameters and the measured errors, the
// residual on a symmetric scale drawn under it; `input` is the image the
// report was made from. A usage error when the report keeps no
// observed image (Simulate ran with an ObservedRowSink).
std::vector<std::uint8_t> figure_sheet_png(const SimulationReport& report, const Image& input);

}  // namespace fss

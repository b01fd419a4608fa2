// Private to the plots (src/io/plot_*.cpp): the PLplot session that draws a
// picture into memory, its colour map, and the picture's pixels as samples.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "io/plplot_api.h"  // PLplot, loaded at the first picture

namespace fss::plotting {

// Colour map 0 of every picture.
enum Colour : PLINT {
  kBackground = 0,
  kInk = 1,        // axes, labels, text
  kGrid = 2,       // zero line and grid
  kCode = 3,       // the code's curve
  kCodeFill = 4,   // area under the gain function
  kReference = 5,  // the snapshot
  kMarker = 6,     // the minimum of |K|
  kWarning = 7,    // "not invertible"
  kSeries = 8,     // 8 .. 15: overlaid codes
};
inline constexpr int kPaletteSize = 16;
inline constexpr int kMaxSeries = kPaletteSize - kSeries;

// The red, green and blue (0 .. 255) of a Colour, for pictures drawn without PLplot (SVG).
std::array<int, 3> palette_rgb(PLINT colour);

// The cairo driver draws at 72 dots per inch; PLplot sizes text in mm.
inline constexpr double kPixelsPerMm = 72.0 / 25.4;

// Draws `draw` over `rgba` (width x height RGBA, rows top down): one PLplot
// stream drawn by the memcairo device over the caller's buffer, under one
// process-wide mutex (PLplot keeps global state). PLplot's recoverable errors
// and anything a library prints on stderr meanwhile (PLplot's warnings,
// GLib's) fail the picture with that text, and never reach stderr; so does a
// fatal PLplot error, instead of ending the process. The first call loads PLplot
// (plplot_api.h): an fss::Error when it is not installed.
void render(int width, int height, std::vector<std::uint8_t>& rgba,
            const std::function<void()>& draw);

// The RGBA buffer as interleaved RGB, or gray, 8-bit samples; gray is the
// rounded mean of red, green and blue.
std::vector<std::uint8_t> to_samples(const std::vector<std::uint8_t>& rgba, int channels);

}  // namespace fss::plotting

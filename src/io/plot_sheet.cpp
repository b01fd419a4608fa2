// The figure sheet (fss/io/plot.h): a run's images side by side under
// their captions.
#include <algorithm>
#include <string>
#include <vector>

#include "fss/core/error.h"
#include "fss/io/plot.h"
#include "fss/io/png_io.h"
#include "io/plot_backend.h"
#include "io/plot_draw.h"

namespace fss {

using plotting::Canvas;
using plotting::ellipsize;
using plotting::literal;
using plotting::render;
using plotting::to_samples;
using enum plotting::Colour;

namespace {

// Width of a figure sheet of `panels`; a usage error unless they can make one.
int sheet_width(const std::vector<SheetPanel>& panels) {
  if (panels.empty()) throw_usage_error("a figure sheet needs at least one image");
  const int height = panels[0].image != nullptr ? panels[0].image->height : 0;
  const int channels = panels[0].image != nullptr ? panels[0].image->channels : 0;
  int width = kSheetMargin;
  for (const SheetPanel& panel : panels) {
    const Image* image = panel.image;
    if (image == nullptr || image->width <= 0 || image->height != height ||
        image->channels != channels || (channels != 1 && channels != 3) ||
        image->data.size() != image->plane_size() * channels) {
      throw_usage_error(
          "the images of a figure sheet must be non-empty, of equal heights and of equal channel "
          "counts (1 or 3)");
    }
    width += image->width + kSheetMargin;
  }
  return width;
}

// Copies the panels into `rgba` (`width` pixels a row) below the header, a
// margin apart; returns the x of their centres.
std::vector<double> paste_panels(const std::vector<SheetPanel>& panels, int width,
                                 std::vector<std::uint8_t>& rgba) {
  std::vector<double> centres;
  int left = kSheetMargin;
  for (const SheetPanel& panel : panels) {
    const Image& image = *panel.image;
    for (int y = 0; y < image.height; ++y) {
      std::uint8_t* row =
          &rgba[(static_cast<std::size_t>(kSheetHeaderHeight + y) * width + left) * 4];
      for (int x = 0; x < image.width; ++x) {
        for (int c = 0; c < 3; ++c) {
          row[4 * x + c] = png8_sample(image.at(image.channels == 1 ? 0 : c, y, x));
        }
      }
    }
    centres.push_back(left + image.width / 2.0);
    left += image.width + kSheetMargin;
  }
  return centres;
}

}  // namespace

std::vector<std::uint8_t> figure_sheet_png(const std::vector<SheetPanel>& panels,
                                           const std::string& title) {
  const int width = sheet_width(panels);
  const int height = panels[0].image->height, channels = panels[0].image->channels;
  const int sheet_height = kSheetHeaderHeight + height + kSheetMargin;
  if (width > 32767 || sheet_height > 32767) {
    throw_usage_error("a figure sheet of " + std::to_string(width) + "x" +
                      std::to_string(sheet_height) + " pixels is too large (32767 at most)");
  }
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(width) * sheet_height * 4, 255);
  const std::vector<double> centres = paste_panels(panels, width, rgba);
  render(width, sheet_height, rgba, [&] {
    const Canvas canvas(width, sheet_height);
    // About 7.5 pixels per character at this size: cut what would not fit.
    const auto fit = [](const std::string& text, double pixels) {
      return literal(ellipsize(text, static_cast<std::size_t>(std::max(4.0, pixels / 7.5))));
    };
    canvas.text(kSheetMargin, 14.0, 0.0, 13.0, kInk, fit(title, width - 2.0 * kSheetMargin));
    for (std::size_t i = 0; i < panels.size(); ++i) {
      canvas.text(centres[i], kSheetHeaderHeight - 12.0, 0.5, 13.0, kInk,
                  fit(panels[i].caption, panels[i].image->width));
    }
  });
  return encode_png8_samples(width, sheet_height, channels, to_samples(rgba, channels));
}

}  // namespace fss

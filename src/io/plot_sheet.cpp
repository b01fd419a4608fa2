// The figure sheet (fss/io/plot.h): a run's images side by side under
// their captions, a panel's gray scale under it.
#include <algorithm>
#include <cmath>
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
using plotting::number;
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

// Where the gray bar of a panel of `panel_width` pixels centred at `centre`
// goes: its left and right pixel columns, and its top row.
struct ScaleBar {
  int left = 0;
  int right = 0;  // one past the last column
  int top = 0;
};

ScaleBar scale_bar(double centre, int panel_width, int panel_height) {
  const int width = std::max(2, std::min(360, panel_width - 48));
  const int left = static_cast<int>(std::lround(centre - width / 2.0));
  return {left, left + width, kSheetHeaderHeight + panel_height + kSheetMargin + 4};
}

constexpr int kScaleBarHeight = 12;

// Fills the bar of each panel with a scale in `rgba` (`width` pixels a row)
// with its gray ramp, black at its left end, white at its right.
void paste_scale_bars(const std::vector<SheetPanel>& panels, const std::vector<double>& centres,
                      int width, std::vector<std::uint8_t>& rgba) {
  for (std::size_t i = 0; i < panels.size(); ++i) {
    if (!panels[i].scale) continue;
    const ScaleBar bar = scale_bar(centres[i], panels[i].image->width, panels[i].image->height);
    for (int y = bar.top; y < bar.top + kScaleBarHeight; ++y) {
      for (int x = bar.left; x < bar.right; ++x) {
        const double t = static_cast<double>(x - bar.left) / (bar.right - bar.left - 1);
        const auto gray = static_cast<std::uint8_t>(std::lround(255.0 * t));
        std::uint8_t* pixel = &rgba[(static_cast<std::size_t>(y) * width + x) * 4];
        pixel[0] = pixel[1] = pixel[2] = gray;
      }
    }
  }
}

// The frame, ticks, values and unit of a panel's gray bar (PLplot, inside
// render): 5 values on a bar of 240 pixels or more, 3 on one of 60, else its
// two ends.
void draw_scale(const Canvas& canvas, const SheetScale& scale, const ScaleBar& bar) {
  const double h = canvas.height();
  const double top = h - bar.top, bottom = h - (bar.top + kScaleBarHeight);
  canvas.pixel_window();
  plcol0(kInk);
  plwidth(1.0);
  pllsty(1);
  PLFLT fx[5] = {static_cast<PLFLT>(bar.left), static_cast<PLFLT>(bar.right),
                 static_cast<PLFLT>(bar.right), static_cast<PLFLT>(bar.left),
                 static_cast<PLFLT>(bar.left)};
  PLFLT fy[5] = {top, top, bottom, bottom, top};
  plline(5, fx, fy);
  const int span = bar.right - bar.left;
  const int ticks = span >= 240 ? 5 : span >= 60 ? 3 : 2;
  for (int k = 0; k < ticks; ++k) {
    const double t = static_cast<double>(k) / (ticks - 1);
    const double x = bar.left + t * span;
    canvas.pixel_window();
    plcol0(kInk);
    pljoin(x, bottom, x, bottom - 4.0);
    const double value = scale.black + t * (scale.white - scale.black);
    // "−" (U+2212) for negative values, as typeset.
    std::string text = number("%g", std::abs(value) < 1e-12 * std::abs(scale.white) ? 0.0 : value);
    if (text[0] == '-') text = "−" + text.substr(1);
    canvas.text(x, bar.top + kScaleBarHeight + 12.0, 0.5, 12.0, kInk, text);
  }
  canvas.text((bar.left + bar.right) / 2.0, bar.top + kScaleBarHeight + 30.0, 0.5, 12.0, kInk,
              literal(scale.unit));
}

}  // namespace

std::vector<std::uint8_t> figure_sheet_png(const std::vector<SheetPanel>& panels,
                                           const std::string& title) {
  const int width = sheet_width(panels);
  const int height = panels[0].image->height, channels = panels[0].image->channels;
  for (const SheetPanel& panel : panels) {
    if (panel.scale && !(std::isfinite(panel.scale->black) && std::isfinite(panel.scale->white) &&
                         panel.scale->black != panel.scale->white)) {
      throw_usage_error(
          "the scale of a figure sheet panel needs finite, different values at black and white");
    }
  }
  const bool scales = std::any_of(panels.begin(), panels.end(),
                                  [](const SheetPanel& panel) { return panel.scale.has_value(); });
  const int sheet_height =
      kSheetHeaderHeight + height + kSheetMargin + (scales ? kSheetScaleHeight : 0);
  if (width > 32767 || sheet_height > 32767) {
    throw_usage_error("a figure sheet of " + std::to_string(width) + "x" +
                      std::to_string(sheet_height) + " pixels is too large (32767 at most)");
  }
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(width) * sheet_height * 4, 255);
  const std::vector<double> centres = paste_panels(panels, width, rgba);
  paste_scale_bars(panels, centres, width, rgba);
  render(width, sheet_height, rgba, [&] {
    const Canvas canvas(width, sheet_height);
    // At most 9 pixels per character at this size (digits and capitals are
    // the widest): cut what would not fit.
    const auto fit = [](const std::string& text, double pixels) {
      return literal(ellipsize(text, static_cast<std::size_t>(std::max(4.0, pixels / 9.0))));
    };
    canvas.text(kSheetMargin, 14.0, 0.0, 13.0, kInk, fit(title, width - 2.0 * kSheetMargin));
    for (std::size_t i = 0; i < panels.size(); ++i) {
      canvas.text(centres[i], kSheetHeaderHeight - 12.0, 0.5, 13.0, kInk,
                  fit(panels[i].caption, panels[i].image->width));
      if (panels[i].scale) {
        SheetScale scale = *panels[i].scale;
        scale.unit = ellipsize(
            scale.unit, static_cast<std::size_t>(std::max(4.0, panels[i].image->width / 9.0)));
        draw_scale(canvas, scale,
                   scale_bar(centres[i], panels[i].image->width, panels[i].image->height));
      }
    }
  });
  return encode_png8_samples(width, sheet_height, channels, to_samples(rgba, channels));
}

}  // namespace fss

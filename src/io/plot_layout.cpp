// The text widths, text fitting and axis ticks of the plots (plot_layout.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "io/plot_layout.h"

namespace fss::plotting {

namespace {

// Advance widths of DejaVu Sans, in thousandths of an em, of the characters 32 (space) to 126
// (tilde).
constexpr int kAsciiWidths[95] = {318,  401, 460, 838, 636, 950, 780, 275,
                                  390,  390, 500, 838, 318, 361, 318, 337,  //  !"#$%&'()*+,-./
                                  636,  636, 636, 636, 636, 636, 636, 636,
                                  636,  636, 337, 337, 838, 838, 838, 531,  // 0-9 :;<=>?
                                  1000, 684, 686, 698, 770, 632, 575, 775,
                                  752,  295, 295, 656, 557, 863, 748, 787,  // @A-O
                                  603,  787, 695, 635, 611, 732, 684, 989,
                                  685,  611, 685, 390, 337, 390, 838, 500,  // P-Z [\]^_
                                  500,  613, 635, 550, 635, 615, 352, 635,
                                  634,  278, 278, 579, 278, 974, 634, 612,  // `a-o
                                  635,  635, 411, 521, 392, 634, 592, 818,
                                  592,  592, 525, 636, 337, 636, 838};  // p-z {|}~

// Allowance for a renderer's rounding and kerning, over the advance widths.
constexpr double kWidthAllowance = 1.04;

// The code points of UTF-8 text, each as its bytes.
std::vector<std::string> characters_of(std::string_view text) {
  std::vector<std::string> out;
  for (const char c : text) {
    if ((static_cast<unsigned char>(c) & 0xC0) != 0x80 || out.empty()) {
      out.emplace_back(1, c);
    } else {
      out.back() += c;
    }
  }
  return out;
}

std::string join(const std::vector<std::string>& characters, std::size_t begin, std::size_t end) {
  std::string out;
  for (std::size_t i = begin; i < end; ++i) out += characters[i];
  return out;
}

// `text` without spaces at its ends.
std::string trimmed(const std::string& text) {
  const std::size_t first = text.find_first_not_of(' ');
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(' ') - first + 1);
}

// The most even cut of `text` into two lines no wider than `width` at `size`: after one of the
// `breaks` (the break kept on the first line, the spaces after it dropped), or, with `anywhere`,
// between any two characters. Empty when no cut fits.
std::vector<std::string> two_lines(const std::string& text, double width, double size,
                                   const std::vector<std::string_view>& breaks, bool anywhere) {
  std::vector<std::string> best;
  double best_width = HUGE_VAL;
  const auto consider = [&](const std::string& first, const std::string& second) {
    const double wider = std::max(text_width(first, size), text_width(second, size));
    if (first.empty() || second.empty() || wider > width || wider >= best_width) return;
    best = {first, second};
    best_width = wider;
  };
  for (const std::string_view mark : breaks) {
    for (std::size_t at = text.find(mark); at != std::string::npos; at = text.find(mark, at + 1)) {
      const std::size_t end = at + mark.size();
      consider(trimmed(text.substr(0, end)), trimmed(text.substr(end)));
    }
    if (!best.empty()) return best;
  }
  if (anywhere) {
    const std::vector<std::string> chars = characters_of(text);
    for (std::size_t i = 1; i < chars.size(); ++i) {
      consider(join(chars, 0, i), join(chars, i, chars.size()));
    }
  }
  return best;
}

// `text` in at most `max_lines` lines at `size`, or empty lines when it does not fit.
std::vector<std::string> lines_at(const std::string& text, double width, double size, int max_lines,
                                  bool anywhere) {
  if (text_width(text, size) <= width) return {text};
  if (max_lines < 2) return {};
  return two_lines(text, width, size, {"; ", ", ", " "}, anywhere);
}

// `text` cut short in its middle (an ellipsis for the characters left out) so that it fits.
std::vector<std::string> cut_to_fit(const std::string& text, double width, double size,
                                    int max_lines) {
  const std::vector<std::string> chars = characters_of(text);
  const auto cut = [&](std::size_t kept) {
    return join(chars, 0, (kept + 1) / 2) + "…" +
           join(chars, chars.size() - kept / 2, chars.size());
  };
  std::size_t low = 0, high = chars.size();  // cut(low) fits; find the largest kept count
  while (low < high) {
    const std::size_t mid = (low + high + 1) / 2;
    if (!lines_at(cut(mid), width, size, max_lines, true).empty()) {
      low = mid;
    } else {
      high = mid - 1;
    }
  }
  std::vector<std::string> lines = lines_at(cut(low), width, size, max_lines, true);
  return lines.empty() ? std::vector<std::string>{"…"} : lines;
}

// The label of m × 10^k: plain decimals from 0.001 to 90000 (0.5, 1, 20, 400), else m×10^k
// (m = 1: 10^k).
Tick power_tick(double value, int multiple, int power) {
  if (power >= -3 && power <= 4) {
    const std::string digits = std::to_string(multiple);
    if (power >= 0) return {value, digits + std::string(static_cast<std::size_t>(power), '0'), ""};
    return {value, "0." + std::string(static_cast<std::size_t>(-power - 1), '0') + digits, ""};
  }
  return {value, multiple == 1 ? "10" : std::to_string(multiple) + "×10", std::to_string(power)};
}

}  // namespace

double text_width(std::string_view text, double size) {
  double ems = 0.0;
  for (const std::string& c : characters_of(text)) {
    const auto byte = static_cast<unsigned char>(c[0]);
    ems += byte >= 32 && byte < 127 ? kAsciiWidths[byte - 32] / 1000.0 : 1.0;
  }
  return ems * size * kWidthAllowance;
}

TextBlock fit_text(const std::string& text, double width, double size, double min_size,
                   int max_lines) {
  for (double s = size; s >= min_size; s -= 1.0) {
    std::vector<std::string> lines = lines_at(text, width, s, max_lines, s - 1.0 < min_size);
    if (!lines.empty()) return {lines, s};
  }
  return {cut_to_fit(text, width, min_size, max_lines), min_size};
}

double tick_label_width(const Tick& tick, double size) {
  return text_width(tick.label, size) + 0.75 * text_width(tick.exponent, size);
}

std::vector<Tick> log_ticks(double low, double high) {
  const double lo = low * (1.0 - 1e-9), hi = high * (1.0 + 1e-9);
  const int first = static_cast<int>(std::floor(std::log10(low)));
  const int last = static_cast<int>(std::ceil(std::log10(high)));
  const auto in_range = [&](int m, int k) {
    return m * std::pow(10.0, k) >= lo && m * std::pow(10.0, k) <= hi;
  };
  // Labelled multiples of each power: 1; else 1, 2, 5.
  const std::vector<std::vector<int>> label_sets = {{1}, {1, 2, 5}};
  std::vector<int> labelled;
  int labels = 0;
  for (const std::vector<int>& set : label_sets) {
    labelled = set;
    labels = 0;
    for (int k = first; k <= last; ++k) {
      for (const int m : set) labels += in_range(m, k);
    }
    if (labels >= 3) break;
  }
  if (labels < 3) return linear_ticks(low, high, 4);  // about a decade or less: plain steps
  const bool minor = std::log10(high / low) < 6.0;
  std::vector<Tick> ticks;
  for (int k = first; k <= last; ++k) {
    for (int m = 1; m <= 9; ++m) {
      if (!in_range(m, k)) continue;
      if (std::find(labelled.begin(), labelled.end(), m) != labelled.end()) {
        ticks.push_back(power_tick(m * std::pow(10.0, k), m, k));
      } else if (minor) {
        ticks.push_back({m * std::pow(10.0, k), "", ""});
      }
    }
  }
  return ticks;
}

std::vector<Tick> linear_ticks(double low, double high, int target) {
  const double span = high - low;
  if (!(span > 0.0)) return {};
  const double raw = span / target, power = std::pow(10.0, std::floor(std::log10(raw)));
  const int multiple = raw / power < 1.5 ? 1 : raw / power < 3.5 ? 2 : raw / power < 7.5 ? 5 : 10;
  const double step = multiple * power;
  const int decimals = std::max(0, -static_cast<int>(std::floor(std::log10(step) + 1e-9)));
  std::vector<Tick> ticks;
  for (double i = std::ceil(low / step - 1e-9); i * step <= high + 1e-9 * span; i += 1.0) {
    const double value = i * step;
    char text[64];
    if (std::abs(value) >= 1e6) {
      std::snprintf(text, sizeof text, "%g", value);
    } else {
      std::snprintf(text, sizeof text, "%.*f", decimals, value == 0.0 ? 0.0 : value);
    }
    ticks.push_back({value, text, ""});
  }
  // A step that leaves fewer than 3 ticks (target small for its span): the next finer one.
  if (ticks.size() < 3 && target < 64) return linear_ticks(low, high, 2 * target);
  return ticks;
}

double AxisLayout::pixel(double value) const {
  const double t =
      log ? (std::log10(value) - std::log10(low)) / (std::log10(high) - std::log10(low))
          : (value - low) / (high - low);
  return pixel_low + t * (pixel_high - pixel_low);
}

}  // namespace fss::plotting

#include "fss/campaign/figures.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <map>
#include <string_view>

#include "campaign/campaign_text.h"
#include "fss/core/error.h"
#include "fss/io/plot.h"

namespace fss {

namespace {

// One swept quantity of a campaign.
struct Axis {
  const char* name;   // in file names and labels
  const char* label;  // x axis label
  int Setting::*field;
  std::vector<double> values;
  bool log;
};

std::vector<Axis> swept_axes(const ResolvedCampaign& c) {
  std::vector<double> restore;
  for (const auto& r : c.restore_velocities) restore.push_back(r.value_or(std::nan("")));
  std::vector<Axis> axes = {
      {"velocity", "velocity (pixels per time slot)", &Setting::velocity, c.velocities.values,
       c.velocities.geometric},
      {"restore_velocity", "restore velocity (pixels per time slot)", &Setting::restore_velocity,
       restore, c.restore_geometric},
      {"snr", "snr", &Setting::snr, c.snrs.values, true},
      {"dt", "dt (time slot length)", &Setting::dt, c.dts.values, c.dts.geometric},
      {"read_noise", "read noise (electrons RMS per readout)", &Setting::read_noise,
       c.read_noises.values, c.read_noises.geometric}};
  std::vector<Axis> swept;
  for (Axis& a : axes) {
    if (a.values.size() < 2) continue;
    a.log =
        a.log && std::all_of(a.values.begin(), a.values.end(), [](double v) { return v > 0.0; });
    swept.push_back(a);
  }
  return swept;
}

std::string fixed_settings(const ResolvedCampaign& c, const Setting& s, const Axis& axis) {
  using campaign_text::shortest;
  std::string text = c.images[s.image].name;
  const auto slash = text.rfind('/');
  if (slash != std::string::npos) text = text.substr(slash + 1);
  text += ", " + to_string(c.modes[s.mode]);
  const auto add = [&](const char* name, const char* label, const std::string& value) {
    if (std::string(axis.name) != name) text += std::string(", ") + label + " " + value;
  };
  if (s.velocity_distribution >= 0) {
    text += ", v ~ " + c.velocity_distributions[s.velocity_distribution].name;
  } else {
    add("velocity", "v", shortest(c.velocities.values[s.velocity]));
  }
  if (const auto& r = c.restore_velocities[s.restore_velocity])
    add("restore_velocity", "v_r", shortest(*r));
  add("snr", "snr", shortest(c.snrs.values[s.snr]));
  add("dt", "dt", shortest(c.dts.values[s.dt]));
  if (c.has_sensor()) add("read_noise", "read noise", shortest(c.read_noises.values[s.read_noise]));
  // One restoration other than the inverse filter: named here, not on each curve.
  if (c.restorations.size() == 1 && c.has_restorations()) {
    text += ", " + describe(c.restorations.front());
  }
  return text;
}

// A curve's name: its code, and its restoration when the campaign has several.
std::string curve_name(const ResolvedCampaign& c, const Setting& s) {
  std::string name = c.codes[s.code].name;
  if (c.restorations.size() > 1) name += ": " + describe(c.restorations[s.restoration]);
  return name;
}

// The curves of one figure: for each code, y and error at each x.
struct FigureData {
  std::string title;
  std::vector<double> x;  // sorted
  std::vector<ErrorBarSeries> series;
  bool log_x = false;
  std::string x_label;
  std::string y_label;
};

// The quantity a figure plots: the mean RMSE of the trials, or, in a campaign with velocity
// distributions, sqrt(mean MSE) of the trials, the estimate of sqrt(E[MSE]) that the prediction
// gives (docs/method.md §13; the mean RMSE is below it, Jensen), with the same error bars.
const char* y_quantity(const ResolvedCampaign& c) {
  return c.has_velocity_distributions() ? "sqrt(mean MSE)" : "RMSE";
}

std::string y_label(const ResolvedCampaign& c) {
  return c.has_velocity_distributions() ? "sqrt(mean MSE) (gray levels), ± sd of the RMSE"
                                        : "RMSE (gray levels), mean ± sd";
}

double cell_number(const ResultRow& row, const char* column) {
  const std::string& text = row[campaign_column_index(column)];
  if (text.empty()) return std::nan("");
  return std::strtod(text.c_str(), nullptr);
}

// SVG of a figure, drawn directly: axes, ticks, curves, error bars, legend.
std::string figure_svg(const FigureData& f);

}  // namespace

namespace {

std::string figure_title(const ResolvedCampaign& c, const Setting& s, const Axis& axis) {
  const std::string margin =
      c.rmse_margin_columns < 0 ? std::string("3B") : std::to_string(c.rmse_margin_columns);
  return std::string(y_quantity(c)) + " vs " + axis.name + ": " + fixed_settings(c, s, axis) +
         "; " + std::to_string(c.trials) + (c.trials == 1 ? " trial" : " trials") + ", margin " +
         margin;
}

// The figures of one axis, keyed by the other settings (and the block of
// curves): each curve (a code, and a restoration when there are several)
// gets the ok rows' mean RMSE and sd.
std::map<std::vector<int>, FigureData> axis_figures(const ResolvedCampaign& c,
                                                    const std::vector<ResultRow>& rows,
                                                    const Axis& axis) {
  const int status = campaign_column_index("status");
  std::map<std::vector<int>, FigureData> groups;
  std::map<std::vector<int>, std::map<int, std::size_t>> curve_series;
  const int variants = static_cast<int>(c.restorations.size());
  std::vector<double> xs = axis.values;
  std::sort(xs.begin(), xs.end());
  xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    Setting s = setting_at(c, static_cast<long long>(i));
    const double x = axis.values[s.*axis.field];
    s.*axis.field = 0;
    const int curve = s.code * variants + s.restoration;
    const std::vector<int> key = {
        s.image, s.mode, s.velocity,   s.velocity_distribution,    s.restore_velocity,
        s.snr,   s.dt,   s.read_noise, curve / kMaxCurvesPerFigure};
    FigureData& f = groups[key];
    if (f.x.empty()) f = {figure_title(c, s, axis), xs, {}, axis.log, axis.label, y_label(c)};
    auto [it, added] = curve_series[key].try_emplace(curve, f.series.size());
    if (added) {
      f.series.push_back({curve_name(c, s), std::vector<double>(xs.size(), std::nan("")),
                          std::vector<double>(xs.size(), std::nan(""))});
    }
    const auto j = static_cast<std::size_t>(std::lower_bound(xs.begin(), xs.end(), x) - xs.begin());
    if (rows[i][status] == kStatusOk) {
      f.series[it->second].y[j] = c.has_velocity_distributions()
                                      ? std::sqrt(cell_number(rows[i], "mse_mean"))
                                      : cell_number(rows[i], "rmse_mean");
      f.series[it->second].error[j] = cell_number(rows[i], "rmse_sd");
    }
  }
  return groups;
}

}  // namespace

std::vector<CampaignFigure> campaign_figures(const ResolvedCampaign& c,
                                             const std::vector<ResultRow>& rows) {
  if (static_cast<long long>(rows.size()) != c.setting_count()) {
    throw_usage_error("campaign figures need every row of the campaign");
  }
  std::vector<CampaignFigure> figures;
  for (const Axis& axis : swept_axes(c)) {
    int n = 0;
    for (const auto& entry : axis_figures(c, rows, axis)) {
      const FigureData& f = entry.second;
      if (static_cast<int>(figures.size()) >= kMaxCampaignFigures) return figures;
      PlotOptions options;
      options.width = 800;
      options.height = 500;
      options.title = f.title;
      figures.push_back(
          {"rmse_vs_" + std::string(axis.name) + "_" + std::to_string(++n),
           plot_error_bar_curves_png(f.x, f.series, f.x_label, f.y_label, f.log_x, options),
           figure_svg(f)});
    }
  }
  return figures;
}

namespace {

constexpr double kPlotLeft = 80, kPlotRight = 780, kPlotTop = 50, kPlotBottom = 440;
const char* const kColours[] = {"#1f5caa", "#d67814", "#28963c", "#963caa",
                                "#14a0b4", "#c81e1e", "#8c6e28", "#6e6e6e"};

std::string svg_escape(const std::string& text) {
  std::string out;
  for (const char ch : text) {
    if (ch == '&') {
      out += "&amp;";
    } else if (ch == '<') {
      out += "&lt;";
    } else if (ch == '>') {
      out += "&gt;";
    } else {
      out += ch;
    }
  }
  return out;
}

std::string fixed(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.2f", v);
  return buffer;
}

// "Nice" ticks over [low, high]: steps of 1, 2 or 5 times a power of ten.
std::vector<double> ticks(double low, double high) {
  const double span = high - low;
  if (!(span > 0.0)) return {low};
  const double raw = span / 6.0, power = std::pow(10.0, std::floor(std::log10(raw)));
  const double step = raw / power < 2 ? 2 * power : raw / power < 5 ? 5 * power : 10 * power;
  std::vector<double> t;
  const double first = std::ceil(low / step);
  for (int i = 0; first + i <= high / step + 1e-9 * span / step; ++i)
    t.push_back((first + i) * step);
  return t;
}

// The figure's coordinates: data to SVG pixels.
class SvgFrame {
 public:
  explicit SvgFrame(const FigureData& f) : log_x_(f.log_x) {
    y_low_ = HUGE_VAL;
    y_high_ = -HUGE_VAL;
    for (const ErrorBarSeries& s : f.series) {
      for (std::size_t j = 0; j < s.y.size(); ++j) {
        if (!std::isfinite(s.y[j])) continue;
        const double e = std::isfinite(s.error[j]) ? s.error[j] : 0.0;
        y_low_ = std::min(y_low_, s.y[j] - e);
        y_high_ = std::max(y_high_, s.y[j] + e);
      }
    }
    if (!(y_low_ <= y_high_)) y_low_ = 0.0, y_high_ = 1.0;
    const double pad = y_high_ > y_low_ ? 0.08 * (y_high_ - y_low_) : 0.1 * std::max(1.0, y_high_);
    y_low_ = std::max(0.0, y_low_ - pad);
    y_high_ += pad;
    x0_ = tx(f.x.front());
    x1_ = tx(f.x.back());
    x_pad_ = f.x.size() > 1 ? 0.04 * (x1_ - x0_) : 0.5;
  }
  double x(double value) const {
    return kPlotLeft +
           (tx(value) - x0_ + x_pad_) / (x1_ - x0_ + 2 * x_pad_) * (kPlotRight - kPlotLeft);
  }
  double y(double value) const {
    return kPlotBottom - (value - y_low_) / (y_high_ - y_low_) * (kPlotBottom - kPlotTop);
  }
  double y_low() const { return y_low_; }
  double y_high() const { return y_high_; }

 private:
  double tx(double value) const { return log_x_ ? std::log10(value) : value; }
  bool log_x_;
  double y_low_, y_high_, x0_ = 0, x1_ = 0, x_pad_ = 0;
};

void append(std::string& svg, std::initializer_list<std::string_view> parts) {
  for (const std::string_view part : parts) svg.append(part);
}

// Frame, ticks, tick labels and axis labels.
void svg_axes(std::string& svg, const FigureData& f, const SvgFrame& frame) {
  append(svg, {"<text x=\"430\" y=\"25\" text-anchor=\"middle\" font-size=\"14\">",
               svg_escape(f.title), "</text>\n",
               "<rect x=\"80\" y=\"50\" width=\"700\" height=\"390\" fill=\"none\" "
               "stroke=\"#222\"/>\n"});
  for (const double t : ticks(frame.y_low(), frame.y_high())) {
    const std::string y = fixed(frame.y(t)), label_y = fixed(frame.y(t) + 4);
    append(svg, {"<line x1=\"76\" x2=\"80\" y1=\"", y, "\" y2=\"", y, "\" stroke=\"#222\"/>",
                 "<text x=\"72\" y=\"", label_y, "\" text-anchor=\"end\">",
                 campaign_text::shortest(t), "</text>\n"});
  }
  for (const double value : f.x) {
    const std::string x = fixed(frame.x(value));
    append(svg, {"<line y1=\"440\" y2=\"444\" x1=\"", x, "\" x2=\"", x, "\" stroke=\"#222\"/>",
                 "<text y=\"458\" x=\"", x, "\" text-anchor=\"middle\">",
                 campaign_text::shortest(value), "</text>\n"});
  }
  append(svg, {"<text x=\"430\" y=\"485\" text-anchor=\"middle\">", svg_escape(f.x_label),
               f.log_x ? " (log scale)" : "", "</text>\n",
               "<text transform=\"translate(22 245) rotate(-90)\" text-anchor=\"middle\">",
               svg_escape(f.y_label), "</text>\n"});
}

// One code: error bars and markers, the polyline through its runs of
// values, and its legend entry (row i).
void svg_series(std::string& svg, const FigureData& f, const SvgFrame& frame, std::size_t i) {
  const ErrorBarSeries& s = f.series[i];
  const std::string colour = kColours[i % 8];
  std::string path;
  for (std::size_t j = 0; j < s.y.size(); ++j) {
    if (!std::isfinite(s.y[j])) {
      path += ' ';
      continue;
    }
    const std::string x = fixed(frame.x(f.x[j])), y = fixed(frame.y(s.y[j]));
    append(path, {path.empty() || path.back() == ' ' ? "M" : "L", x, ",", y});
    const double e = std::isfinite(s.error[j]) ? s.error[j] : 0.0;
    append(svg, {"<line x1=\"", x, "\" x2=\"", x, "\" y1=\"", fixed(frame.y(s.y[j] - e)),
                 "\" y2=\"", fixed(frame.y(s.y[j] + e)), "\" stroke=\"", colour, "\"/>",
                 "<circle cx=\"", x, "\" cy=\"", y, "\" r=\"3.5\" fill=\"", colour, "\"/>\n"});
  }
  const double legend_y = 70 + 18 * static_cast<double>(i);
  append(svg,
         {"<path d=\"", path, "\" fill=\"none\" stroke=\"", colour, "\" stroke-width=\"1.8\"/>\n",
          "<line x1=\"95\" x2=\"120\" y1=\"", fixed(legend_y), "\" y2=\"", fixed(legend_y),
          "\" stroke=\"", colour, "\" stroke-width=\"1.8\"/>", "<text x=\"126\" y=\"",
          fixed(legend_y + 4), "\">", svg_escape(s.name), "</text>\n"});
}

std::string figure_svg(const FigureData& f) {
  const SvgFrame frame(f);
  std::string svg =
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"800\" height=\"500\" "
      "viewBox=\"0 0 800 500\" font-family=\"sans-serif\" font-size=\"12\">\n"
      "<rect width=\"800\" height=\"500\" fill=\"white\"/>\n";
  svg_axes(svg, f, frame);
  for (std::size_t i = 0; i < f.series.size(); ++i) svg_series(svg, f, frame, i);
  return svg + "</svg>\n";
}

}  // namespace

}  // namespace fss

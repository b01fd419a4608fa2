#include "fss/campaign/figures.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

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
      {"dt", "dt (time slot length)", &Setting::dt, c.dts.values, c.dts.geometric}};
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
  add("velocity", "v", shortest(c.velocities.values[s.velocity]));
  if (const auto& r = c.restore_velocities[s.restore_velocity])
    add("restore_velocity", "v_r", shortest(*r));
  add("snr", "snr", shortest(c.snrs.values[s.snr]));
  add("dt", "dt", shortest(c.dts.values[s.dt]));
  return text;
}

// The curves of one figure: for each code, y and error at each x.
struct FigureData {
  std::string title;
  std::vector<double> x;  // sorted
  std::vector<ErrorBarSeries> series;
  bool log_x = false;
  std::string x_label;
};

double cell_number(const ResultRow& row, const char* column) {
  const std::string& text = row[campaign_column_index(column)];
  if (text.empty()) return std::nan("");
  return std::strtod(text.c_str(), nullptr);
}

// SVG of a figure, drawn directly: axes, ticks, curves, error bars, legend.
std::string figure_svg(const FigureData& f);

}  // namespace

std::vector<CampaignFigure> campaign_figures(const ResolvedCampaign& c,
                                             const std::vector<ResultRow>& rows) {
  if (static_cast<long long>(rows.size()) != c.setting_count()) {
    throw_usage_error("campaign figures need every row of the campaign");
  }
  const int status = campaign_column_index("status");
  std::vector<CampaignFigure> figures;
  for (const Axis& axis : swept_axes(c)) {
    // Group the rows by everything but the axis and the code.
    std::map<std::vector<int>, FigureData> groups;
    std::map<std::vector<int>, std::map<int, std::size_t>> code_series;
    std::vector<double> xs = axis.values;
    std::sort(xs.begin(), xs.end());
    xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
    for (std::size_t i = 0; i < rows.size(); ++i) {
      Setting s = setting_at(c, static_cast<long long>(i));
      const double x = axis.values[s.*axis.field];
      const int code = s.code;
      s.*axis.field = 0;
      const std::vector<int> key = {
          s.image, s.mode, s.velocity, s.restore_velocity, s.snr, s.dt, code / kMaxCodesPerFigure};
      FigureData& f = groups[key];
      if (f.x.empty()) {
        f.x = xs;
        f.log_x = axis.log;
        f.x_label = axis.label;
        f.title =
            "RMSE vs " + std::string(axis.name) + ": " + fixed_settings(c, s, axis) + "; " +
            std::to_string(c.trials) + (c.trials == 1 ? " trial" : " trials") + ", margin " +
            (c.rmse_margin_columns < 0 ? std::string("3B") : std::to_string(c.rmse_margin_columns));
      }
      auto [it, added] = code_series[key].try_emplace(code, f.series.size());
      if (added) {
        f.series.push_back({c.codes[code].name, std::vector<double>(xs.size(), std::nan("")),
                            std::vector<double>(xs.size(), std::nan(""))});
      }
      const std::size_t j = std::lower_bound(xs.begin(), xs.end(), x) - xs.begin();
      if (rows[i][status] == kStatusOk) {
        f.series[it->second].y[j] = cell_number(rows[i], "rmse_mean");
        f.series[it->second].error[j] = cell_number(rows[i], "rmse_sd");
      }
    }
    int n = 0;
    for (const auto& [key, f] : groups) {
      if (static_cast<int>(figures.size()) >= kMaxCampaignFigures) return figures;
      PlotOptions options;
      options.width = 800;
      options.height = 500;
      options.title = f.title;
      figures.push_back(
          {"rmse_vs_" + std::string(axis.name) + "_" + std::to_string(++n),
           plot_error_bar_curves_png(f.x, f.series, f.x_label, "RMSE (gray levels), mean ± sd",
                                     f.log_x, options),
           figure_svg(f)});
    }
  }
  return figures;
}

namespace {

constexpr double kSvgWidth = 800, kSvgHeight = 500;
constexpr double kPlotLeft = 80, kPlotRight = 780, kPlotTop = 50, kPlotBottom = 440;
const char* const kColours[] = {"#1f5caa", "#d67814", "#28963c", "#963caa",
                                "#14a0b4", "#c81e1e", "#8c6e28", "#6e6e6e"};

std::string svg_escape(const std::string& text) {
  std::string out;
  for (const char ch : text) {
    if (ch == '&')
      out += "&amp;";
    else if (ch == '<')
      out += "&lt;";
    else if (ch == '>')
      out += "&gt;";
    else
      out += ch;
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
  for (double v = std::ceil(low / step) * step; v <= high + 1e-9 * span; v += step) t.push_back(v);
  return t;
}

std::string figure_svg(const FigureData& f) {
  double y_low = HUGE_VAL, y_high = -HUGE_VAL;
  for (const ErrorBarSeries& s : f.series) {
    for (std::size_t j = 0; j < s.y.size(); ++j) {
      if (!std::isfinite(s.y[j])) continue;
      const double e = std::isfinite(s.error[j]) ? s.error[j] : 0.0;
      y_low = std::min(y_low, s.y[j] - e);
      y_high = std::max(y_high, s.y[j] + e);
    }
  }
  if (!(y_low <= y_high)) y_low = 0.0, y_high = 1.0;
  const double pad = y_high > y_low ? 0.08 * (y_high - y_low) : 0.1 * std::max(1.0, y_high);
  y_low = std::max(0.0, y_low - pad);
  y_high += pad;
  const auto tx = [&](double x) { return f.log_x ? std::log10(x) : x; };
  const double x0 = tx(f.x.front()), x1 = tx(f.x.back());
  const double x_pad = f.x.size() > 1 ? 0.04 * (x1 - x0) : 0.5;
  const auto sx = [&](double x) {
    return kPlotLeft + (tx(x) - x0 + x_pad) / (x1 - x0 + 2 * x_pad) * (kPlotRight - kPlotLeft);
  };
  const auto sy = [&](double y) {
    return kPlotBottom - (y - y_low) / (y_high - y_low) * (kPlotBottom - kPlotTop);
  };
  std::string svg =
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"800\" height=\"500\" "
      "viewBox=\"0 0 800 500\" font-family=\"sans-serif\" font-size=\"12\">\n";
  svg += "<rect width=\"800\" height=\"500\" fill=\"white\"/>\n";
  svg += "<text x=\"430\" y=\"25\" text-anchor=\"middle\" font-size=\"14\">" + svg_escape(f.title) +
         "</text>\n";
  svg += "<rect x=\"80\" y=\"50\" width=\"700\" height=\"390\" fill=\"none\" stroke=\"#222\"/>\n";
  for (const double t : ticks(y_low, y_high)) {
    svg += "<line x1=\"76\" x2=\"80\" y1=\"" + fixed(sy(t)) + "\" y2=\"" + fixed(sy(t)) +
           "\" stroke=\"#222\"/>";
    svg += "<text x=\"72\" y=\"" + fixed(sy(t) + 4) + "\" text-anchor=\"end\">" +
           campaign_text::shortest(t) + "</text>\n";
  }
  for (const double x : f.x) {
    svg += "<line y1=\"440\" y2=\"444\" x1=\"" + fixed(sx(x)) + "\" x2=\"" + fixed(sx(x)) +
           "\" stroke=\"#222\"/>";
    svg += "<text y=\"458\" x=\"" + fixed(sx(x)) + "\" text-anchor=\"middle\">" +
           campaign_text::shortest(x) + "</text>\n";
  }
  svg += "<text x=\"430\" y=\"485\" text-anchor=\"middle\">" + svg_escape(f.x_label) +
         (f.log_x ? " (log scale)" : "") + "</text>\n";
  svg +=
      "<text transform=\"translate(22 245) rotate(-90)\" text-anchor=\"middle\">RMSE (gray "
      "levels), mean ± sd</text>\n";
  for (std::size_t i = 0; i < f.series.size(); ++i) {
    const ErrorBarSeries& s = f.series[i];
    const std::string colour = kColours[i % 8];
    std::string path;
    for (std::size_t j = 0; j < s.y.size(); ++j) {
      if (!std::isfinite(s.y[j])) {
        path += " ";
        continue;
      }
      path += (path.empty() || path.back() == ' ' ? "M" : "L") + fixed(sx(f.x[j])) + "," +
              fixed(sy(s.y[j]));
      const double e = std::isfinite(s.error[j]) ? s.error[j] : 0.0;
      svg += "<line x1=\"" + fixed(sx(f.x[j])) + "\" x2=\"" + fixed(sx(f.x[j])) + "\" y1=\"" +
             fixed(sy(s.y[j] - e)) + "\" y2=\"" + fixed(sy(s.y[j] + e)) + "\" stroke=\"" + colour +
             "\"/>";
      svg += "<circle cx=\"" + fixed(sx(f.x[j])) + "\" cy=\"" + fixed(sy(s.y[j])) +
             "\" r=\"3.5\" fill=\"" + colour + "\"/>\n";
    }
    svg +=
        "<path d=\"" + path + "\" fill=\"none\" stroke=\"" + colour + "\" stroke-width=\"1.8\"/>\n";
    const std::string ly = fixed(70 + 18 * static_cast<double>(i));
    svg += "<line x1=\"95\" x2=\"120\" y1=\"" + ly + "\" y2=\"" + ly + "\" stroke=\"" + colour +
           "\" stroke-width=\"1.8\"/>";
    svg += "<text x=\"126\" y=\"" + fixed(70 + 18 * static_cast<double>(i) + 4) + "\">" +
           svg_escape(s.name) + "</text>\n";
  }
  return svg + "</svg>\n";
}

}  // namespace

}  // namespace fss

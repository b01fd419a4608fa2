#include "fss/campaign/figures.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <string_view>

#include "campaign/campaign_text.h"
#include "fss/core/error.h"
#include "fss/io/plot.h"

namespace fss {

namespace {

using campaign_text::shortest;

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

// The last part of a path: the file name of an image or of a code file.
std::string file_name(const std::string& path) {
  const auto slash = path.rfind('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

std::string fixed_settings(const ResolvedCampaign& c, const Setting& s, const Axis& axis) {
  std::string text = file_name(c.images[s.image].name) + ", " + to_string(c.modes[s.mode]);
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

// A series' name: its code (a code file by its file name), and its restoration when the
// campaign has several.
std::string curve_name(const ResolvedCampaign& c, const Setting& s) {
  std::string name = file_name(c.codes[s.code].name);
  if (c.restorations.size() > 1) name += ": " + describe(c.restorations[s.restoration]);
  return name;
}

// `text` for a file name: characters outside [A-Za-z0-9._-] become '-' (runs of them one),
// at most `limit` characters.
std::string file_part(std::string_view text, std::size_t limit = 40) {
  std::string out;
  for (const char ch : text) {
    const bool kept =
        std::isalnum(static_cast<unsigned char>(ch)) != 0 || ch == '.' || ch == '_' || ch == '-';
    if (kept) {
      out += ch;
    } else if (out.empty() || out.back() != '-') {
      out += '-';
    }
  }
  while (!out.empty() && out.back() == '-') out.pop_back();
  return out.substr(0, limit);
}

// The figure's file name: the swept quantity, the image's file name without its extension, the
// mode, then each other setting whose campaign has more than one value of it; the block of
// curves when there are more than kMaxCurvesPerFigure.
std::string figure_name(const ResolvedCampaign& c, const Setting& s, const Axis& axis, int block) {
  std::string image = file_name(c.images[s.image].name);
  if (const auto dot = image.rfind('.'); dot != std::string::npos && dot > 0) image.resize(dot);
  std::string name = "rmse_vs_" + std::string(axis.name) + "__" + file_part(image) + "__" +
                     file_part(to_string(c.modes[s.mode]));
  const auto add = [&](const char* quantity, std::size_t count, const std::string& part) {
    if (count > 1 && std::string_view(axis.name) != quantity) name += "__" + file_part(part);
  };
  if (s.velocity_distribution >= 0) {
    add("", c.velocity_distributions.size(),
        "v-" + c.velocity_distributions[s.velocity_distribution].name);
  } else {
    add("velocity", c.velocities.values.size(), "v" + shortest(c.velocities.values[s.velocity]));
  }
  if (const auto& r = c.restore_velocities[s.restore_velocity]) {
    add("restore_velocity", c.restore_velocities.size(), "vr" + shortest(*r));
  }
  add("snr", c.snrs.values.size(), "snr" + shortest(c.snrs.values[s.snr]));
  add("dt", c.dts.values.size(), "dt" + shortest(c.dts.values[s.dt]));
  add("read_noise", c.read_noises.values.size(),
      "rn" + shortest(c.read_noises.values[s.read_noise]));
  if (block > 0) {
    name += "__curves" + std::to_string(block * kMaxCurvesPerFigure + 1) + "-" +
            std::to_string((block + 1) * kMaxCurvesPerFigure);
  }
  return name.substr(0, 160);
}

// `name`, or name_2, name_3, ... : the first not in `taken`, which then holds it.
std::string unique_name(const std::string& name, std::set<std::string>& taken) {
  std::string unique = name;
  for (int n = 2; !taken.insert(unique).second; ++n) unique = name + "_" + std::to_string(n);
  return unique;
}

double cell_number(const ResultRow& row, const char* column) {
  const std::string& text = row[campaign_column_index(column)];
  if (text.empty()) return std::nan("");
  return std::strtod(text.c_str(), nullptr);
}

// One ok row as a point of its figure.
struct Point {
  double y;          // the mean RMSE; sqrt(mean MSE) under a velocity distribution
  double error;      // 1.96 standard errors of y; NaN with one trial
  double predicted;  // predicted_rmse; sqrt(predicted_mse) under a velocity distribution
  bool open;         // RMSE margin below 3B
};

// The point of an ok row. The standard error of the mean RMSE is sd / sqrt(n) over the n
// trials; that of sqrt(mean MSE) is, to first order (delta method), the standard error of the
// mean MSE divided by 2 sqrt(mean MSE). The rmse_margin cell holds the margin used in columns
// (-1: 3B, the default).
Point point_of(const ResolvedCampaign& c, const ResultRow& row) {
  const double trials = cell_number(row, "trials");
  const double root_n = trials > 1.0 ? std::sqrt(trials) : std::nan("");
  Point p{};
  if (c.has_velocity_distributions()) {
    p.y = std::sqrt(cell_number(row, "mse_mean"));
    p.error = 1.96 * cell_number(row, "mse_sd") / root_n / (2.0 * p.y);
    p.predicted = std::sqrt(cell_number(row, "predicted_mse"));
  } else {
    p.y = cell_number(row, "rmse_mean");
    p.error = 1.96 * cell_number(row, "rmse_sd") / root_n;
    p.predicted = cell_number(row, "predicted_rmse");
  }
  const double margin = cell_number(row, "rmse_margin");
  p.open = margin >= 0.0 && margin < 3.0 * cell_number(row, "blur_length");
  return p;
}

// One figure being gathered: its series by curve, and the statuses of the rows of each curve
// that is not ok.
struct FigureData {
  std::string title;
  std::string name;
  std::map<int, MeasuredSeries> series;
  std::map<int, std::vector<std::string>> statuses;
};

std::string figure_title(const ResolvedCampaign& c, const Setting& s, const Axis& axis) {
  const std::string margin = c.rmse_margin_columns == kRmseMarginDefault ? std::string("3B")
                             : c.rmse_margin_columns == kRmseMarginAuto
                                 ? std::string("auto")
                                 : std::to_string(c.rmse_margin_columns);
  return std::string(c.has_velocity_distributions() ? "sqrt(mean MSE)" : "RMSE") + " vs " +
         axis.name + ": " + fixed_settings(c, s, axis) + "; " + std::to_string(c.trials) +
         (c.trials == 1 ? " trial" : " trials") + ", margin " + margin;
}

// The figures of one axis, keyed by the other settings (and the block of curves), in the
// order of their keys.
std::map<std::vector<int>, FigureData> axis_figures(const ResolvedCampaign& c,
                                                    const std::vector<ResultRow>& rows,
                                                    const Axis& axis, std::vector<double>& xs) {
  const int status = campaign_column_index("status");
  std::map<std::vector<int>, FigureData> groups;
  const int variants = static_cast<int>(c.restorations.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    Setting s = setting_at(c, static_cast<long long>(i));
    const double x = axis.values[s.*axis.field];
    s.*axis.field = 0;
    const int curve = s.code * variants + s.restoration;
    const std::vector<int> key = {
        s.image, s.mode, s.velocity,   s.velocity_distribution,    s.restore_velocity,
        s.snr,   s.dt,   s.read_noise, curve / kMaxCurvesPerFigure};
    FigureData& f = groups[key];
    if (f.title.empty()) {
      f.title = figure_title(c, s, axis);
      f.name = figure_name(c, s, axis, key.back());
    }
    const auto j = static_cast<std::size_t>(std::lower_bound(xs.begin(), xs.end(), x) - xs.begin());
    if (rows[i][status] != kStatusOk) {
      f.statuses[curve].push_back(rows[i][status]);
      continue;
    }
    auto [it, added] = f.series.try_emplace(curve);
    MeasuredSeries& series = it->second;
    if (added) {
      const std::size_t n = xs.size();
      series = {curve_name(c, s),
                std::vector<double>(n, std::nan("")),
                std::vector<double>(n, std::nan("")),
                std::vector<double>(n, std::nan("")),
                std::vector<bool>(n, false),
                curve % kMaxCurvesPerFigure};
    }
    const Point p = point_of(c, rows[i]);
    series.measured[j] = p.y;
    series.error[j] = p.error;
    series.predicted[j] = p.predicted;
    series.open[j] = p.open;
  }
  return groups;
}

// The note of the series with no point: "no data: sinc, mip (code-refused); accumulation
// (not-invertible)", the statuses of their rows; empty when every series has a point.
std::string no_data_note(const ResolvedCampaign& c, const FigureData& f) {
  std::vector<std::pair<std::string, std::string>> by_status;  // status, names
  const int variants = static_cast<int>(c.restorations.size());
  for (const auto& [curve, statuses] : f.statuses) {
    if (f.series.count(curve) > 0) continue;
    Setting s{};
    s.code = curve / variants;
    s.restoration = curve % variants;
    std::string status = statuses.front();
    if (std::any_of(statuses.begin(), statuses.end(),
                    [&](const std::string& t) { return t != status; })) {
      status = "not ok";
    }
    auto it = std::find_if(by_status.begin(), by_status.end(),
                           [&](const auto& e) { return e.first == status; });
    if (it == by_status.end()) it = by_status.insert(by_status.end(), {status, ""});
    it->second += (it->second.empty() ? "" : ", ") + curve_name(c, s);
  }
  std::string note;
  for (const auto& [status, names] : by_status) {
    note += (note.empty() ? "no data: " : "; ") + names + " (" + status + ")";
  }
  return note;
}

// The figure of gathered data on the x values `xs`.
MeasuredFigure measured_figure(const ResolvedCampaign& c, const FigureData& f, const Axis& axis,
                               const std::vector<double>& xs) {
  MeasuredFigure figure;
  figure.x = xs;
  for (const auto& entry : f.series) figure.series.push_back(entry.second);
  figure.x_label = axis.label;
  figure.y_label =
      c.has_velocity_distributions() ? "sqrt(mean MSE) (gray levels)" : "RMSE (gray levels)";
  figure.log_x = axis.log;
  figure.points_key = std::string("measured: ") +
                      (c.has_velocity_distributions() ? "sqrt(mean MSE)" : "mean") +
                      (c.trials > 1 ? " ± 1.96 SE" : " (1 trial)");
  figure.predicted_key = "predicted";
  figure.open_key = "RMSE margin < 3B";
  if (const std::string note = no_data_note(c, f); !note.empty()) figure.notes.push_back(note);
  return figure;
}

}  // namespace

// The figures of a campaign: for each swept quantity, one figure per combination of the other
// settings, with one series per code (per code and restoration when the campaign has several;
// the same colour for one in every figure). Each point is a setting whose status is ok: its
// mean RMSE (sqrt of the mean MSE under a velocity distribution, the estimate of sqrt E[MSE],
// docs/method.md §13) with a bar of ± 1.96 standard errors of the trials (none with one
// trial), an open marker when its RMSE margin is below 3B; each line its prediction. A series
// without an ok row is left out (a note names it with its rows' status), and a figure without
// one is not drawn. Quantities with one value have no figure; beyond kMaxCampaignFigures the
// rest are left out, and curves beyond kMaxCurvesPerFigure start a new figure.
std::vector<CampaignFigureData> campaign_figure_data(const ResolvedCampaign& c,
                                                     const std::vector<ResultRow>& rows) {
  if (static_cast<long long>(rows.size()) != c.setting_count()) {
    throw_usage_error("campaign figures need every row of the campaign");
  }
  std::vector<CampaignFigureData> figures;
  std::set<std::string> names;
  for (const Axis& axis : swept_axes(c)) {
    std::vector<double> xs = axis.values;
    std::sort(xs.begin(), xs.end());
    xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
    for (const auto& entry : axis_figures(c, rows, axis, xs)) {
      const FigureData& f = entry.second;
      if (f.series.empty()) continue;
      if (static_cast<int>(figures.size()) >= kMaxCampaignFigures) return figures;
      figures.push_back({unique_name(f.name, names), f.title, measured_figure(c, f, axis, xs)});
    }
  }
  return figures;
}

std::vector<CampaignFigure> campaign_figures(const ResolvedCampaign& c,
                                             const std::vector<ResultRow>& rows) {
  std::vector<CampaignFigure> figures;
  for (const CampaignFigureData& data : campaign_figure_data(c, rows)) {
    const PlotOptions options{800, 500, data.title};
    figures.push_back({data.name, plot_measured_png(data.figure, options),
                       plot_measured_svg(data.figure, options)});
  }
  return figures;
}

}  // namespace fss

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "core/number_text.h"
#include "core/text_file.h"
#include "fss/core/error.h"
#include "fss/model/velocity_distribution.h"

namespace fss {

namespace {

// The white-space separated fields of `line` before any '#'.
std::vector<std::string_view> line_fields(std::string_view line) {
  line = line.substr(0, line.find('#'));
  std::vector<std::string_view> fields;
  std::size_t i = 0;
  const auto space = [](char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
  };
  while (i < line.size()) {
    while (i < line.size() && space(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !space(line[i])) ++i;
    if (i > start) fields.push_back(line.substr(start, i - start));
  }
  return fields;
}

std::vector<VelocityPoint> parse_velocity_lines(std::string_view text, const std::string& shown) {
  std::vector<VelocityPoint> points;
  int line_number = 0;
  for (std::size_t start = 0; start <= text.size();) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    ++line_number;
    const std::vector<std::string_view> fields = line_fields(text.substr(start, end - start));
    start = end + 1;
    if (fields.empty()) continue;
    const std::string where = "velocity file '" + shown + "', line " + std::to_string(line_number);
    if (fields.size() != 2) {
      throw_runtime_error(where + ": expected 'velocity weight' (two numbers), got " +
                          std::to_string(fields.size()) + " fields");
    }
    const double v = parse_finite_number(fields[0]);
    const double w = parse_finite_number(fields[1]);
    if (std::isnan(v) || std::isnan(w)) {
      throw_runtime_error(where + ": '" +
                          shorten_for_message(std::isnan(v) ? fields[0] : fields[1]) +
                          "' is not a finite number");
    }
    if (!(std::abs(v) <= kMaxDistributionVelocity) || !(w > 0.0)) {
      throw_runtime_error(where + ": velocity " + format_exact(v) + " with weight " +
                          format_exact(w) + " (expected |velocity| <= " +
                          format_exact(kMaxDistributionVelocity) + " and a weight > 0)");
    }
    if (points.size() >= static_cast<std::size_t>(kMaxDiscreteVelocities)) {
      throw_runtime_error(where + ": more than " + std::to_string(kMaxDiscreteVelocities) +
                          " velocities");
    }
    points.push_back({v, w});
  }
  if (points.empty()) {
    throw_runtime_error("velocity file '" + shown +
                        "' holds no velocity (expected 'velocity weight' lines)");
  }
  return points;
}

}  // namespace

VelocityDistribution load_velocity_distribution(const std::string& spec_or_path,
                                                const std::string& named_as) {
  const std::string shown = escape_control_characters(spec_or_path);
  const std::string_view kind = std::string_view(spec_or_path).substr(0, spec_or_path.find(':'));
  VelocityDistribution distribution;
  std::string error;
  if (kind == "uniform" || kind == "normal") {
    if (!parse_velocity_distribution(spec_or_path, &distribution, &error)) {
      throw_usage_error(named_as + ": " + error);
    }
    return distribution;
  }
  if (spec_or_path.find('\0') != std::string::npos) {
    throw_usage_error(named_as + " '" + shown +
                      "' holds a NUL byte: no distribution or file "
                      "name has one");
  }
  std::error_code ec;
  const std::filesystem::path path(spec_or_path);
  const bool exists = !spec_or_path.empty() && std::filesystem::exists(path, ec);
  if (ec) throw_runtime_error("cannot access velocity file '" + shown + "': " + ec.message());
  if (!exists) {
    throw_usage_error(named_as + " '" + shorten_for_message(spec_or_path) +
                      "' is neither uniform:LO:HI, normal:MEAN:SD, normal:MEAN:SD:LO:HI nor an "
                      "existing file of 'velocity weight' lines");
  }
  const std::vector<VelocityPoint> points = parse_velocity_lines(
      detail::read_bounded_text_file(path, kMaxVelocityFileBytes, "velocity file", shown,
                                     "a text file of 'velocity weight' lines"),
      shown);
  if (!discrete_velocity_distribution(points, spec_or_path, &distribution, &error)) {
    throw_runtime_error("velocity file '" + shown + "': " + error);
  }
  return distribution;
}

}  // namespace fss

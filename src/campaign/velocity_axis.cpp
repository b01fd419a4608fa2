#include "campaign/velocity_axis.h"

#include <set>
#include <stdexcept>
#include <string_view>
#include <utility>

#include "campaign/campaign_text.h"
#include "campaign/sha256.h"
#include "fss/core/error.h"
#include "fss/model/velocity_distribution.h"

namespace fss {

namespace {

using Json = nlohmann::json;

// How messages name the axis: by its option and its campaign file key.
constexpr const char* kField = "--velocity-distribution / \"velocity_distribution\"";

// The canonical text of a distribution: its spec, or its points, one "velocity weight" a line
// in shortest round-trip form.
std::string distribution_text(const VelocityDistribution& d) {
  if (d.kind != VelocityDistributionKind::kDiscrete) return d.text();
  std::string text;
  for (const VelocityPoint& p : d.points) {
    text += campaign_text::shortest(p.velocity) + " " + campaign_text::shortest(p.weight) + "\n";
  }
  return text;
}

// The distribution named `name`, with the SHA-256 of its canonical text.
CampaignDistribution campaign_distribution(std::string name, VelocityDistribution d) {
  std::string digest = sha256_hex(distribution_text(d));
  return {std::move(name), std::move(d), std::move(digest)};
}

}  // namespace

std::string velocity_distributions_error(const CampaignSpec& spec) {
  const std::vector<std::string>& items = spec.velocity_distributions;
  if (items.empty()) return {};
  const std::string field = kField;
  if (parse_value_list(spec.velocity, "velocity").values != std::vector<double>{1.0}) {
    return "--velocity / \"velocity\" = " + shorten_for_message(spec.velocity) + " with " + field +
           ": a setting has a velocity or a distribution of velocities, not both; give "
           "one";
  }
  if (items.size() > static_cast<std::size_t>(kMaxCampaignValues)) {
    return field + ": more than " + std::to_string(kMaxCampaignValues) + " distributions";
  }
  for (const std::string& item : items) {
    if (item.empty()) return field + ": an empty item (expected a distribution or a file)";
    const std::string_view kind = std::string_view(item).substr(0, item.find(':'));
    VelocityDistribution d;
    std::string error;
    if ((kind == "uniform" || kind == "normal") && !parse_velocity_distribution(item, &d, &error)) {
      return std::string(field).append(": ").append(error);
    }
  }
  return {};
}

std::vector<CampaignDistribution> load_velocity_distributions(
    const std::vector<std::string>& items) {
  std::vector<CampaignDistribution> distributions;
  std::set<std::string> seen;
  for (const std::string& item : items) {
    VelocityDistribution d;
    try {
      d = load_velocity_distribution(item, kField);
    } catch (const Error& e) {
      if (e.kind() == ErrorKind::kUsage) throw;
      throw_runtime_error(std::string(kField) + ": " + e.what());  // an unreadable file
    }
    std::string name = d.kind == VelocityDistributionKind::kDiscrete ? item : d.text();
    if (!seen.insert(name).second) continue;
    try {
      static_cast<void>(Json(name).dump());  // the canonical JSON holds the name
    } catch (const Json::exception&) {
      throw_usage_error("velocity distribution '" + shorten_for_message(name, 200) +
                        "' is not valid UTF-8: a campaign keeps its names in JSON; rename it");
    }
    distributions.push_back(campaign_distribution(std::move(name), std::move(d)));
  }
  return distributions;
}

void check_velocity_distribution_options(const ResolvedCampaign& c) {
  for (const CampaignDistribution& d : c.velocity_distributions) {
    for (const RestorationOptions& r : c.restorations) {
      SimulationOptions o;
      o.noise = c.noise;
      o.sensor = c.sensor;
      o.trials = c.trials;
      o.rmse_margin_columns = c.rmse_margin_columns;
      o.restoration = r;
      std::string error;
      if (!o.IsValid(&error)) continue;  // a row's status, as without distributions
      o.velocity_distribution = d.distribution;
      if (!o.IsValid(&error)) {
        throw_usage_error(std::string(kField) + " '" + shorten_for_message(d.name) + "' with " +
                          "--restoration / \"restoration\" " + describe(r) + ": " + error);
      }
    }
  }
}

Json velocity_distribution_json(const CampaignDistribution& d) {
  Json j = {{"name", d.name}};
  if (d.distribution.kind == VelocityDistributionKind::kDiscrete) {
    Json points = Json::array();
    for (const VelocityPoint& p : d.distribution.points) points.push_back({p.velocity, p.weight});
    j["points"] = points;
  }
  return j;
}

CampaignDistribution velocity_distribution_from_json(const Json& j) {
  const std::string name = j.at("name").get<std::string>();
  VelocityDistribution d;
  std::string error;
  if (!j.contains("points")) {
    if (!parse_velocity_distribution(name, &d, &error)) throw std::invalid_argument(error);
    if (d.text() != name) throw std::invalid_argument("a distribution not in canonical form");
    return campaign_distribution(name, std::move(d));
  }
  d.kind = VelocityDistributionKind::kDiscrete;
  d.source = name;
  for (const Json& p : j.at("points")) {
    d.points.push_back({p.at(0).get<double>(), p.at(1).get<double>()});
  }
  if (d.points.empty()) throw std::invalid_argument("a distribution without points");
  for (std::size_t i = 1; i < d.points.size(); ++i) {
    if (!(d.points[i - 1].velocity < d.points[i].velocity)) {
      throw std::invalid_argument("a distribution's points out of order");
    }
  }
  d.low = d.points.front().velocity;
  d.high = d.points.back().velocity;
  if (!d.IsValid(&error)) throw std::invalid_argument(error);
  return campaign_distribution(name, std::move(d));
}

}  // namespace fss

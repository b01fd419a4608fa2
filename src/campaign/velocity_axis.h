// The velocity distributions of a campaign (docs/campaign.md, docs/method.md §13), an axis in
// place of the velocities: their rules, how they are read, and their canonical JSON
// (src/campaign/spec.cpp uses these).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "fss/campaign/spec.h"

namespace fss {

// Why the velocity distributions of `spec` are malformed on their own, "" when they are not: a
// velocity list other than the default {1} with them, an empty item, more than
// kMaxCampaignValues items, a spec that does not parse (a file is read by
// load_velocity_distributions).
std::string velocity_distributions_error(const CampaignSpec& spec);

// The distributions of the items (load_velocity_distribution), each once, at its first place: a
// spec named by its canonical text, a file by its path as given. Throws the usage fss::Error of
// load_velocity_distribution, naming the option and the key; a runtime one naming them for a
// file that cannot be read or parsed.
std::vector<CampaignDistribution> load_velocity_distributions(
    const std::vector<std::string>& items);

// Refuses (a usage fss::Error, before any run) a distribution the simulator cannot run with one
// of the campaign's restorations and fixed settings (SimulationOptions::IsValid, whose rule for
// distributions is the library's), where the same options without the distribution are valid.
void check_velocity_distribution_options(const ResolvedCampaign& campaign);

// One distribution in the canonical JSON: {"name": NAME}, and a file's points as [velocity,
// weight] pairs (a spec's name is its canonical text).
nlohmann::json velocity_distribution_json(const CampaignDistribution& distribution);

// The distribution of velocity_distribution_json (std::invalid_argument or nlohmann exceptions
// if malformed). A file's points are taken as they are, already normalised (normalising again
// could change their last bits, and the hash).
CampaignDistribution velocity_distribution_from_json(const nlohmann::json& j);

}  // namespace fss

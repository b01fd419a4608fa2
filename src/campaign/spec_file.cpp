// The campaign file (docs/campaign.md): a JSON object whose keys are the
// fields of CampaignSpec.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "campaign/campaign_text.h"
#include "campaign/user_input.h"
#include "fss/campaign/spec.h"
#include "fss/core/error.h"
#include "fss/model/velocity_distribution.h"
#include "model/noise.h"

namespace fss {

namespace {

using Json = nlohmann::json;
using campaign_input::describe_json;

// Parses one file, naming it in every message.
class CampaignFileReader {
 public:
  explicit CampaignFileReader(const std::string& name)
      : where_("campaign file '" + shorten_for_message(name, 200) + "': ") {}

  [[noreturn]] void Refuse(const std::string& what) const { throw_usage_error(where_ + what); }

  // A JSON value as a list of strings: "a" or ["a", "b"].
  std::vector<std::string> Strings(const Json& value, const std::string& key) const {
    std::vector<std::string> out;
    for (const Json& item : value.is_array() ? value : Json::array({value})) {
      if (!item.is_string()) Refuse("'" + key + "' takes strings");
      out.push_back(item.get<std::string>());
    }
    return out;
  }

  // A value list: "1:2:0.5", 3, or [1, "2:4:1"], as parse_value_list text.
  std::string Values(const Json& value, const std::string& key) const {
    std::string out;
    for (const Json& item : value.is_array() ? value : Json::array({value})) {
      if (!out.empty()) out += ",";
      if (item.is_number()) {
        out += format_exact(item.get<double>());
      } else if (item.is_string()) {
        out += item.get<std::string>();
      } else {
        Refuse("'" + key + "' takes numbers or range strings");
      }
    }
    if (out.empty()) Refuse("'" + key + "' is an empty list");
    return out;
  }

  // A list of items that are strings or numbers ("optimal", 0.01, "1e-3:1e-1:x10"), numbers in
  // shortest round-trip form; never empty.
  std::vector<std::string> Items(const Json& value, const std::string& key) const {
    std::vector<std::string> out;
    for (const Json& item : value.is_array() ? value : Json::array({value})) {
      if (item.is_number()) {
        out.push_back(format_exact(item.get<double>()));
      } else if (item.is_string()) {
        out.push_back(item.get<std::string>());
      } else {
        Refuse("'" + key + "' takes strings or numbers, got " + describe_json(item));
      }
    }
    if (out.empty()) Refuse("'" + key + "' is an empty list");
    return out;
  }

  std::vector<ShutterMode> Modes(const Json& value) const {
    std::vector<ShutterMode> modes;
    for (const std::string& name : Strings(value, "mode")) {
      const auto mode = shutter_mode_from_string(name);
      if (!mode) {
        Refuse("mode '" + shorten_for_message(name) + "': expected numerical or analog");
      }
      modes.push_back(*mode);
    }
    return modes;
  }

  // trials, rmse_margin: an integer; out of int's range it breaks its rule
  // anyway, so it is refused here.
  int Integer(const Json& value, const std::string& key) const {
    const std::optional<long long> n = campaign_input::json_integer(value);
    if (!n || *n < -2 || *n > (1LL << 30)) {
      Refuse("'" + key + "' takes an integer in range, got " + describe_json(value));
    }
    return static_cast<int>(*n);
  }

  // Distributions of velocities (docs/method.md §13): each item a spec or a file's path, read
  // here (load_velocity_distribution) so that a bad one is refused naming this file, the key and
  // the item; never empty.
  std::vector<std::string> Distributions(const Json& value, const std::string& key) const {
    std::vector<std::string> items = Strings(value, key);
    if (items.empty()) Refuse("'" + key + "' is an empty list");
    for (const std::string& item : items) {
      try {
        static_cast<void>(load_velocity_distribution(item, "\"" + key + "\""));
      } catch (const Error& e) {
        if (e.kind() == ErrorKind::kUsage) Refuse(e.what());
        throw_runtime_error(where_ + "\"" + key + "\": " + e.what());
      }
    }
    return items;
  }

  bool List(const std::string& key, const Json& value, CampaignSpec& spec) const;
  bool Scalar(const std::string& key, const Json& value, CampaignSpec& spec) const;
  bool Sensor(const std::string& key, const Json& value, CampaignSpec& spec) const;

 private:
  std::string where_;
};

bool CampaignFileReader::List(const std::string& key, const Json& value, CampaignSpec& spec) const {
  if (key == "input") {
    spec.inputs = Strings(value, key);
  } else if (key == "code") {
    spec.codes = Strings(value, key);
  } else if (key == "mode") {
    spec.modes = Modes(value);
  } else if (key == "velocity") {
    spec.velocity = Values(value, key);
  } else if (key == "restore_velocity") {
    spec.restore_velocity = Values(value, key);
  } else if (key == "snr") {
    spec.snr = Values(value, key);
  } else if (key == "dt") {
    spec.dt = Values(value, key);
  } else if (key == "read_noise") {
    spec.read_noise = Values(value, key);
  } else if (key == "restoration" || key == "prior") {
    std::vector<std::string> items = Strings(value, key);
    if (items.empty()) Refuse("'" + key + "' is an empty list");
    (key == "restoration" ? spec.restorations : spec.priors) = std::move(items);
  } else if (key == "regularization") {
    spec.regularization = Items(value, key);
  } else if (key == "velocity_distribution") {
    spec.velocity_distributions = Distributions(value, key);
  } else {
    return false;
  }
  return true;
}

bool CampaignFileReader::Scalar(const std::string& key, const Json& value,
                                CampaignSpec& spec) const {
  if (key == "trials") {
    spec.trials = Integer(value, key);
  } else if (key == "rmse_margin") {
    // "auto" or a number of columns (-1: the paper's 3B)
    spec.rmse_margin_columns = value.is_string() && value.get<std::string>() == "auto"
                                   ? kRmseMarginAuto
                                   : Integer(value, key);
  } else if (key == "seed") {
    if (!value.is_number_unsigned()) Refuse("'seed' takes an integer >= 0");
    spec.seed = value.get<std::uint64_t>();
  } else if (key == "noise") {
    if (!value.is_string()) Refuse("'noise' takes a string");
    const auto noise = noise_model_from_string(value.get<std::string>());
    if (!noise) {
      Refuse("noise '" + shorten_for_message(value.get<std::string>()) +
             "': not a noise model of fssim");
    }
    spec.noise = *noise;
  } else if (key == "per_trial") {
    if (!value.is_boolean()) Refuse("'per_trial' takes true or false");
    spec.per_trial = value.get<bool>();
  } else {
    return Sensor(key, value, spec);
  }
  return true;
}

// A fixed sensor field (docs/method.md §10); the values are checked by
// CampaignSpec's rules when the campaign is resolved.
bool CampaignFileReader::Sensor(const std::string& key, const Json& value,
                                CampaignSpec& spec) const {
  if (key == "adc_bits") {
    const std::optional<long long> bits = campaign_input::json_integer(value);
    if (!bits || *bits < 0 || *bits > 64) {
      Refuse("'adc_bits' takes an integer in [1, 32], got " + describe_json(value));
    }
    spec.sensor.adc_bits = static_cast<int>(*bits);
    return true;
  }
  if (key != "dark_current" && key != "full_well" && key != "adc_gain") return false;
  if (!value.is_number()) {
    Refuse("'" + key + "' takes a number, got " + describe_json(value));
  }
  const double number = value.get<double>();
  if (key == "dark_current") spec.sensor.dark_current_electrons_per_slot = number;
  if (key == "full_well") spec.sensor.full_well_electrons = number;
  if (key == "adc_gain") spec.sensor.adc_gain_electrons_per_count = number;
  return true;
}

}  // namespace

// The keys are those docs/campaign.md lists; value lists are kept as text, numbers in shortest
// round-trip form.
CampaignSpec parse_campaign_file(std::string_view text, const std::string& name) {
  const CampaignFileReader reader(name);
  std::string error;
  const std::optional<Json> parsed = campaign_input::parse_json(text, &error);
  if (!parsed) reader.Refuse(error);
  const Json& j = *parsed;
  if (!j.is_object()) reader.Refuse("expected an object");
  if (j.contains("velocity") && j.contains("velocity_distribution")) {
    reader.Refuse(
        "'velocity' and 'velocity_distribution': a setting has a velocity or a "
        "distribution of velocities, not both; give one");
  }
  CampaignSpec spec;
  for (const auto& [key, value] : j.items()) {
    if (!reader.List(key, value, spec) && !reader.Scalar(key, value, spec)) {
      reader.Refuse("unknown key '" + shorten_for_message(key) +
                    "' (input, code, mode, velocity, restore_velocity, snr, dt, trials, seed, "
                    "noise, rmse_margin, per_trial, read_noise, dark_current, full_well, "
                    "adc_bits, adc_gain, restoration, regularization, prior, "
                    "velocity_distribution)");
    }
  }
  return spec;
}

CampaignSpec read_campaign_file(const std::string& path) {
  return parse_campaign_file(
      campaign_input::read_text_file(path, kMaxCampaignFileBytes, "campaign file"), path);
}

}  // namespace fss

#include "fss/campaign/spec.h"

#include <glob.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <stdexcept>

#include "campaign/campaign_text.h"
#include "campaign/sha256.h"
#include "campaign/user_input.h"
#include "campaign/velocity_axis.h"
#include "core/number_text.h"
#include "fss/core/error.h"
#include "fss/pipeline/option_rules.h"
#include "model/noise.h"

namespace fss {

namespace {

using Json = nlohmann::json;

// 12 significant digits: start + i step without its rounding noise (0.1 steps read 0.3).
double tidy(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.12g", value);
  return std::strtod(buffer, nullptr);
}

[[noreturn]] void refuse_item(const std::string& field, std::string_view item,
                              const std::string& why) {
  throw_usage_error(field + " item '" + shorten_for_message(item) + "': " + why);
}

// A value within half a step of stop counts, as in sweep's ranges, so that
// rounding never drops stop ("0:1:0.1" has 11 values); a value that then
// leaves the doubles ("2:1e308:x10" would end at 2e308) is refused.
constexpr double kRangeSlack = 0.5;

// Appends the values of one range item "start:stop:step" or "start:stop:xF".
void append_range(std::string_view item, const std::string& field, ValueList& list) {
  const auto first = item.find(':');
  const auto second = item.find(':', first + 1);
  if (second == std::string_view::npos || item.find(':', second + 1) != std::string_view::npos) {
    refuse_item(field, item, "a range has three parts, start:stop:step or start:stop:xFACTOR");
  }
  const double start = parse_finite_number(item.substr(0, first));
  const double stop = parse_finite_number(item.substr(first + 1, second - first - 1));
  std::string_view step_text = item.substr(second + 1);
  const bool geometric = !step_text.empty() && (step_text[0] == 'x' || step_text[0] == 'X');
  if (geometric) step_text.remove_prefix(1);
  const double step = parse_finite_number(step_text);
  if (std::isnan(start) || std::isnan(stop) || std::isnan(step)) {
    refuse_item(field, item, "start, stop and step must be finite numbers");
  }
  if (stop < start) refuse_item(field, item, "stop must not be below start");
  double count = 0.0;
  if (geometric) {
    if (!(start > 0.0) || !(step > 1.0)) {
      refuse_item(field, item, "a geometric range needs start > 0 and a factor > 1");
    }
    count = std::floor(std::log(stop / start) / std::log(step) + kRangeSlack) + 1.0;
  } else {
    if (!(step > 0.0)) refuse_item(field, item, "step must be > 0");
    count = std::floor((stop - start) / step + kRangeSlack) + 1.0;
  }
  if (!(count + static_cast<double>(list.values.size()) <= kMaxCampaignValues)) {
    refuse_item(field, item, "more than " + std::to_string(kMaxCampaignValues) + " values");
  }
  list.geometric = list.geometric || geometric;
  for (int i = 0; i < static_cast<int>(count); ++i) {
    const double value = tidy(geometric ? start * std::pow(step, i) : start + i * step);
    if (!std::isfinite(value)) refuse_item(field, item, "its values leave the range of doubles");
    list.values.push_back(value);
  }
}

}  // namespace

ValueList parse_value_list(std::string_view text, const std::string& field) {
  ValueList list;
  if (text.empty()) throw_usage_error(field + ": empty value list");
  std::size_t begin = 0;
  while (begin <= text.size()) {
    const std::size_t end = std::min(text.find(',', begin), text.size());
    const std::string_view item = text.substr(begin, end - begin);
    if (item.find(':') != std::string_view::npos) {
      append_range(item, field, list);
    } else {
      const double value = parse_finite_number(item);
      if (std::isnan(value)) {
        refuse_item(field, item, "expected a finite number, start:stop:step or start:stop:xF");
      }
      if (list.values.size() >= static_cast<std::size_t>(kMaxCampaignValues)) {
        refuse_item(field, item, "more than " + std::to_string(kMaxCampaignValues) + " values");
      }
      list.values.push_back(value);
    }
    begin = end + 1;
  }
  return list;
}

namespace {

// How messages name a field: by its option and its campaign file key, as
// either may have set it.
std::string field_name(const char* option, const char* key) {
  return std::string(option) + " / \"" + key + "\"";
}

// The fixed sensor parts, named as the options and keys that set them; ""
// when valid (a read noise value out of range is a row's status instead).
std::string sensor_error(const SensorModel& sensor) {
  const auto rule = [](const char* option, const char* key, double value, const char* what) {
    return field_name(option, key) + " = " + format_exact(value) + ": " + what;
  };
  const double dark = sensor.dark_current_electrons_per_slot;
  if (!(std::isfinite(dark) && dark >= 0.0)) {
    return rule("--dark-current", "dark_current", dark, "must be finite and >= 0");
  }
  const double full = sensor.full_well_electrons.value_or(1.0);
  if (!(std::isfinite(full) && full > 0.0)) {
    return rule("--full-well", "full_well", full, "must be finite and > 0");
  }
  if (sensor.adc_bits < 0 || sensor.adc_bits > 32) {
    return rule("--adc-bits", "adc_bits", sensor.adc_bits, "must lie in [1, 32] (or 0 for no ADC)");
  }
  if (dark > kMaxSensorScale) {
    return rule("--dark-current", "dark_current", dark, "must lie in [0, 1e100]");
  }
  const double gain = sensor.adc_gain_electrons_per_count;
  if (!(std::isfinite(gain) && gain > 0.0)) {
    return rule("--adc-gain", "adc_gain", gain, "must be finite and > 0");
  }
  if (gain > kMaxSensorScale) return rule("--adc-gain", "adc_gain", gain, "must lie in (0, 1e100]");
  if (sensor.adc_bits == 0 && gain != 1.0) {
    return rule("--adc-gain", "adc_gain", gain,
                "needs --adc-bits / \"adc_bits\" (without an ADC there are no counts)");
  }
  SensorModel fixed = sensor;
  fixed.read_noise_electrons = 0.0;
  std::string error;
  return fixed.IsValid(&error) ? std::string() : "sensor: " + error;
}

// The items of lists given as strings that may each hold several, comma-separated.
std::vector<std::string> split_items(const std::vector<std::string>& lists) {
  std::vector<std::string> items;
  for (const std::string& list : lists) {
    std::size_t begin = 0;
    while (begin <= list.size()) {
      const std::size_t end = std::min(list.find(',', begin), list.size());
      items.push_back(list.substr(begin, end - begin));
      begin = end + 1;
    }
  }
  return items;
}

// The methods of --restoration / "restoration", each once, in the order given; the inverse
// filter when none is given.
std::vector<RestorationMethod> restoration_methods(const std::vector<std::string>& names) {
  const std::string field = field_name("--restoration", "restoration");
  std::vector<RestorationMethod> methods;
  for (const std::string& name : split_items(names)) {
    const auto method = restoration_method_from_string(name);
    if (!method) refuse_item(field, name, "expected inverse, tikhonov or wiener");
    if (std::find(methods.begin(), methods.end(), *method) == methods.end()) {
      methods.push_back(*method);
    }
  }
  if (methods.empty()) methods.push_back(RestorationMethod::kInverse);
  return methods;
}

// Tikhonov's lambdas: "optimal" (empty) or the values of value list items, each within the
// library's range; optimal alone when none is given.
std::vector<std::optional<double>> regularizations(const std::vector<std::string>& lists) {
  const std::string field = field_name("--regularization", "regularization");
  if (lists.empty()) return {std::nullopt};
  std::vector<std::optional<double>> lambdas;
  for (const std::string& item : split_items(lists)) {
    if (item == "optimal") {
      lambdas.emplace_back();
      continue;
    }
    if (item.find(':') == std::string::npos && std::isnan(parse_finite_number(item))) {
      refuse_item(field, item, "expected optimal, a number, start:stop:step or start:stop:xF");
    }
    for (const double lambda : parse_value_list(item, field).values) {
      if (!(lambda >= kMinRegularization && lambda <= kMaxRegularization)) {
        throw_usage_error(field + " = " + format_exact(lambda) + ": must lie in [" +
                          format_exact(kMinRegularization) + ", " +
                          format_exact(kMaxRegularization) + "] (or be optimal)");
      }
      lambdas.emplace_back(lambda);
    }
    if (lambdas.size() > static_cast<std::size_t>(kMaxCampaignValues)) {
      refuse_item(field, item, "more than " + std::to_string(kMaxCampaignValues) + " values");
    }
  }
  return lambdas;
}

// Why `item` is not a prior a campaign takes ("power-law", "power-law:GAMMA", "oracle"); "" when
// it is one.
std::string prior_rule(std::string_view item) {
  constexpr std::string_view kPowerLaw = "power-law";
  if (item == "oracle" || item == kPowerLaw) return {};
  if (item.substr(0, kPowerLaw.size() + 1) != "power-law:") {
    return "expected power-law, power-law:GAMMA or oracle";
  }
  const std::string_view gamma = item.substr(kPowerLaw.size() + 1);
  if (gamma.find(':') != std::string_view::npos) {
    return "gives a level; a simulation estimates it from a calibration observation (give "
           "power-law, power-law:GAMMA or oracle)";
  }
  const double value = parse_finite_number(gamma);
  if (!(value >= 0.0 && value <= kMaxPriorExponent)) {
    return "GAMMA must be a number in [0, " + format_exact(kMaxPriorExponent) + "]";
  }
  return {};
}

// Wiener's priors, each a Wiener restoration; power-law:2 alone when none is given.
std::vector<RestorationOptions> wiener_priors(const std::vector<std::string>& lists) {
  const std::string field = field_name("--prior", "prior");
  RestorationOptions wiener;
  wiener.method = RestorationMethod::kWiener;
  if (lists.empty()) return {wiener};
  std::vector<RestorationOptions> priors;
  for (const std::string& item : split_items(lists)) {
    RestorationOptions r = wiener;
    std::string error = prior_rule(item);
    if (error.empty() && !parse_prior(item, &r, &error)) error = "not a prior";
    if (!error.empty()) refuse_item(field, item, error);
    priors.push_back(r);
  }
  return priors;
}

bool same_restoration(const RestorationOptions& a, const RestorationOptions& b) {
  return a.method == b.method && a.regularization == b.regularization && a.prior == b.prior &&
         (a.prior == PriorKind::kOracle || a.prior_exponent == b.prior_exponent) &&
         a.prior_level == b.prior_level;
}

// The restoration variants of `spec`: for each method given, the inverse filter once, Tikhonov
// at each lambda, Wiener with each prior; a variant given twice is kept at its first place. A
// lambda or a prior without its method is refused: it would be accepted and ignored.
std::vector<RestorationOptions> restoration_variants(const CampaignSpec& spec) {
  const std::vector<RestorationMethod> methods = restoration_methods(spec.restorations);
  const auto has = [&](RestorationMethod m) {
    return std::find(methods.begin(), methods.end(), m) != methods.end();
  };
  const std::string restoration = field_name("--restoration", "restoration");
  if (!spec.regularization.empty() && !has(RestorationMethod::kTikhonov)) {
    throw_usage_error(field_name("--regularization", "regularization") +
                      ": applies to the tikhonov restoration only, and " + restoration +
                      " has no tikhonov");
  }
  if (!spec.priors.empty() && !has(RestorationMethod::kWiener)) {
    throw_usage_error(field_name("--prior", "prior") +
                      ": applies to the wiener restoration only, and " + restoration +
                      " has no wiener");
  }
  std::vector<RestorationOptions> variants;
  const auto add = [&variants](const RestorationOptions& r) {
    const auto same = [&r](const RestorationOptions& v) { return same_restoration(v, r); };
    if (std::none_of(variants.begin(), variants.end(), same)) variants.push_back(r);
  };
  for (const RestorationMethod method : methods) {
    if (method == RestorationMethod::kInverse) add(RestorationOptions{});
    if (method == RestorationMethod::kTikhonov) {
      for (const std::optional<double>& lambda : regularizations(spec.regularization)) {
        RestorationOptions r;
        r.method = RestorationMethod::kTikhonov;
        r.regularization = lambda;
        add(r);
      }
    }
    if (method == RestorationMethod::kWiener) {
      for (const RestorationOptions& r : wiener_priors(spec.priors)) add(r);
    }
  }
  return variants;
}

}  // namespace

bool CampaignSpec::IsValid(std::string* error) const {
  const auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (inputs.empty()) {
    return fail(field_name("--input", "input") + ": the campaign needs at least one image");
  }
  if (codes.empty()) {
    return fail(field_name("--code", "code") + ": the campaign needs at least one code");
  }
  if (modes.empty()) {
    return fail(field_name("--mode", "mode") + ": the campaign needs at least one mode");
  }
  try {
    parse_value_list(velocity, field_name("--velocity", "velocity"));
    if (!restore_velocity.empty()) {
      parse_value_list(restore_velocity, field_name("--restore-velocity", "restore_velocity"));
    }
    parse_value_list(snr, field_name("--snr", "snr"));
    parse_value_list(dt, field_name("--dt", "dt"));
    parse_value_list(read_noise, field_name("--read-noise", "read_noise"));
    restoration_variants(*this);
  } catch (const Error& e) {
    return fail(e.what());
  }
  if (const std::string rule = trials_rule(trials); !rule.empty()) {
    return fail(field_name("--trials", "trials") + " = " + std::to_string(trials) + ": " + rule);
  }
  if (const std::string rule = margin_rule(rmse_margin_columns); !rule.empty()) {
    return fail(field_name("--rmse-margin", "rmse_margin") + " = " +
                std::to_string(rmse_margin_columns) + ": " + rule);
  }
  if (const std::string message = sensor_error(sensor); !message.empty()) return fail(message);
  if (const std::string message = velocity_distributions_error(*this); !message.empty()) {
    return fail(message);
  }
  return true;
}

namespace {

// Refuses (a usage fss::Error) a name the canonical JSON cannot hold.
void require_utf8(const std::string& name, const char* what) {
  try {
    static_cast<void>(Json(name).dump());
  } catch (const Json::exception&) {
    throw_usage_error(std::string(what) + " '" + shorten_for_message(name, 200) +
                      "' is not valid UTF-8: a campaign keeps its names in JSON; rename it");
  }
}

// The bytes of image `path`: a PNG or TIFF file of at most
// kMaxCampaignImageBytes. A regular file: a campaign reads its images again
// (to run a setting, to resume), which a pipe or a FIFO cannot give twice.
std::string read_image_bytes(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec)) {
    throw_usage_error("image '" + escape_control_characters(path) +
                      "' is not a regular file: a campaign reads its images more than once (to "
                      "run and to resume); copy it to a file");
  }
  return campaign_input::read_image_file(path, kMaxCampaignImageBytes, "image");
}

// `name`'s extension in lower case, without the dot ("tif" for "a.TIF").
std::string lower_extension(const std::filesystem::path& name) {
  std::string extension = name.extension().string();
  if (!extension.empty()) extension.erase(0, 1);
  for (char& ch : extension) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return extension;
}

// The images of directory `dir`: its regular files named *.png, *.tif or
// *.tiff in any case (the formats the simulator reads), hidden files left
// out as a shell glob leaves them. A file named as an image of another
// format (*.jpg, *.bmp, ...) is refused rather than left out silently; other
// files (notes, results) are left out.
std::vector<std::string> directory_images(const std::string& dir) {
  namespace fs = std::filesystem;
  static const std::set<std::string> kRead = {"png", "tif", "tiff"};
  static const std::set<std::string> kOther = {"jpg",  "jpeg", "jpe",  "jp2", "bmp", "gif",
                                               "webp", "pbm",  "pgm",  "ppm", "pnm", "exr",
                                               "hdr",  "heic", "avif", "jxl"};
  std::vector<std::string> paths;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const fs::path& path = it->path();
    std::error_code kind;
    if (path.filename().string().starts_with(".") || !it->is_regular_file(kind)) continue;
    const std::string extension = lower_extension(path.filename());
    if (kRead.contains(extension)) {
      paths.push_back(path.string());
    } else if (kOther.contains(extension)) {
      throw_usage_error("input '" + escape_control_characters(dir) + "' holds '" +
                        escape_control_characters(path.filename().string()) +
                        "', an image format fssim does not read (PNG and TIFF only): convert "
                        "it, or name the images one by one");
    }
  }
  if (ec) {
    throw_usage_error("cannot read directory '" + escape_control_characters(dir) +
                      "': " + ec.message());
  }
  return paths;
}

// The image files one input stands for: itself, a directory's images
// (directory_images), or a glob's matches, sorted by name.
std::vector<std::string> expand_input(const std::string& input) {
  namespace fs = std::filesystem;
  std::vector<std::string> paths;
  std::error_code ec;
  if (fs::is_directory(input, ec)) {
    paths = directory_images(input);
  } else if (input.find_first_of("*?[") != std::string::npos) {
    glob_t matches{};
    if (glob(input.c_str(), 0, nullptr, &matches) == 0) {
      for (std::size_t i = 0; i < matches.gl_pathc; ++i) paths.emplace_back(matches.gl_pathv[i]);
    }
    globfree(&matches);
  } else if (fs::exists(input, ec)) {
    paths.push_back(input);
  } else {
    throw_usage_error("input '" + escape_control_characters(input) + "' does not exist");
  }
  if (paths.empty()) {
    throw_usage_error("input '" + escape_control_characters(input) +
                      "' matches no PNG or TIFF file (*.png, *.tif, *.tiff)");
  }
  std::sort(paths.begin(), paths.end());
  return paths;
}

std::string code_digest(const std::vector<double>& gains) {
  std::string text;
  for (const double g : gains) text += campaign_text::shortest(g) + "\n";
  return sha256_hex(text);
}

Json values_json(const ValueList& list) {
  return Json{{"values", list.values}, {"geometric", list.geometric}};
}

ValueList values_from_json(const Json& j) {
  return {j.at("values").get<std::vector<double>>(), j.at("geometric").get<bool>()};
}

// The sensor's part of the canonical JSON: the read noise axis and the
// fixed parts (full_well null for none).
Json sensor_json(const ResolvedCampaign& c) {
  const SensorModel& s = c.sensor;
  return {{"read_noise", values_json(c.read_noises)},
          {"dark_current", s.dark_current_electrons_per_slot},
          {"full_well", s.full_well_electrons ? Json(*s.full_well_electrons) : Json(nullptr)},
          {"adc_bits", s.adc_bits},
          {"adc_gain", s.adc_gain_electrons_per_count}};
}

// j[key] as an integer; throws std::invalid_argument if it is none.
long long integer_at(const Json& j, const char* key) {
  const std::optional<long long> n = campaign_input::json_integer(j.at(key));
  if (!n) throw std::invalid_argument(std::string("'") + key + "' is not an integer");
  return *n;
}

void sensor_from_json(const Json& j, ResolvedCampaign& c) {
  c.read_noises = values_from_json(j.at("read_noise"));
  c.sensor.dark_current_electrons_per_slot = j.at("dark_current").get<double>();
  if (!j.at("full_well").is_null()) c.sensor.full_well_electrons = j.at("full_well").get<double>();
  c.sensor.adc_bits = static_cast<int>(std::clamp(integer_at(j, "adc_bits"), -1LL, 64LL));
  c.sensor.adc_gain_electrons_per_count = j.at("adc_gain").get<double>();
}

// One restoration variant in the canonical JSON: its method, and Tikhonov's lambda (a number,
// or "optimal") or Wiener's prior (as parse_prior reads it).
Json restoration_json(const RestorationOptions& r) {
  Json j = {{"method", to_string(r.method)}};
  if (r.method == RestorationMethod::kTikhonov) {
    j["regularization"] = r.regularization ? Json(*r.regularization) : Json("optimal");
  }
  if (r.method == RestorationMethod::kWiener) j["prior"] = prior_text(r);
  return j;
}

// A variant of restoration_json (std::invalid_argument or nlohmann exceptions if malformed).
RestorationOptions restoration_from_json(const Json& j) {
  const auto method = restoration_method_from_string(j.at("method").get<std::string>());
  if (!method) throw std::invalid_argument("an unknown restoration");
  RestorationOptions r;
  r.method = *method;
  if (r.method == RestorationMethod::kTikhonov) {
    const Json& lambda = j.at("regularization");
    if (!lambda.is_string()) {
      r.regularization = lambda.get<double>();
    } else if (lambda.get<std::string>() != "optimal") {
      throw std::invalid_argument("a regularization that is neither a number nor optimal");
    }
  }
  std::string error;
  if (r.method == RestorationMethod::kWiener &&
      !parse_prior(j.at("prior").get<std::string>(), &r, &error)) {
    throw std::invalid_argument(error);
  }
  return r;
}

void seal(ResolvedCampaign& c) {
  Json images = Json::array(), codes = Json::array(), modes = Json::array(),
       restore = Json::array();
  for (const CampaignImage& i : c.images)
    images.push_back({{"name", i.name}, {"sha256", i.sha256}});
  for (const CampaignCode& k : c.codes) {
    codes.push_back({{"name", k.name}, {"sha256", k.sha256}, {"gains", k.code.gains}});
  }
  for (const ShutterMode m : c.modes) modes.push_back(to_string(m));
  for (const auto& r : c.restore_velocities) restore.push_back(r ? Json(*r) : Json(nullptr));
  Json j = {{"campaign_schema", 1},
            {"images", images},
            {"codes", codes},
            {"modes", modes},
            {"velocity", values_json(c.velocities)},
            {"restore_velocity", {{"values", restore}, {"geometric", c.restore_geometric}}},
            {"snr", values_json(c.snrs)},
            {"dt", values_json(c.dts)},
            {"trials", c.trials},
            {"seed", c.seed},
            {"noise", to_string(c.noise)},
            {"rmse_margin", c.rmse_margin_columns}};
  if (c.per_trial) j["per_trial"] = true;  // absent when off: earlier campaigns keep their hash
  // Aggregated noise only (earlier campaigns of the other noise models keep their hash): the
  // sampler's version, absent in the campaigns of version 1.
  if (c.noise == NoiseModel::kAggregated && c.aggregated_sampler != 1) {
    j["aggregated_sampler"] = c.aggregated_sampler;
  }
  if (c.has_sensor()) j["sensor"] = sensor_json(c);
  // Absent for the inverse filter alone: earlier campaigns keep their hash.
  if (c.has_restorations()) {
    Json restorations = Json::array();
    for (const RestorationOptions& r : c.restorations) restorations.push_back(restoration_json(r));
    j["restoration"] = restorations;
  }
  // Absent without distributions: earlier campaigns keep their hash.
  if (c.has_velocity_distributions()) {
    Json distributions = Json::array();
    for (const CampaignDistribution& d : c.velocity_distributions) {
      distributions.push_back(velocity_distribution_json(d));
    }
    j["velocity_distribution"] = distributions;
  }
  c.canonical_json = j.dump();
  c.sha256 = sha256_hex(c.canonical_json);
}

}  // namespace

// Only a campaign with a sensor names it in its canonical JSON and its settings' descriptions, so
// that a campaign without one keeps its hash and its seeds.
bool ResolvedCampaign::has_sensor() const {
  SensorModel fixed = sensor;
  fixed.read_noise_electrons = 0.0;
  return fixed.enabled() || read_noises.values != std::vector<double>{0.0};
}

bool ResolvedCampaign::has_restorations() const {
  return restorations.size() != 1 || restorations.front().method != RestorationMethod::kInverse;
}

long long ResolvedCampaign::setting_count() const {
  long long n = 1;
  for (const std::size_t size :
       {images.size(), codes.size(), modes.size(), velocities.values.size(),
        std::max<std::size_t>(velocity_distributions.size(), 1), restore_velocities.size(),
        snrs.values.size(), dts.values.size(), read_noises.values.size(), restorations.size()}) {
    n *= static_cast<long long>(size);
    if (n > kMaxCampaignSettings) return kMaxCampaignSettings + 1;
  }
  return n;
}

ResolvedCampaign resolve_campaign(const CampaignSpec& spec) {
  std::string error;
  if (!spec.IsValid(&error)) throw_usage_error(error);
  ResolvedCampaign c;
  // An image or code named twice runs once, at its first place.
  std::set<std::string> seen;
  for (const std::string& input : spec.inputs) {
    for (const std::string& path : expand_input(input)) {
      if (!seen.insert(path).second) continue;
      require_utf8(path, "image");
      c.images.push_back({path, path, sha256_hex(read_image_bytes(path))});
    }
  }
  seen.clear();
  for (const std::string& name : spec.codes) {
    if (!seen.insert(name).second) continue;
    require_utf8(name, "code");
    const ShutterCode code = load_code(name);
    c.codes.push_back({name, code, code_digest(code.gains)});
  }
  c.modes = spec.modes;
  c.velocities = parse_value_list(spec.velocity, "velocity");
  c.restore_velocities = {std::nullopt};
  if (!spec.restore_velocity.empty()) {
    const ValueList r = parse_value_list(spec.restore_velocity, "restore_velocity");
    c.restore_velocities.assign(r.values.begin(), r.values.end());
    c.restore_geometric = r.geometric;
  }
  c.snrs = parse_value_list(spec.snr, "snr");
  c.dts = parse_value_list(spec.dt, "dt");
  c.trials = spec.trials;
  c.seed = spec.seed;
  c.noise = spec.noise;
  c.rmse_margin_columns = spec.rmse_margin_columns;
  c.per_trial = spec.per_trial;
  c.read_noises = parse_value_list(spec.read_noise, "read_noise");
  c.sensor = spec.sensor;
  c.sensor.read_noise_electrons = 0.0;
  c.restorations = restoration_variants(spec);
  c.velocity_distributions = load_velocity_distributions(spec.velocity_distributions);
  check_velocity_distribution_options(c);
  if (c.setting_count() > kMaxCampaignSettings) {
    throw_usage_error("the campaign has more than " + std::to_string(kMaxCampaignSettings) +
                      " settings");
  }
  seal(c);
  return c;
}

namespace {

// Why restoration variants read from a canonical JSON cannot be a campaign's; "" when they can.
std::string restorations_error(const std::vector<RestorationOptions>& restorations) {
  for (const RestorationOptions& r : restorations) {
    std::string error;
    if (!r.IsValid(&error)) return "restoration " + error;
    if (r.prior_level) return "a restoration prior with a level";
  }
  return {};
}

// Why `c`, read from a canonical JSON, cannot be a campaign fssim resolved;
// "" when it can.
std::string canonical_error(const ResolvedCampaign& c) {
  for (const std::size_t size :
       {c.images.size(), c.codes.size(), c.modes.size(), c.velocities.values.size(),
        c.restore_velocities.size(), c.snrs.values.size(), c.dts.values.size(),
        c.read_noises.values.size(), c.restorations.size()}) {
    if (size == 0) return "a list of the product is empty";
  }
  if (c.setting_count() > kMaxCampaignSettings) {
    return "more than " + std::to_string(kMaxCampaignSettings) + " settings";
  }
  for (const ValueList* list : {&c.velocities, &c.snrs, &c.dts, &c.read_noises}) {
    if (list->values.size() > static_cast<std::size_t>(kMaxCampaignValues)) {
      return "a value list longer than " + std::to_string(kMaxCampaignValues);
    }
    for (const double v : list->values) {
      if (!std::isfinite(v)) return "a value that is not finite";
    }
  }
  for (const CampaignCode& k : c.codes) {
    if (k.code.gains.empty() || k.code.gains.size() > static_cast<std::size_t>(kMaxCodeLength)) {
      return "code '" + shorten_for_message(k.name) + "' has " +
             std::to_string(k.code.gains.size()) + " gains";
    }
    for (const double g : k.code.gains) {
      if (!std::isfinite(g)) return "a gain that is not finite";
    }
  }
  if (!trials_rule(c.trials).empty() || !margin_rule(c.rmse_margin_columns).empty()) {
    return "trials or rmse_margin out of range";
  }
  if (c.aggregated_sampler < 1 || c.aggregated_sampler > kAggregatedSamplerVersion) {
    return "an unknown aggregated_sampler version";
  }
  for (const auto& r : c.restore_velocities) {
    if (r && !std::isfinite(*r)) return "a value that is not finite";
  }
  if (std::string why = restorations_error(c.restorations); !why.empty()) return why;
  if (c.has_velocity_distributions() && c.velocities.values != std::vector<double>{1.0}) {
    return "velocities with velocity distributions";
  }
  if (c.velocity_distributions.size() > static_cast<std::size_t>(kMaxCampaignValues)) {
    return "more than " + std::to_string(kMaxCampaignValues) + " velocity distributions";
  }
  return sensor_error(c.sensor);
}

// The fields of a canonical JSON `j` into `c` (nlohmann exceptions for a
// missing key or a wrong type; the values are checked by canonical_error).
void read_canonical(const Json& j, ResolvedCampaign& c) {
  for (const Json& i : j.at("images")) {
    const std::string name = i.at("name").get<std::string>();
    c.images.push_back({name, name, i.at("sha256").get<std::string>()});
  }
  for (const Json& k : j.at("codes")) {
    const std::string name = k.at("name").get<std::string>();
    c.codes.push_back({name, ShutterCode{name, k.at("gains").get<std::vector<double>>()},
                       k.at("sha256").get<std::string>()});
  }
  for (const Json& m : j.at("modes")) {
    const auto mode = shutter_mode_from_string(m.get<std::string>());
    if (!mode) throw_runtime_error("malformed campaign specification: an unknown mode");
    c.modes.push_back(*mode);
  }
  c.velocities = values_from_json(j.at("velocity"));
  for (const Json& r : j.at("restore_velocity").at("values")) {
    c.restore_velocities.push_back(r.is_null() ? std::nullopt
                                               : std::optional<double>(r.get<double>()));
  }
  c.restore_geometric = j.at("restore_velocity").at("geometric").get<bool>();
  c.snrs = values_from_json(j.at("snr"));
  c.dts = values_from_json(j.at("dt"));
  const long long trials = integer_at(j, "trials");
  const long long margin = integer_at(j, "rmse_margin");
  c.trials = static_cast<int>(std::clamp(trials, 0LL, 1LL << 30));
  c.rmse_margin_columns = static_cast<int>(std::clamp(margin, -2LL, 1LL << 30));
  const std::optional<std::uint64_t> seed = campaign_input::json_unsigned(j.at("seed"));
  if (!seed) throw std::invalid_argument("'seed' is not an unsigned integer");
  c.seed = *seed;
  const auto noise = noise_model_from_string(j.at("noise").get<std::string>());
  if (!noise) throw_runtime_error("malformed campaign specification: an unknown noise model");
  c.noise = *noise;
  c.per_trial = j.value("per_trial", false);
  // Absent from an aggregated campaign: version 1, before the versions were named.
  c.aggregated_sampler = c.noise == NoiseModel::kAggregated ? j.value("aggregated_sampler", 1)
                                                            : kAggregatedSamplerVersion;
  if (j.contains("sensor")) sensor_from_json(j.at("sensor"), c);
  if (j.contains("restoration")) {
    c.restorations.clear();
    for (const Json& r : j.at("restoration")) c.restorations.push_back(restoration_from_json(r));
  }
  if (j.contains("velocity_distribution")) {
    for (const Json& d : j.at("velocity_distribution")) {
      c.velocity_distributions.push_back(velocity_distribution_from_json(d));
    }
    if (c.velocity_distributions.empty()) throw std::invalid_argument("no velocity distribution");
  }
}

}  // namespace

ResolvedCampaign campaign_from_canonical_json(const std::string& json) {
  std::string error;
  const std::optional<Json> j = campaign_input::parse_json(json, &error);
  if (!j) throw_runtime_error("malformed campaign specification: " + error);
  ResolvedCampaign c;
  try {
    read_canonical(*j, c);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw_runtime_error("malformed campaign specification: " + shorten_for_message(e.what(), 200));
  }
  if (const std::string why = canonical_error(c); !why.empty()) {
    throw_runtime_error("malformed campaign specification: " + why);
  }
  seal(c);
  return c;
}

Setting setting_at(const ResolvedCampaign& c, long long index) {
  Setting s;
  s.index = index;
  long long rest = index;
  const auto take = [&rest](std::size_t size) {
    const auto n = static_cast<long long>(size);
    const int value = static_cast<int>(rest % n);
    rest /= n;
    return value;
  };
  // The last list varies fastest.
  s.restoration = take(c.restorations.size());
  s.read_noise = take(c.read_noises.values.size());
  s.dt = take(c.dts.values.size());
  s.snr = take(c.snrs.values.size());
  s.restore_velocity = take(c.restore_velocities.size());
  if (c.has_velocity_distributions()) {
    s.velocity_distribution = take(c.velocity_distributions.size());
  }
  s.velocity = take(c.velocities.values.size());
  s.mode = take(c.modes.size());
  s.code = take(c.codes.size());
  s.image = take(c.images.size());
  return s;
}

std::string setting_description(const ResolvedCampaign& c, const Setting& s) {
  const auto& r = c.restore_velocities[s.restore_velocity];
  Json j = {{"image_sha256", c.images[s.image].sha256},
            {"code_sha256", c.codes[s.code].sha256},
            {"mode", to_string(c.modes[s.mode])},
            {"velocity", c.velocities.values[s.velocity]},
            {"restore_velocity", r ? Json(*r) : Json(nullptr)},
            {"snr", c.snrs.values[s.snr]},
            {"dt", c.dts.values[s.dt]}};
  if (c.has_sensor()) {
    j["sensor"] = sensor_json(c);
    j["sensor"].erase("read_noise");
    j["read_noise"] = c.read_noises.values[s.read_noise];
  }
  if (c.has_velocity_distributions()) {
    j.erase("velocity");
    j["velocity_distribution_sha256"] = c.velocity_distributions[s.velocity_distribution].sha256;
  }
  return j.dump();
}

std::uint64_t setting_seed(const ResolvedCampaign& c, const Setting& s) {
  const std::string digest = sha256_hex(setting_description(c, s));
  std::uint64_t h = 0;
  std::from_chars(digest.data(), digest.data() + 16, h, 16);
  std::uint64_t state = c.seed + h;
  return splitmix64(state);
}

SimulationOptions setting_options(const ResolvedCampaign& c, const Setting& s) {
  SimulationOptions o;
  o.mode = c.modes[s.mode];
  o.velocity_px_per_slot = c.velocities.values[s.velocity];
  o.restore_velocity_px_per_slot = c.restore_velocities[s.restore_velocity];
  o.snr = c.snrs.values[s.snr];
  o.dt = c.dts.values[s.dt];
  o.seed = setting_seed(c, s);
  o.noise = c.noise;
  o.rmse_margin_columns = c.rmse_margin_columns;
  o.trials = c.trials;
  o.sensor = c.sensor;
  o.sensor.read_noise_electrons = c.read_noises.values[s.read_noise];
  o.restoration = c.restorations[s.restoration];
  if (c.has_velocity_distributions()) {
    o.velocity_distribution = c.velocity_distributions[s.velocity_distribution].distribution;
  }
  return o;
}

}  // namespace fss

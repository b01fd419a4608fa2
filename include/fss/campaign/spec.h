// A campaign's specification (docs/campaign.md), its canonical form and hash, and the settings
// of its cartesian product (images x codes x modes x velocities x ...) in a stable order, each
// with its own seed. Conventions: fss/fss.h.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fss/core/image.h"
#include "fss/model/code.h"
#include "fss/model/restoration.h"
#include "fss/model/velocity_distribution.h"
#include "fss/pipeline/option_rules.h"
#include "fss/pipeline/simulate.h"

namespace fss {

// Most values one value list may hold, and most settings of a campaign.
inline constexpr int kMaxCampaignValues = 10000;
inline constexpr long long kMaxCampaignSettings = 10'000'000;
// Largest campaign file and campaign image read (checked before reading; a stream is cut there).
inline constexpr std::size_t kMaxCampaignFileBytes = std::size_t{16} << 20;
inline constexpr std::size_t kMaxCampaignImageBytes = std::size_t{1} << 30;

// Values of one swept quantity and how they were written.
struct ValueList {
  std::vector<double> values;
  bool geometric = false;  // some item was a geometric range (a log axis suits it)
};

// Parses `text` for field `field` (named in errors): comma-separated items, each a finite number,
// an arithmetic range start:stop:step (start + i step, the last not beyond stop + step / 2) or a
// geometric one start:stop:xF (start F^i, the last not beyond stop sqrt(F); start and stop > 0,
// F > 1), range values rounded to 12 significant digits. Throws a usage fss::Error naming the
// field and the item.
ValueList parse_value_list(std::string_view text, const std::string& field);

// What the user asked for: the campaign specification before files are read.
struct CampaignSpec {
  std::vector<std::string> inputs;  // PNG files, directories (their *.png) or globs
  std::vector<std::string> codes;   // built-in names or code files
  std::vector<ShutterMode> modes = {ShutterMode::kNumerical};
  std::string velocity = "1";    // value lists (parse_value_list)
  std::string restore_velocity;  // empty: the true velocity
  std::string snr = "100";
  std::string dt = "1";
  int trials = 1;
  std::uint64_t seed = 0;
  NoiseModel noise = NoiseModel::kPoisson;
  // The RMSE margin: kRmseMarginAuto (3B where the image is wide enough, else the largest margin
  // leaving a window of B columns: no setting lost to a narrow image), kRmseMarginDefault (3B) or
  // a number of columns (option_rules.h).
  int rmse_margin_columns = kRmseMarginAuto;
  bool per_trial = false;  // also one row per trial (trials.csv, trials.jsonl)
  // The sensor (docs/method.md §10): the read noise is an axis (a value list, electrons RMS per
  // readout), the other parts are fixed; sensor.read_noise_electrons is not used.
  std::string read_noise = "0";
  SensorModel sensor;
  // The restorations (docs/method.md §12), an axis of restoration variants, each list's strings
  // holding one item or several, comma-separated: the methods (empty: the inverse filter only),
  // Tikhonov's lambdas (value list items or the word "optimal"; empty: optimal) and Wiener's
  // priors ("power-law", "power-law:GAMMA", "oracle"; empty: power-law:2). A lambda or a prior
  // without its method in `restorations` is refused.
  std::vector<std::string> restorations;
  std::vector<std::string> regularization;
  std::vector<std::string> priors;
  // Distributions of velocities (docs/method.md §13), an axis in place of the velocities: each
  // item a spec ("uniform:LO:HI", "normal:MEAN:SD", "normal:MEAN:SD:LO:HI") or the path of a
  // file of "velocity weight" lines (load_velocity_distribution). Empty: the velocity axis. With
  // distributions, `velocity` must keep its default "1", as SimulationOptions's velocity does.
  std::vector<std::string> velocity_distributions;

  // False, with a message naming the field, its value and the rule, when a field is malformed on
  // its own (values a setting cannot run with, such as snr = 0, are rows with a status instead).
  bool IsValid(std::string* error) const;
};

// Parses the text of a campaign file (docs/campaign.md), a JSON object; fields it does not name
// keep their defaults, value lists are kept as text for CampaignSpec::IsValid. Throws a usage
// fss::Error naming the file (`name`) for malformed JSON, an unknown key or a value of the wrong
// type.
CampaignSpec parse_campaign_file(std::string_view text, const std::string& name);

// Reads the campaign file at `path` (at most kMaxCampaignFileBytes; a
// runtime fss::Error naming it when larger or unreadable) and parses it.
CampaignSpec read_campaign_file(const std::string& path);

// One image of a campaign: its name (the path as expanded), path and digest.
struct CampaignImage {
  std::string name;
  std::string path;
  std::string sha256;  // of the file's bytes
};

// One distribution of velocities: its name (the spec's canonical text, or the file's path as
// given), the distribution, and the digest of its canonical text (a file's points, one
// "velocity weight" a line in shortest round-trip form).
struct CampaignDistribution {
  std::string name;
  VelocityDistribution distribution;
  std::string sha256;
};

// One code: its name as given, its gains and the digest of their canonical
// text (one gain a line, shortest round-trip decimal).
struct CampaignCode {
  std::string name;
  ShutterCode code;
  std::string sha256;
};

// The specification with its files read and its lists expanded: what the
// campaign hash covers.
// The current version of the aggregated noise's sampler (ResolvedCampaign::aggregated_sampler).
inline constexpr int kAggregatedSamplerVersion = 2;

struct ResolvedCampaign {
  std::vector<CampaignImage> images;
  std::vector<CampaignCode> codes;
  std::vector<ShutterMode> modes;
  ValueList velocities;
  std::vector<std::optional<double>> restore_velocities;  // {nullopt}: the true velocity
  bool restore_geometric = false;
  ValueList snrs;
  ValueList dts;
  int trials = 1;
  std::uint64_t seed = 0;
  NoiseModel noise = NoiseModel::kPoisson;
  // The aggregated noise's sampler (noise aggregated only): 1 before the frames of equal gains
  // were drawn as one exact Poisson variate, 2 since (docs/method.md §6c). A new campaign has the
  // current one, a journal's specification its own; named in the canonical JSON for aggregated
  // noise only, so that a directory of the other sampler is not resumed with these draws.
  int aggregated_sampler = kAggregatedSamplerVersion;
  int rmse_margin_columns = kRmseMarginAuto;
  bool per_trial = false;
  ValueList read_noises = {{0.0}, false};  // the read noise axis
  SensorModel sensor;                      // the fixed parts; its read noise unused
  // The restoration variants, an axis: the inverse filter once, Tikhonov at each lambda, Wiener
  // with each prior, in the order the methods were given; each variant once.
  std::vector<RestorationOptions> restorations = {RestorationOptions{}};
  // The distributions of velocities, an axis in place of the velocities (which are then {1},
  // unused); empty: none, each setting has a velocity.
  std::vector<CampaignDistribution> velocity_distributions;

  // True when the campaign uses a sensor (a read noise other than {0} or a fixed part on): only
  // then do the canonical JSON and the settings' descriptions name the sensor.
  bool has_sensor() const;
  // True when the restorations are other than the inverse filter alone: only then does the
  // canonical JSON name them.
  bool has_restorations() const;
  // True when the settings run under velocity distributions: only then do the canonical JSON,
  // the settings' descriptions and the result files name them (results schema 4).
  bool has_velocity_distributions() const { return !velocity_distributions.empty(); }

  // Canonical JSON of everything above (one line, keys sorted, numbers in shortest round-trip
  // form) and its SHA-256: specifications that run the same settings have the same hash.
  std::string canonical_json;
  std::string sha256;

  long long setting_count() const;
};

// Reads and expands `spec`: directories give their *.png files, globs their matches, each sorted
// by name; codes are loaded (load_code); an image path or code name given twice is kept once, at
// its first place. Throws a usage fss::Error for an invalid spec or an input that matches
// nothing, a runtime one for a file that cannot be read.
ResolvedCampaign resolve_campaign(const CampaignSpec& spec);

// Rebuilds a resolved campaign from its canonical JSON (as a journal keeps
// it), without reading any file. Throws a runtime fss::Error if malformed.
ResolvedCampaign campaign_from_canonical_json(const std::string& json);

// One setting of the product, by the index of each of its values.
struct Setting {
  long long index = 0;  // position in the product's order
  int image = 0, code = 0, mode = 0, velocity = 0, restore_velocity = 0, snr = 0, dt = 0;
  int read_noise = 0;
  int restoration = 0;
  // The index into ResolvedCampaign::velocity_distributions; -1 in a campaign without them.
  int velocity_distribution = -1;
};

// The setting at position `index` of the product, in the order images,
// codes, modes, velocities (or velocity distributions), restore velocities, snrs, dts, read
// noises, restorations (the last varies fastest).
Setting setting_at(const ResolvedCampaign& campaign, long long index);

// The setting's canonical description, one line of JSON: the digests of its image and code and
// its values (with a sensor, its read noise and the fixed sensor parts; under a velocity
// distribution, the distribution's canonical text or digest in place of the velocity); not the
// campaign's trials, noise and margin, so that more trials extend a setting's seeds, nor its
// restoration, so that the restorations of one observation restore the same noisy images.
std::string setting_description(const ResolvedCampaign& campaign, const Setting& setting);

// The setting's seed: splitmix64 of the campaign seed plus the first 64 bits of
// SHA-256(description), so it depends on the setting's values only, never on its index, shard or
// the order of the run; its trials use seed, seed + 1, ...
std::uint64_t setting_seed(const ResolvedCampaign& campaign, const Setting& setting);

// The SimulationOptions of a setting (threads and memory limit left at
// their defaults for the caller).
SimulationOptions setting_options(const ResolvedCampaign& campaign, const Setting& setting);

}  // namespace fss

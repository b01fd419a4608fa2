#include "fss/model/velocity_distribution.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <queue>
#include <string>

#include "core/number_text.h"
#include "fss/core/error.h"
#include "model/noise_stream.h"

namespace fss {

namespace {

bool fail(std::string* error, const std::string& message) {
  if (error) *error = message;
  return false;
}

std::string velocity_rule(double v) {
  if (!(std::isfinite(v) && std::abs(v) <= kMaxDistributionVelocity)) {
    return "must be a finite number with |v| <= " + format_exact(kMaxDistributionVelocity);
  }
  return "";
}

// Phi, the standard normal distribution function.
double normal_cdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

// P(V <= v) of the truncated normal.
double truncated_normal_cdf(const VelocityDistribution& d, double v) {
  const double a = normal_cdf((d.low - d.mean) / d.sd);
  const double b = normal_cdf((d.high - d.mean) / d.sd);
  const double x = normal_cdf((std::clamp(v, d.low, d.high) - d.mean) / d.sd);
  return (x - a) / (b - a);
}

// The probability mass of [low, high] under the untruncated normal.
double normal_mass(const VelocityDistribution& d) {
  return normal_cdf((d.high - d.mean) / d.sd) - normal_cdf((d.low - d.mean) / d.sd);
}

// Nodes and weights of the n-point Gauss-Legendre rule on [-1, 1], by Newton's method on P_n.
void gauss_legendre(int n, std::vector<double>* x, std::vector<double>* w) {
  x->assign(static_cast<std::size_t>(n), 0.0);
  w->assign(static_cast<std::size_t>(n), 0.0);
  for (int i = 0; i < n; ++i) {
    double t = std::cos(M_PI * (i + 0.75) / (n + 0.5));
    double derivative = 1.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1.0;
      double p1 = t;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * t * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      // P_n'(t) = n (t P_n - P_{n-1}) / (t^2 - 1)
      derivative = n * (t * p1 - p0) / (t * t - 1.0);
      const double step = p1 / derivative;
      t -= step;
      if (std::abs(step) < 1e-16) break;
    }
    (*x)[static_cast<std::size_t>(i)] = t;
    (*w)[static_cast<std::size_t>(i)] = 2.0 / ((1.0 - t * t) * derivative * derivative);
  }
}

// The 15-point Kronrod rule on [-1, 1] and its embedded 7-point Gauss rule (published values):
// the non-negative nodes, the node 0 last.
constexpr std::array<double, 8> kKronrodNodes = {
    0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
    0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
    0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
    0.207784955007898467600689403773245, 0.000000000000000000000000000000000};
constexpr std::array<double, 8> kKronrodWeights = {
    0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
    0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
    0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
    0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
// Gauss weights of the Kronrod nodes 1, 3, 5 (odd indices) and 7 (the centre).
constexpr std::array<double, 4> kGaussWeights = {
    0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
    0.381830050505118944950369775488975, 0.417959183673469387755102040816327};

struct Interval {
  double a = 0.0;
  double b = 0.0;
  double kronrod = 0.0;
  double error = 0.0;
  bool operator<(const Interval& other) const { return error < other.error; }
};

// The Kronrod and Gauss sums of f times the density on [a, b].
Interval kronrod_interval(const VelocityDistribution& d, const std::function<double(double)>& f,
                          double a, double b, int* evaluations) {
  const double centre = 0.5 * (a + b);
  const double half = 0.5 * (b - a);
  double kronrod = 0.0;
  double gauss = 0.0;
  for (std::size_t i = 0; i < kKronrodNodes.size(); ++i) {
    const int signs = i + 1 == kKronrodNodes.size() ? 1 : 2;
    for (int s = 0; s < signs; ++s) {
      const double v = centre + (s == 0 ? 1.0 : -1.0) * half * kKronrodNodes[i];
      const double value = f(v) * d.density(v);
      ++*evaluations;
      kronrod += kKronrodWeights[i] * value;
      if (i % 2 == 1) gauss += kGaussWeights[i / 2] * value;
    }
  }
  return {a, b, half * kronrod, std::abs(half * (kronrod - gauss))};
}

void add_kronrod_rule(const VelocityDistribution& d, const Interval& interval,
                      std::vector<VelocityNode>* rule) {
  const double centre = 0.5 * (interval.a + interval.b);
  const double half = 0.5 * (interval.b - interval.a);
  for (std::size_t i = 0; i < kKronrodNodes.size(); ++i) {
    const int signs = i + 1 == kKronrodNodes.size() ? 1 : 2;
    for (int s = 0; s < signs; ++s) {
      const double v = centre + (s == 0 ? 1.0 : -1.0) * half * kKronrodNodes[i];
      rule->push_back({v, half * kKronrodWeights[i] * d.density(v)});
    }
  }
}

// E[f] of a distribution with finitely many velocities: the exact weighted sum.
VelocityExpectation expected_over_points(const std::vector<VelocityPoint>& points,
                                         const std::function<double(double)>& f,
                                         std::vector<VelocityNode>* rule) {
  VelocityExpectation e;
  for (const VelocityPoint& p : points) {
    e.value += p.weight * f(p.velocity);
    ++e.evaluations;
    if (rule) rule->push_back({p.velocity, p.weight});
  }
  return e;
}

std::vector<VelocityPoint> support_points(const VelocityDistribution& d) {
  if (d.kind == VelocityDistributionKind::kDiscrete) return d.points;
  return {{d.low, 1.0}};
}

}  // namespace

bool VelocityDistribution::IsValid(std::string* error) const {
  for (const auto& [name, value] : {std::pair<const char*, double>{"low", low}, {"high", high}}) {
    if (const std::string rule = velocity_rule(value); !rule.empty()) {
      return fail(error, std::string("velocity distribution ") + name + " = " +
                             format_exact(value) + ": " + rule);
    }
  }
  if (kind == VelocityDistributionKind::kNormal &&
      !(std::isfinite(sd) && sd > 0.0 && sd <= kMaxDistributionVelocity)) {
    return fail(error, "normal velocity distribution: sd " + format_exact(sd) +
                           " must be > 0 and at most " + format_exact(kMaxDistributionVelocity));
  }
  if (!(low <= high)) {
    return fail(error, "velocity distribution [" + format_exact(low) + ", " + format_exact(high) +
                           "]: the lower bound must not exceed the upper one");
  }
  switch (kind) {
    case VelocityDistributionKind::kUniform:
      return true;
    case VelocityDistributionKind::kNormal:
      if (!(std::isfinite(mean) && std::abs(mean) <= kMaxDistributionVelocity)) {
        return fail(error, "normal velocity distribution: mean " + format_exact(mean) + " " +
                               velocity_rule(mean));
      }
      if (!(low < high) || !(normal_mass(*this) > 1e-12)) {
        return fail(error, "normal velocity distribution of mean " + format_exact(mean) +
                               " and sd " + format_exact(sd) + " truncated to [" +
                               format_exact(low) + ", " + format_exact(high) +
                               "]: the interval must be wider than a point and hold a "
                               "probability above 1e-12");
      }
      return true;
    case VelocityDistributionKind::kDiscrete:
      if (points.empty()) return fail(error, "discrete velocity distribution: no velocity");
      for (const VelocityPoint& p : points) {
        if (!velocity_rule(p.velocity).empty() || !(std::isfinite(p.weight) && p.weight > 0.0)) {
          return fail(error, "discrete velocity distribution: velocity " +
                                 format_exact(p.velocity) + " with weight " +
                                 format_exact(p.weight) + " (velocities finite with |v| <= " +
                                 format_exact(kMaxDistributionVelocity) +
                                 ", weights finite and > 0)");
        }
      }
      return true;
  }
  return true;
}

double VelocityDistribution::max_abs_velocity() const {
  return std::max(std::abs(low), std::abs(high));
}

bool VelocityDistribution::is_point() const {
  if (kind == VelocityDistributionKind::kDiscrete) return points.size() == 1;
  return kind == VelocityDistributionKind::kUniform && low == high;
}

double VelocityDistribution::density(double v) const {
  if (kind == VelocityDistributionKind::kDiscrete || is_point() || v < low || v > high) return 0.0;
  if (kind == VelocityDistributionKind::kUniform) return 1.0 / (high - low);
  const double z = (v - mean) / sd;
  return std::exp(-0.5 * z * z) / (sd * std::sqrt(2.0 * M_PI) * normal_mass(*this));
}

double VelocityDistribution::quantile(double u) const {
  if (!(u > 0.0))
    return kind == VelocityDistributionKind::kDiscrete ? points.front().velocity : low;
  if (u >= 1.0) return high;
  switch (kind) {
    case VelocityDistributionKind::kUniform:
      return std::min(high, low + u * (high - low));
    case VelocityDistributionKind::kNormal: {
      // Bisection on the truncated distribution function to the last bit.
      double a = low;
      double b = high;
      for (int step = 0; step < 200 && a < b; ++step) {
        const double m = 0.5 * (a + b);
        if (m <= a || m >= b) break;
        (truncated_normal_cdf(*this, m) < u ? a : b) = m;
      }
      return b;
    }
    case VelocityDistributionKind::kDiscrete: {
      double cumulative = 0.0;
      for (const VelocityPoint& p : points) {
        cumulative += p.weight;
        if (cumulative >= u) return p.velocity;
      }
      return points.back().velocity;
    }
  }
  return low;
}

double VelocityDistribution::expected_velocity() const {
  switch (kind) {
    case VelocityDistributionKind::kUniform:
      return 0.5 * (low + high);
    case VelocityDistributionKind::kNormal: {
      // mu + sd (phi(a) - phi(b)) / (Phi(b) - Phi(a)), a and b the standardised bounds
      const auto phi = [](double z) { return std::exp(-0.5 * z * z) / std::sqrt(2.0 * M_PI); };
      const double a = (low - mean) / sd;
      const double b = (high - mean) / sd;
      return mean + sd * (phi(a) - phi(b)) / normal_mass(*this);
    }
    case VelocityDistributionKind::kDiscrete: {
      double sum = 0.0;
      for (const VelocityPoint& p : points) sum += p.weight * p.velocity;
      return sum;
    }
  }
  return low;
}

std::string VelocityDistribution::text() const {
  switch (kind) {
    case VelocityDistributionKind::kUniform:
      return "uniform:" + format_exact(low) + ":" + format_exact(high);
    case VelocityDistributionKind::kNormal:
      return "normal:" + format_exact(mean) + ":" + format_exact(sd) +
             (bounds_given ? ":" + format_exact(low) + ":" + format_exact(high) : "");
    case VelocityDistributionKind::kDiscrete:
      return source.empty() ? "discrete" : source;
  }
  return "";
}

std::string VelocityDistribution::describe() const {
  std::string support = "[" + format_number(low) + ", " + format_number(high) + "]";
  switch (kind) {
    case VelocityDistributionKind::kUniform:
      return "uniform on " + support;
    case VelocityDistributionKind::kNormal:
      return "normal of mean " + format_number(mean) + ", sd " + format_number(sd) +
             (bounds_given ? ", truncated to " + support
                           : ", truncated at mean +/- " + format_number(kDefaultNormalTruncation) +
                                 " sd to " + support) +
             " and renormalised";
    case VelocityDistributionKind::kDiscrete:
      return std::to_string(points.size()) + (points.size() == 1 ? " velocity" : " velocities") +
             (source.empty() ? "" : " from '" + escape_control_characters(source) + "'") + " in " +
             support;
  }
  return support;
}

bool parse_velocity_distribution(std::string_view text, VelocityDistribution* distribution,
                                 std::string* error) {
  const auto bad = [&](const std::string& why) {
    return fail(error, "velocity distribution '" + shorten_for_message(text) + "': " + why +
                           " (expected uniform:LO:HI, normal:MEAN:SD, normal:MEAN:SD:LO:HI or a "
                           "file of 'velocity weight' lines)");
  };
  std::vector<std::string_view> fields;
  for (std::size_t start = 0;;) {
    const std::size_t colon = text.find(':', start);
    fields.push_back(text.substr(start, colon == std::string_view::npos ? colon : colon - start));
    if (colon == std::string_view::npos) break;
    start = colon + 1;
  }
  std::vector<double> numbers;
  for (std::size_t i = 1; i < fields.size(); ++i) {
    numbers.push_back(parse_finite_number(fields[i]));
    if (std::isnan(numbers.back())) {
      return bad("'" + shorten_for_message(fields[i]) + "' is not a finite number");
    }
  }
  VelocityDistribution d;
  if (fields[0] == "uniform" && numbers.size() == 2) {
    d.kind = VelocityDistributionKind::kUniform;
    d.low = numbers[0] + 0.0;
    d.high = numbers[1] + 0.0;
  } else if (fields[0] == "normal" && (numbers.size() == 2 || numbers.size() == 4)) {
    d.kind = VelocityDistributionKind::kNormal;
    d.mean = numbers[0] + 0.0;
    d.sd = numbers[1];
    d.bounds_given = numbers.size() == 4;
    d.low = d.bounds_given ? numbers[2] + 0.0 : d.mean - kDefaultNormalTruncation * d.sd;
    d.high = d.bounds_given ? numbers[3] + 0.0 : d.mean + kDefaultNormalTruncation * d.sd;
  } else if (fields[0] == "uniform" || fields[0] == "normal") {
    return bad("wrong number of fields");
  } else {
    return bad("unknown distribution");
  }
  std::string rule;
  if (!d.IsValid(&rule)) {
    // The syntax was right: the spec and the rule, without the list of forms.
    constexpr std::string_view kPrefix = "velocity distribution ";
    if (std::string_view(rule).substr(0, kPrefix.size()) == kPrefix) rule.erase(0, kPrefix.size());
    return fail(error, "velocity distribution '" + shorten_for_message(text) + "': " + rule);
  }
  *distribution = std::move(d);
  return true;
}

bool discrete_velocity_distribution(std::vector<VelocityPoint> points, std::string source,
                                    VelocityDistribution* distribution, std::string* error) {
  if (points.empty()) return fail(error, "discrete velocity distribution: no velocity");
  if (points.size() > static_cast<std::size_t>(kMaxDiscreteVelocities)) {
    return fail(error, "discrete velocity distribution: " + std::to_string(points.size()) +
                           " velocities, more than the " + std::to_string(kMaxDiscreteVelocities) +
                           " allowed");
  }
  double total = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const VelocityPoint& p = points[i];
    if (!velocity_rule(p.velocity).empty() || !(std::isfinite(p.weight) && p.weight > 0.0)) {
      return fail(error, "discrete velocity distribution, velocity " + std::to_string(i + 1) +
                             ": '" + format_exact(p.velocity) + " " + format_exact(p.weight) +
                             "' (the velocity finite with |v| <= " +
                             format_exact(kMaxDistributionVelocity) +
                             ", the weight finite and > 0)");
    }
    total += p.weight;
  }
  if (!std::isfinite(total)) {
    return fail(error, "discrete velocity distribution: the weights sum beyond double precision");
  }
  std::stable_sort(
      points.begin(), points.end(),
      [](const VelocityPoint& a, const VelocityPoint& b) { return a.velocity < b.velocity; });
  VelocityDistribution d;
  d.kind = VelocityDistributionKind::kDiscrete;
  for (const VelocityPoint& p : points) {
    const double v = p.velocity + 0.0;  // -0 is 0
    if (!d.points.empty() && d.points.back().velocity == v) {
      d.points.back().weight += p.weight / total;
    } else {
      d.points.push_back({v, p.weight / total});
    }
  }
  d.low = d.points.front().velocity;
  d.high = d.points.back().velocity;
  d.source = std::move(source);
  *distribution = std::move(d);
  return true;
}

double trial_velocity(const VelocityDistribution& distribution, std::uint64_t seed,
                      std::uint64_t trial) {
  // A stream of its own: channel coordinate 2^31, which no image channel (c) and no calibration
  // observation (2^30 + c) uses; the trial is its row coordinate.
  constexpr std::uint64_t kVelocityChannel = std::uint64_t{1} << 31;
  RandomStream stream(seed, kVelocityChannel, 0, trial);
  const double u = stream.uniform();
  return distribution.quantile(u);
}

std::vector<VelocityNode> composite_gauss_nodes(const VelocityDistribution& distribution,
                                                int panels, int order) {
  if (panels < 1 || order < 1 || order > 64) {
    throw_usage_error("composite Gauss rule of " + std::to_string(panels) + " panels of " +
                      std::to_string(order) + " nodes: need panels >= 1 and 1 <= order <= 64");
  }
  std::vector<VelocityNode> nodes;
  if (distribution.kind == VelocityDistributionKind::kDiscrete || distribution.is_point()) {
    for (const VelocityPoint& p : support_points(distribution)) {
      nodes.push_back({p.velocity, p.weight});
    }
    return nodes;
  }
  std::vector<double> x;
  std::vector<double> w;
  gauss_legendre(order, &x, &w);
  const double width = (distribution.high - distribution.low) / panels;
  double total = 0.0;
  for (int p = 0; p < panels; ++p) {
    const double centre = distribution.low + (p + 0.5) * width;
    for (int i = 0; i < order; ++i) {
      const double v = centre + 0.5 * width * x[static_cast<std::size_t>(i)];
      const double weight = 0.5 * width * w[static_cast<std::size_t>(i)] * distribution.density(v);
      nodes.push_back({v, weight});
      total += weight;
    }
  }
  for (VelocityNode& node : nodes) node.weight /= total;
  return nodes;
}

VelocityExpectation expected_over_velocity(const VelocityDistribution& distribution,
                                           const std::function<double(double)>& f,
                                           double relative_tolerance, int max_intervals,
                                           std::vector<VelocityNode>* rule, int initial_intervals) {
  if (rule) rule->clear();
  if (distribution.kind == VelocityDistributionKind::kDiscrete || distribution.is_point()) {
    return expected_over_points(support_points(distribution), f, rule);
  }
  VelocityExpectation e;
  std::priority_queue<Interval> queue;
  const int pieces = std::max(initial_intervals, 1);
  const double width = (distribution.high - distribution.low) / pieces;
  double value = 0.0;
  double error = 0.0;
  for (int p = 0; p < pieces; ++p) {
    const double a = distribution.low + p * width;
    const double b = p + 1 == pieces ? distribution.high : distribution.low + (p + 1) * width;
    const Interval piece = kronrod_interval(distribution, f, a, b, &e.evaluations);
    value += piece.kronrod;
    error += piece.error;
    queue.push(piece);
  }
  int intervals = pieces;
  while (std::isfinite(value) && error > relative_tolerance * std::abs(value)) {
    if (intervals >= max_intervals) {
      e.converged = false;
      break;
    }
    const Interval worst = queue.top();
    queue.pop();
    const double middle = 0.5 * (worst.a + worst.b);
    const Interval left = kronrod_interval(distribution, f, worst.a, middle, &e.evaluations);
    const Interval right = kronrod_interval(distribution, f, middle, worst.b, &e.evaluations);
    queue.push(left);
    queue.push(right);
    ++intervals;
    // The sums again from the intervals, so that round-off does not build up.
    value = 0.0;
    error = 0.0;
    for (std::priority_queue<Interval> copy = queue; !copy.empty(); copy.pop()) {
      value += copy.top().kronrod;
      error += copy.top().error;
    }
  }
  e.value = std::isnan(value) ? std::numeric_limits<double>::infinity() : value;
  e.error_estimate = error;
  e.intervals = intervals;
  if (rule) {
    std::vector<Interval> finals;
    for (; !queue.empty(); queue.pop()) finals.push_back(queue.top());
    std::sort(finals.begin(), finals.end(),
              [](const Interval& a, const Interval& b) { return a.a < b.a; });
    for (const Interval& interval : finals) add_kronrod_rule(distribution, interval, rule);
  }
  return e;
}

}  // namespace fss

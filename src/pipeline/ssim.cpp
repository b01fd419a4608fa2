#include "pipeline/ssim.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "core/parallel.h"
#include "core/vectorize.h"
#include "fss/core/error.h"

namespace fss {

namespace {

constexpr int kRadius = kSsimRadius;
constexpr int kTaps = 2 * kRadius + 1;
// A work item: up to kTileColumns output columns of up to kBlockRows output rows of one channel.
// Both are fixed, so the order of the sums is the same for any thread count.
constexpr int kTileColumns = 512;
constexpr int kBlockRows = 32;

// C1 = (K1 L)^2, C2 = (K2 L)^2 with K1 = 0.01, K2 = 0.03, L = 255.
constexpr double kC1 = (0.01 * 255.0) * (0.01 * 255.0);
constexpr double kC2 = (0.03 * 255.0) * (0.03 * 255.0);

// w[k] for k = 0..r: the 1-D Gaussian weight at distance k, exp(-k^2 / (2 sigma^2)) divided by
// the sum over j = -r..r of exp(-j^2 / (2 sigma^2)). The 2-D weights are w[|i|] w[|j|].
using HalfWeights = std::array<double, kRadius + 1>;

HalfWeights gaussian_half_weights() {
  std::array<double, kTaps> phi{};
  double sum = 0.0;
  for (int i = 0; i < kTaps; ++i) {
    const int k = i - kRadius;
    phi[i] = std::exp(-0.5 / (kSsimSigma * kSsimSigma) * static_cast<double>(k * k));
    sum += phi[i];
  }
  HalfWeights w{};
  for (int k = 0; k <= kRadius; ++k) w[k] = phi[kRadius + k] / sum;
  return w;
}

std::string size_text(const Image& image) {
  return std::to_string(image.width) + "x" + std::to_string(image.height) + "x" +
         std::to_string(image.channels);
}

// input's columns [offset, offset + restored.width) face restored's columns, and [first, end) is
// a non-empty window of restored's columns.
void require_window(const Image& input, int offset, const Image& restored, int first, int end) {
  if (input.height != restored.height || input.channels != restored.channels || offset < 0 ||
      offset > input.width - restored.width) {
    throw_usage_error("image " + size_text(restored) + " cannot face columns [" +
                      std::to_string(offset) + ", " + std::to_string(offset + restored.width) +
                      ") of image " + size_text(input));
  }
  if (first < 0 || end > restored.width || first >= end) {
    throw_usage_error("column window [" + std::to_string(first) + ", " + std::to_string(end) +
                      ") is empty or outside an image of width " + std::to_string(restored.width));
  }
}

// The maps filtered, shifted by a constant t near the values (the ground truth's mean over the
// strip, per channel) so that the variances keep their precision at any level: g' = g - t,
// x' = x - t, q = g'^2 + x'^2 and p = g' x'. The variances enter SSIM only through their sum,
// s_g^2 + s_x^2 = E[q] - mu_g'^2 - mu_x'^2, and the covariance is E[p] - mu_g' mu_x'; the means
// are mu_g = mu_g' + t, mu_x = mu_x' + t.
//
// The shifted values and products of one row over n columns.
[[gnu::always_inline]] inline void product_row(const double* __restrict g,
                                               const double* __restrict x, double t, int n,
                                               double* __restrict gs, double* __restrict xs,
                                               double* __restrict q, double* __restrict p) {
  for (int i = 0; i < n; ++i) {
    const double a = g[i] - t;
    const double b = x[i] - t;
    gs[i] = a;
    xs[i] = b;
    q[i] = a * a + b * b;
    p[i] = a * b;
  }
}

// Row pointers of the 2r + 1 rows around an output row (index r + k for row k = -r..r), each from
// the first column of the strip.
struct Neighbourhood {
  std::array<const double*, kTaps> g, x, q, p;
};

// The vertical pass of one map at one output row, over the n columns of the strip, rows[r + k]
// pointing at row k (k = -r..r):
//   v[i] = w0 m(0, i) + sum_{k = r..1} w_k (m(-k, i) + m(k, i)).
[[gnu::always_inline]] inline void filter_column(const std::array<const double*, kTaps>& rows,
                                                 const HalfWeights& w, int n,
                                                 double* __restrict v) {
  for (int i = 0; i < n; ++i) {
    double sum = rows[kRadius][i] * w[0];
    for (int k = kRadius; k >= 1; --k) sum += (rows[kRadius - k][i] + rows[kRadius + k][i]) * w[k];
    v[i] = sum;
  }
}

// The horizontal pass of one map over n output columns, from its vertical pass v (output column
// i at strip column i + r):
//   h[i] = w0 v[i + r] + sum_{k = r..1} w_k (v[i + r - k] + v[i + r + k]).
[[gnu::always_inline]] inline void filter_row(const double* __restrict v, const HalfWeights& w,
                                              int n, double* __restrict h) {
  for (int i = 0; i < n; ++i) {
    const double* c = v + i + kRadius;
    double sum = c[0] * w[0];
    for (int k = kRadius; k >= 1; --k) sum += (c[-k] + c[k]) * w[k];
    h[i] = sum;
  }
}

// SSIM at n output columns from the filtered shifted maps mu_g', mu_x', E[q], E[p] and the
// shift t:
//   mu = mu' + t,
//   (2 mu_g mu_x + C1)(2 (E[p] - mu_g' mu_x') + C2) /
//   ((mu_g^2 + mu_x^2 + C1)(E[q] - mu_g'^2 - mu_x'^2 + C2)).
[[gnu::always_inline]] inline void ssim_row(const double* __restrict mu_g,
                                            const double* __restrict mu_x,
                                            const double* __restrict e_q,
                                            const double* __restrict e_p, double t, int n,
                                            double* __restrict s) {
  for (int i = 0; i < n; ++i) {
    const double dg = mu_g[i];
    const double dx = mu_x[i];
    const double mg = dg + t;
    const double mx = dx + t;
    const double a1 = 2.0 * mg * mx + kC1;
    const double a2 = 2.0 * (e_p[i] - dg * dx) + kC2;
    const double b1 = (mg * mg + mx * mx) + kC1;
    const double b2 = (e_q[i] - (dg * dg + dx * dx)) + kC2;
    s[i] = (a1 * a2) / (b1 * b2);
  }
}

// s[0] + ... + s[n - 1] as four partial sums of the indices i mod 4, then (p0 + p1) + (p2 + p3).
[[gnu::always_inline]] inline double fixed_order_sum(const double* __restrict s, int n) {
  std::array<double, 4> p{};
  int i = 0;
  for (; i + 4 <= n; i += 4) {
    for (int j = 0; j < 4; ++j) p[j] += s[i + j];
  }
  for (int j = 0; i < n; ++i, ++j) p[j] += s[i];
  return (p[0] + p[1]) + (p[2] + p[3]);
}

// A thread's scratch: a row's vertical pass of one map (over a tile's strip), its four maps
// filtered and its SSIM (over a tile), and the shifted values and products of the last 2r + 1
// rows (row y in slot y mod (2r + 1), over a tile's strip).
struct Scratch {
  static constexpr int kStrip = kTileColumns + 2 * kRadius;
  std::vector<double> v = std::vector<double>(kStrip);
  std::vector<double> mu_g = std::vector<double>(kTileColumns), mu_x = mu_g, e_q = mu_g, e_p = mu_g;
  std::vector<double> s = std::vector<double>(kTileColumns);
  std::vector<double> gs = std::vector<double>(kTaps * kStrip), xs = gs, q = gs, p = gs;
  static double* slot(std::vector<double>& ring, int y) {
    return ring.data() + static_cast<std::size_t>(y % kTaps) * kStrip;
  }
  double* gs_row(int y) { return slot(gs, y); }
  double* xs_row(int y) { return slot(xs, y); }
  double* q_row(int y) { return slot(q, y); }
  double* p_row(int y) { return slot(p, y); }
  // the products of row y into its slots
  void products(const double* g, const double* x, double t, int n, int y) {
    product_row(g, x, t, n, gs_row(y), xs_row(y), q_row(y), p_row(y));
  }
};

// The work: output columns [first, end) and rows [r, height - r) of every channel, cut into
// items of kBlockRows rows by kTileColumns columns; `sums` holds one SSIM sum per channel, row
// and tile, in that order.
struct Work {
  const Image& input;
  int offset;
  const Image& restored;
  int first;
  int end;
  int rows;    // height - 2r output rows
  int blocks;  // row blocks a channel
  int tiles;   // column tiles a row
  HalfWeights w;
  std::vector<double> shifts;  // t of each channel
  std::vector<double> sums;
};

// The SSIM sum of output row y over the n columns of the strip starting at column x0 - r of the
// restoration: the products of row y + r, the vertical pass, the horizontal pass and the formula.
double row_sum(const Work& work, int c, int y, int x0, int n, Scratch& scratch) {
  const int strip = n + 2 * kRadius;
  const double t = work.shifts[static_cast<std::size_t>(c)];
  const int last = y + kRadius;  // the row entering the neighbourhood
  const double* g_last = work.input.row(c, last) + work.offset + x0 - kRadius;
  const double* x_last = work.restored.row(c, last) + x0 - kRadius;
  Neighbourhood rows;
  for (int j = 0; j < kTaps; ++j) {
    rows.g[j] = scratch.gs_row(y - kRadius + j);
    rows.x[j] = scratch.xs_row(y - kRadius + j);
    rows.q[j] = scratch.q_row(y - kRadius + j);
    rows.p[j] = scratch.p_row(y - kRadius + j);
  }
  const HalfWeights w = work.w;
  double sum = 0.0;
  detail::run_vectorized([&]() __attribute__((always_inline)) {
    scratch.products(g_last, x_last, t, strip, last);
    filter_column(rows.g, w, strip, scratch.v.data());
    filter_row(scratch.v.data(), w, n, scratch.mu_g.data());
    filter_column(rows.x, w, strip, scratch.v.data());
    filter_row(scratch.v.data(), w, n, scratch.mu_x.data());
    filter_column(rows.q, w, strip, scratch.v.data());
    filter_row(scratch.v.data(), w, n, scratch.e_q.data());
    filter_column(rows.p, w, strip, scratch.v.data());
    filter_row(scratch.v.data(), w, n, scratch.e_p.data());
    ssim_row(scratch.mu_g.data(), scratch.mu_x.data(), scratch.e_q.data(), scratch.e_p.data(), t, n,
             scratch.s.data());
    sum = fixed_order_sum(scratch.s.data(), n);
  });
  return sum;
}

// Item `item`: the SSIM sums of its rows over its tile, after the products of the 2r rows above
// its first row.
void run_item(Work& work, int item, Scratch& scratch) {
  const int c = item / (work.blocks * work.tiles);
  const int block = item / work.tiles % work.blocks;
  const int tile = item % work.tiles;
  const int x0 = work.first + tile * kTileColumns;
  const int n = std::min(kTileColumns, work.end - x0);
  const int y_begin = kRadius + block * kBlockRows;
  const int y_end = std::min(y_begin + kBlockRows, kRadius + work.rows);
  const double t = work.shifts[static_cast<std::size_t>(c)];
  for (int y = y_begin - kRadius; y < y_begin + kRadius; ++y) {
    detail::run_vectorized([&]() __attribute__((always_inline)) {
      scratch.products(work.input.row(c, y) + work.offset + x0 - kRadius,
                       work.restored.row(c, y) + x0 - kRadius, t, n + 2 * kRadius, y);
    });
  }
  for (int y = y_begin; y < y_end; ++y) {
    const auto row = static_cast<std::size_t>(c) * work.rows + (y - kRadius);
    work.sums[row * work.tiles + tile] = row_sum(work, c, y, x0, n, scratch);
  }
}

// t of channel c: the mean of the ground truth over the strip [first - r, end + r) of every row,
// summed in row order.
double strip_mean(const Image& input, int offset, int c, int first, int end) {
  double sum = 0.0;
  for (int y = 0; y < input.height; ++y) {
    const double* g = input.row(c, y) + offset;
    for (int x = first - kRadius; x < end + kRadius; ++x) sum += g[x];
  }
  return sum / (static_cast<double>(end - first + 2 * kRadius) * input.height);
}

}  // namespace

std::optional<double> structural_similarity(const Image& input, int offset, const Image& restored,
                                            int first, int end, int threads) {
  require_window(input, offset, restored, first, end);
  if (first < kRadius || end > restored.width - kRadius || restored.height < kTaps ||
      restored.channels < 1) {
    return std::nullopt;
  }
  const int columns = end - first;
  const int rows = restored.height - 2 * kRadius;
  const int tiles = (columns + kTileColumns - 1) / kTileColumns;
  const int blocks = (rows + kBlockRows - 1) / kBlockRows;
  Work work{input, offset, restored, first, end, rows, blocks, tiles, gaussian_half_weights(),
            {},    {}};
  for (int c = 0; c < restored.channels; ++c) {
    work.shifts.push_back(strip_mean(input, offset, c, first, end));
  }
  work.sums.resize(static_cast<std::size_t>(restored.channels) * rows * tiles);
  const int items = restored.channels * blocks * tiles;
  parallel_for(items, threads, [&work](int begin, int stop) {
    Scratch scratch;
    for (int item = begin; item < stop; ++item) run_item(work, item, scratch);
  });
  // Each channel's sum in the order of its rows and tiles, its mean, then the mean of the means.
  const double count = static_cast<double>(columns) * rows;
  double total = 0.0;
  for (int c = 0; c < restored.channels; ++c) {
    double sum = 0.0;
    const std::size_t size = static_cast<std::size_t>(rows) * tiles;
    for (std::size_t i = 0; i < size; ++i) sum += work.sums[c * size + i];
    total += sum / count;
  }
  return total / restored.channels;
}

}  // namespace fss

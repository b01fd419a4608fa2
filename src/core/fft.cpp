#include "core/fft.h"

#include <fftw3.h>

#include <map>
#include <memory>
#include <mutex>
#include <new>
#include <string>

#include "fss/core/error.h"

namespace fss {

namespace {
std::mutex& planner_mutex() {
  static std::mutex mutex;
  return mutex;
}

template <typename T>
T* fftw_alloc(std::size_t count) {
  void* p = fftw_malloc(sizeof(T) * (count == 0 ? 1 : count));
  if (!p) throw std::bad_alloc();
  return static_cast<T*>(p);
}
}  // namespace

RowFFT::Workspace::Workspace(int n)
    : n_(n), real_(fftw_alloc<double>(static_cast<std::size_t>(n))), spectrum_(nullptr) {
  try {
    spectrum_ = fftw_alloc<std::complex<double>>(static_cast<std::size_t>(n) / 2 + 1);
  } catch (...) {
    fftw_free(real_);
    throw;
  }
}

RowFFT::Workspace::~Workspace() {
  fftw_free(real_);
  fftw_free(spectrum_);
}

RowFFT::RowFFT(int n) : n_(n) {
  if (n < 1) throw_usage_error("FFT length must be at least 1, got " + std::to_string(n));
}

namespace {
// A plan of length n in one direction, on arrays of the alignment of
// fftw_malloc (the workspaces'); throws when FFTW cannot plan it.
void* make_plan(int n, bool forward) {
  RowFFT::Workspace workspace(n);
  auto* real = workspace.real().data();
  auto* spectrum = reinterpret_cast<fftw_complex*>(workspace.spectrum().data());
  std::lock_guard<std::mutex> lock(planner_mutex());
  fftw_plan plan = forward ? fftw_plan_dft_r2c_1d(n, real, spectrum, FFTW_ESTIMATE)
                           : fftw_plan_dft_c2r_1d(n, spectrum, real, FFTW_ESTIMATE);
  if (!plan) throw_runtime_error("FFTW could not plan a transform of length " + std::to_string(n));
  return plan;
}
}  // namespace

void RowFFT::prepare() const {
  forward_plan();
  inverse_plan();
}

void* RowFFT::forward_plan() const {
  std::call_once(forward_once_, [this] { forward_plan_ = make_plan(n_, true); });
  return forward_plan_;
}

void* RowFFT::inverse_plan() const {
  std::call_once(inverse_once_, [this] { inverse_plan_ = make_plan(n_, false); });
  return inverse_plan_;
}

const RowFFT& RowFFT::for_size(int n) {
  static std::mutex cache_mutex;
  // Never destroyed: destroying plans during static destruction could run
  // after the planner mutex is gone. The plans live until the process exits.
  static auto* cache = new std::map<int, std::unique_ptr<RowFFT>>();
  std::lock_guard<std::mutex> lock(cache_mutex);
  auto& entry = (*cache)[n];
  if (!entry) entry = std::make_unique<RowFFT>(n);
  return *entry;
}

RowFFT::~RowFFT() {
  std::lock_guard<std::mutex> lock(planner_mutex());
  if (forward_plan_ != nullptr) fftw_destroy_plan(static_cast<fftw_plan>(forward_plan_));
  if (inverse_plan_ != nullptr) fftw_destroy_plan(static_cast<fftw_plan>(inverse_plan_));
}

void RowFFT::forward(Workspace& workspace) const {
  fftw_execute_dft_r2c(static_cast<fftw_plan>(forward_plan()), workspace.real_,
                       reinterpret_cast<fftw_complex*>(workspace.spectrum_));
}

void RowFFT::inverse(Workspace& workspace) const {
  fftw_execute_dft_c2r(static_cast<fftw_plan>(inverse_plan()),
                       reinterpret_cast<fftw_complex*>(workspace.spectrum_), workspace.real_);
}

void RowFFT::inverse_filtered(Workspace& workspace,
                              std::span<const std::complex<double>> filter) const {
  multiply_half_spectrum(workspace.spectrum(), filter, n_);
  inverse(workspace);
  const double inverse_n = 1.0 / n_;
  for (double& value : workspace.real()) value *= inverse_n;
}

void multiply_half_spectrum(std::span<std::complex<double>> spectrum,
                            std::span<const std::complex<double>> filter, int n) {
  const std::size_t bins = static_cast<std::size_t>(n) / 2 + 1;
  const bool has_nyquist = n % 2 == 0;
  const std::size_t full = has_nyquist ? bins - 1 : bins;
  // Plain (a + ib)(c + id): std::complex's operator* adds NaN/inf recovery
  // branches that cost as much as the FFT; the values here are finite.
  for (std::size_t i = 0; i < full; ++i) {
    const double a = spectrum[i].real(), b = spectrum[i].imag();
    const double c = filter[i].real(), d = filter[i].imag();
    spectrum[i] = std::complex<double>(a * c - b * d, a * d + b * c);
  }
  if (has_nyquist) {
    // X[n/2] of a real row is real: keep Re(X H) = X Re(H).
    spectrum[bins - 1] = std::complex<double>(spectrum[bins - 1].real() * filter[bins - 1].real());
  }
}

}  // namespace fss

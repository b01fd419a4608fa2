#include "fss/core/fft.h"

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

RowFFT::RowFFT(int n) : n_(n), forward_plan_(nullptr), inverse_plan_(nullptr) {
  if (n < 1) throw_usage_error("FFT length must be at least 1, got " + std::to_string(n));
  Workspace workspace(n);
  auto* spectrum = reinterpret_cast<fftw_complex*>(workspace.spectrum_);
  std::lock_guard<std::mutex> lock(planner_mutex());
  forward_plan_ = fftw_plan_dft_r2c_1d(n, workspace.real_, spectrum, FFTW_ESTIMATE);
  inverse_plan_ = fftw_plan_dft_c2r_1d(n, spectrum, workspace.real_, FFTW_ESTIMATE);
  if (!forward_plan_ || !inverse_plan_) {
    if (forward_plan_) fftw_destroy_plan(static_cast<fftw_plan>(forward_plan_));
    if (inverse_plan_) fftw_destroy_plan(static_cast<fftw_plan>(inverse_plan_));
    throw_runtime_error("FFTW could not plan a transform of length " + std::to_string(n));
  }
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
  fftw_destroy_plan(static_cast<fftw_plan>(forward_plan_));
  fftw_destroy_plan(static_cast<fftw_plan>(inverse_plan_));
}

void RowFFT::forward(Workspace& workspace) const {
  fftw_execute_dft_r2c(static_cast<fftw_plan>(forward_plan_), workspace.real_,
                       reinterpret_cast<fftw_complex*>(workspace.spectrum_));
}

void RowFFT::inverse(Workspace& workspace) const {
  fftw_execute_dft_c2r(static_cast<fftw_plan>(inverse_plan_),
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

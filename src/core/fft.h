// Row-wise real FFTs (FFTW3, double precision).
//
// FFTW discipline: one RowFFT holds the r2c and c2r plans for one row length
// N, created once per process (RowFFT::for_size caches them; FFTW_ESTIMATE,
// under a process-wide lock because the FFTW planner is not thread-safe; each
// direction is planned on its first use, since planning costs about a
// millisecond and some lengths are only ever transformed one way) and
// executed many times on per-thread workspaces with FFTW's new-array
// interface, which is thread-safe. Plans are FFTW_ESTIMATE: FFTW_MEASURE's
// planning costs more than a single run's transforms save (CONTRIBUTING.md,
// "Hand-written fast paths").
//
// Scaling: forward is the unnormalized DFT X[i] = sum_x u[x] exp(-2 pi i i x / N);
// inverse is unnormalized too, so inverse(forward(u)) = N u.
// Layout: the half spectrum holds bins 0 .. N/2 (N/2 + 1 values); see
// transfer.h for the frequency of each bin.
#pragma once

#include <complex>
#include <mutex>
#include <span>

namespace fss {

class RowFFT {
 public:
  // Buffers of one worker, allocated with fftw_malloc so they have the
  // alignment the plans were made for.
  class Workspace {
   public:
    explicit Workspace(int n);
    ~Workspace();
    Workspace(const Workspace&) = delete;
    Workspace& operator=(const Workspace&) = delete;
    std::span<double> real() { return {real_, static_cast<std::size_t>(n_)}; }
    std::span<std::complex<double>> spectrum() {
      return {spectrum_, static_cast<std::size_t>(n_ / 2 + 1)};
    }

   private:
    friend class RowFFT;
    int n_;
    double* real_;
    std::complex<double>* spectrum_;
  };

  // The process-wide plans for length n, made on first use; thread-safe.
  static const RowFFT& for_size(int n);

  explicit RowFFT(int n);
  ~RowFFT();
  RowFFT(const RowFFT&) = delete;
  RowFFT& operator=(const RowFFT&) = delete;

  int size() const { return n_; }
  // Makes both plans now (they are otherwise made on first use): for a
  // caller that prepares the transforms of a run ahead of it.
  void prepare() const;
  int spectrum_size() const { return n_ / 2 + 1; }

  // workspace.real() -> workspace.spectrum().
  void forward(Workspace& workspace) const;
  // workspace.spectrum() -> workspace.real(); the spectrum is overwritten.
  void inverse(Workspace& workspace) const;

  // workspace.real() = IDFT(workspace.spectrum() * filter), normalized (the
  // 1/N included): the row filtered by `filter` (half spectrum, see
  // multiply_half_spectrum). The spectrum is overwritten.
  void inverse_filtered(Workspace& workspace, std::span<const std::complex<double>> filter) const;

 private:
  // The plan of one direction, made on first use (thread-safe).
  void* forward_plan() const;
  void* inverse_plan() const;

  int n_;
  mutable std::once_flag forward_once_;
  mutable std::once_flag inverse_once_;
  mutable void* forward_plan_ = nullptr;
  mutable void* inverse_plan_ = nullptr;
};

// spectrum[i] *= filter[i] for the half spectrum of a real row of length n.
// The Nyquist bin (even n) of a real row is real and so must its product be
// for the row to stay real: it is multiplied by Re(filter), which is what the
// real part of a full complex inverse DFT gives.
void multiply_half_spectrum(std::span<std::complex<double>> spectrum,
                            std::span<const std::complex<double>> filter, int n);

}  // namespace fss

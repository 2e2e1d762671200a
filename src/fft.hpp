// Batched 1-D real FFTs along contiguous lines, in place, in FFTW's
// halfcomplex order (r0, r1, ..., r_{n/2}, i_{(n+1)/2-1}, ..., i1): the data
// stays real and keeps its size, and entries m and n - m share one wavenumber,
// so a diagonal operator in Fourier space is a multiplication per entry.
// Unnormalised: backward(forward(f)) = n f.
//
// The interface is backend-neutral; fft_fftw.cpp implements it on the host.
// A cuFFT implementation (r2c plus a repacking kernel) plugs in behind it.
#pragma once
#include <memory>

#include "types.hpp"

namespace softflow {

class LineFft {
 public:
  LineFft(int n, long howmany, Array1 data);
  ~LineFft();
  LineFft(const LineFft&) = delete;
  LineFft& operator=(const LineFft&) = delete;
  void forward();
  void backward();

  // the wavenumber index of halfcomplex entry m of a length-n transform
  KOKKOS_INLINE_FUNCTION static int wavenumber(int m, int n) { return m <= n / 2 ? m : n - m; }

 private:
  struct Plans;
  std::unique_ptr<Plans> plans_;
};

}  // namespace softflow

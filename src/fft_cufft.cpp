// LineFft on cuFFT (device memory), for the Kokkos CUDA backend.
//
// cuFFT has no halfcomplex (r2r) transform, so each direction is a batched
// real<->complex transform through a complex work array allocated once here,
// plus a repacking kernel:
//   forward:  data --D2Z--> work --pack--> data (halfcomplex order)
//   backward: data --unpack--> work --Z2D--> data
// Line l of the caller's array is data[l n .. l n + n), line l of the work
// array work[l nc .. l nc + nc) with nc = n/2 + 1 (the non-negative
// wavenumbers). Halfcomplex entry m holds Re c_m for m <= n/2 and Im c_{n-m}
// for m > n/2, as FFTW's R2HC/HC2R; both directions are unnormalised, and the
// sign convention (forward exp(-2 pi i j k / n)) is FFTW's.
//
// Everything runs on the default Kokkos::Cuda instance's stream, in order with
// the kernels before and after, so no fence is needed here. cuFFT plans are
// deterministic for a given GPU and plan, so restarts reproduce bit for bit on
// the same machine.
#include <cufft.h>

#include <stdexcept>
#include <string>
#include <type_traits>

#include "fft.hpp"

#ifndef KOKKOS_ENABLE_CUDA
#error "fft_cufft.cpp needs Kokkos' CUDA backend; build fft_fftw.cpp otherwise"
#endif
static_assert(std::is_same_v<softflow::ExecSpace, Kokkos::Cuda>,
              "fft_cufft.cpp runs its transforms on Kokkos::Cuda, the default execution space");

namespace softflow {

namespace {

using Complex = Kokkos::complex<double>;
using ComplexArray = Kokkos::View<Complex*, MemSpace>;
static_assert(sizeof(Complex) == sizeof(cufftDoubleComplex), "Kokkos::complex<double> must match cuFFT's");

void check(cufftResult r, const char* what) {
  if (r != CUFFT_SUCCESS)
    throw std::runtime_error(std::string("cuFFT: ") + what + " failed (cufftResult " +
                             std::to_string(int(r)) + ")");
}

// work (n/2 + 1 complex per line) -> data (n real per line, halfcomplex order)
void pack(int n, long howmany, const ComplexArray& work, const Array1& data) {
  const long nc = n / 2 + 1;
  Kokkos::parallel_for(
      "fft_pack_halfcomplex", Kokkos::RangePolicy<ExecSpace>(0, howmany * n), KOKKOS_LAMBDA(long t) {
        const long l = t / n;
        const int m = int(t - l * n);
        data(t) = m <= n / 2 ? work(l * nc + m).real() : work(l * nc + (n - m)).imag();
      });
}

// data (halfcomplex order) -> work; Im c_0 (and Im c_{n/2} for even n) are 0
void unpack(int n, long howmany, const Array1& data, const ComplexArray& work) {
  const long nc = n / 2 + 1;
  Kokkos::parallel_for(
      "fft_unpack_halfcomplex", Kokkos::RangePolicy<ExecSpace>(0, howmany * nc), KOKKOS_LAMBDA(long t) {
        const long l = t / nc;
        const int k = int(t - l * nc);
        const Real re = data(l * n + k);
        const Real im = (k == 0 || 2 * k == n) ? Real(0) : data(l * n + (n - k));
        work(t) = Complex(re, im);
      });
}

}  // namespace

struct LineFft::Plans {
  int n = 0;
  long howmany = 0;
  Array1 data;
  ComplexArray work;
  cufftHandle fwd = 0, bwd = 0;
  bool has_fwd = false, has_bwd = false;
  Plans() = default;
  Plans(const Plans&) = delete;
  Plans& operator=(const Plans&) = delete;
  // here rather than in ~LineFft, so that a constructor that throws half-way
  // still releases the plans it made; no throwing from a destructor
  ~Plans() {
    if (has_fwd) cufftDestroy(fwd);
    if (has_bwd) cufftDestroy(bwd);
  }
};

LineFft::LineFft(int n, long howmany, Array1 data) : plans_(new Plans) {
  Plans& p = *plans_;
  p.n = n;
  p.howmany = howmany;
  p.data = data;
  if (howmany <= 0) return;
  if (long(data.extent(0)) < howmany * n)
    throw std::logic_error("LineFft: the array is shorter than howmany lines of length n");
  const long long nc = n / 2 + 1;
  p.work = ComplexArray(Kokkos::view_alloc(Kokkos::WithoutInitializing, "fft_work"), howmany * nc);

  // contiguous lines: real distance n, complex distance n/2 + 1
  long long len = n, inembed = n, onembed = nc;
  size_t ws = 0;
  cudaStream_t stream = Kokkos::Cuda().cuda_stream();
  check(cufftCreate(&p.fwd), "cufftCreate");
  p.has_fwd = true;
  check(cufftMakePlanMany64(p.fwd, 1, &len, &inembed, 1, n, &onembed, 1, nc, CUFFT_D2Z, howmany, &ws),
        "planning the D2Z transform");
  check(cufftSetStream(p.fwd, stream), "cufftSetStream");
  check(cufftCreate(&p.bwd), "cufftCreate");
  p.has_bwd = true;
  check(cufftMakePlanMany64(p.bwd, 1, &len, &onembed, 1, nc, &inembed, 1, n, CUFFT_Z2D, howmany, &ws),
        "planning the Z2D transform");
  check(cufftSetStream(p.bwd, stream), "cufftSetStream");
}

LineFft::~LineFft() = default;

void LineFft::forward() {
  const Plans& p = *plans_;
  if (!p.has_fwd) return;
  check(cufftExecD2Z(p.fwd, reinterpret_cast<cufftDoubleReal*>(p.data.data()),
                     reinterpret_cast<cufftDoubleComplex*>(p.work.data())),
        "executing the D2Z transform");
  pack(p.n, p.howmany, p.work, p.data);
}

void LineFft::backward() {
  const Plans& p = *plans_;
  if (!p.has_bwd) return;
  unpack(p.n, p.howmany, p.data, p.work);
  // out of place, so cuFFT may overwrite work (C2R does), never data's input
  check(cufftExecZ2D(p.bwd, reinterpret_cast<cufftDoubleComplex*>(p.work.data()),
                     reinterpret_cast<cufftDoubleReal*>(p.data.data())),
        "executing the Z2D transform");
}

}  // namespace softflow

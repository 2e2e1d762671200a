// One launch over many small boxes: the colours' per-particle passes.
//
// Why: each colour field lives in a few boxes about its own particle
// (src/colour_boxes.hpp), a 4-ppr sphere's box ~12^3 cells. One kernel per
// colour and box made ~2800 launches in a dense step of 67 colours, each
// costing ~3 us on two OpenMP threads against ~1 us of work
// (perf/results/solid_cost/, round 29). A batch puts every colour's boxes of
// one pass into one launch: a team per box, its cells spread over the team.
// On a host backend a team is one thread, so the parallelism is the number of
// boxes (dynamic schedule): fine for the dense scenes these passes serve, and
// the single-field path (one phi) does not use it.
//
// A box's fields travel as raw pointers into Field3 storage (one shape for all
// fields of a grid, checked by `add`), because a kernel cannot index a
// std::vector of Views on a device. Each task also carries one scalar (a
// colour's redistribution coefficient, say) and a tag (the colour).
#pragma once
#include <stdexcept>

#include <utility>

#include "grid.hpp"
#include "types.hpp"

namespace softflow {

struct BoxTask {
  Range3 r;                                  // the box, storage indices
  int tag = 0;                               // the caller's index (the colour)
  Real s = 0;                                // the caller's scalar for this box
  Real* f[3] = {nullptr, nullptr, nullptr};  // the caller's fields, Field3 storage
};

// Offset of cell (i, j, k) in Field3 storage (LayoutLeft, unpadded: `add`
// checks the strides of every field it is given)
struct CellOffset {
  long sx = 0, sxy = 0;
  KOKKOS_INLINE_FUNCTION long operator()(int i, int j, int k) const { return i + sx * j + sxy * k; }
};

// The tasks of one pass, staged on the host and copied to the device once;
// storage allocated once (capacity: tasks per pass)
class BoxBatch {
 public:
  using Tasks = Kokkos::View<BoxTask*, MemSpace>;
  BoxBatch() = default;
  BoxBatch(const Grid& g, int capacity)
      : at_{g.sx(), long(g.sx()) * g.sy()},
        dev_("box_batch_tasks", capacity),
        host_(Kokkos::create_mirror_view(dev_)),
        sums_("box_batch_sums", capacity),
        sums_host_(Kokkos::create_mirror_view(sums_)) {}

  void clear() { n_ = 0; }
  // a task over r (skipped if empty) on up to three fields
  void add(const Range3& r, int tag, Real s = 0, const Field3& a = {}, const Field3& b = {},
           const Field3& c = {}) {
    if (r.empty()) return;
    if (n_ >= int(dev_.extent(0))) throw std::logic_error("BoxBatch: more tasks than its capacity");
    BoxTask t{r, tag, s, {pointer(a), pointer(b), pointer(c)}};
    host_(n_++) = t;
  }
  int size() const { return n_; }
  int tag(int b) const { return host_(b).tag; }
  void set_scalar(int b, Real s) { host_(b).s = s; }
  CellOffset offset() const { return at_; }
  // the staged tasks on the device (a copy only where host and device differ)
  Tasks upload() const {
    if (n_ > 0)
      Kokkos::deep_copy(Kokkos::subview(dev_, std::make_pair(0, n_)),
                        Kokkos::subview(host_, std::make_pair(0, n_)));
    return dev_;
  }
  // one pair of sums per task (par_reduce2_boxes), read back on the host
  Kokkos::View<Real* [2], MemSpace> sums() const {
    return sums_;
  } const Kokkos::View<Real* [2], MemSpace>::host_mirror_type& sums_on_host() const {
    Kokkos::deep_copy(sums_host_, sums_);
    return sums_host_;
  }

  private : Real* pointer(const Field3& f) const {
    if (f.data() == nullptr) return nullptr;
    if (long(f.stride(1)) != at_.sx || long(f.stride(2)) != at_.sxy || f.stride(0) != 1)
      throw std::logic_error("BoxBatch: a field not of the grid's storage shape");
    return f.data();
  }
  CellOffset at_;
  int n_ = 0;
  Tasks dev_;
  Tasks::host_mirror_type host_;
  Kokkos::View<Real* [2], MemSpace> sums_;
  Kokkos::View<Real* [2], MemSpace>::host_mirror_type sums_host_;
};

using BoxTeamPolicy = Kokkos::TeamPolicy<ExecSpace, Kokkos::Schedule<Kokkos::Dynamic>>;

// A team per task: on a host backend a team of one thread, which walks its
// box's x lines as plain loops (vectorised as par_for's); elsewhere the
// backend's team, its threads over the lines and the vector lanes along x.
inline BoxTeamPolicy box_policy(int n) {
  if constexpr (host_lines)
    return BoxTeamPolicy(n, 1);
  else
    return BoxTeamPolicy(n, Kokkos::AUTO);
}

// f(task, i, j, k) on every cell of every staged task: one launch. (The two
// paths are two lambdas: nvcc rejects an extended lambda that first
// captures a variable inside an if constexpr.)
template <class F>
inline void par_for_boxes(const char* label, const BoxBatch& batch, const F& f) {
  const int n = batch.size();
  if (n == 0) return;
  const BoxBatch::Tasks tasks = batch.upload();
  if constexpr (host_lines) {
    Kokkos::parallel_for(
        label, box_policy(n), KOKKOS_LAMBDA(const BoxTeamPolicy::member_type& m) {
          const BoxTask t = tasks(m.league_rank());
          for (int k = t.r.kb; k < t.r.ke; ++k)
            for (int j = t.r.jb; j < t.r.je; ++j) {
              SOFTFLOW_SIMD
              for (int i = t.r.ib; i < t.r.ie; ++i) f(t, i, j, k);
            }
        });
  } else {
    Kokkos::parallel_for(
        label, box_policy(n), KOKKOS_LAMBDA(const BoxTeamPolicy::member_type& m) {
          const BoxTask t = tasks(m.league_rank());
          const int nj = t.r.je - t.r.jb;
          Kokkos::parallel_for(Kokkos::TeamThreadRange(m, nj * (t.r.ke - t.r.kb)), [&](int line) {
            const int j = t.r.jb + line % nj, k = t.r.kb + line / nj;
            Kokkos::parallel_for(Kokkos::ThreadVectorRange(m, t.r.ib, t.r.ie), [&](int i) { f(t, i, j, k); });
          });
        });
  }
}

// Two sums per task, f(task, i, j, k, a, b) adding to a and b, into the
// batch's sums(task, 0..1); each task's cells summed in one order (the
// sums are a function of the fields alone). One launch.
template <class F>
inline void par_reduce2_boxes(const char* label, const BoxBatch& batch, const F& f) {
  const int n = batch.size();
  if (n == 0) return;
  const BoxBatch::Tasks tasks = batch.upload();
  const auto out = batch.sums();
  if constexpr (host_lines) {  // a team of one thread: both sums in one pass
    Kokkos::parallel_for(
        label, box_policy(n), KOKKOS_LAMBDA(const BoxTeamPolicy::member_type& m) {
          const BoxTask t = tasks(m.league_rank());
          Real a = 0, b = 0;
          for (int k = t.r.kb; k < t.r.ke; ++k)
            for (int j = t.r.jb; j < t.r.je; ++j)
              for (int i = t.r.ib; i < t.r.ie; ++i) f(t, i, j, k, a, b);
          out(m.league_rank(), 0) = a;
          out(m.league_rank(), 1) = b;
        });
  } else {
    Kokkos::parallel_for(
        label, box_policy(n), KOKKOS_LAMBDA(const BoxTeamPolicy::member_type& m) {
          const BoxTask t = tasks(m.league_rank());
          const int nj = t.r.je - t.r.jb, lines = nj * (t.r.ke - t.r.kb);
          Real sum[2] = {0, 0};
          // one team reduction per sum (a nested reduction takes one value)
          for (int w = 0; w < 2; ++w)
            Kokkos::parallel_reduce(
                Kokkos::TeamThreadRange(m, lines),
                [&](int line, Real& acc) {
                  const int j = t.r.jb + line % nj, k = t.r.kb + line / nj;
                  for (int i = t.r.ib; i < t.r.ie; ++i) {
                    Real ab[2] = {0, 0};
                    f(t, i, j, k, ab[0], ab[1]);
                    acc += ab[w];
                  }
                },
                sum[w]);
          Kokkos::single(Kokkos::PerTeam(m), [&]() {
            out(m.league_rank(), 0) = sum[0];
            out(m.league_rank(), 1) = sum[1];
          });
        });
  }
}

}  // namespace softflow

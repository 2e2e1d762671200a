// A manufactured solution of the forced Navier-Stokes equations between the
// moving walls, three-dimensional and divergence-free, used to verify the
// solver's order in space and time:
//   v = A(t) f(y) cos(a x) cos(c z)
//   u = V_w y/h - A(t) f'(y) sin(a x) cos(c z) / (2a)
//   w =         - A(t) f'(y) cos(a x) sin(c z) / (2c)
//   p = A(t) g(y) cos(a x) sin(c z)            (kinematic, p/rho)
// with f = (1 - eta^2)^2, g = eta - eta^3/3, eta = y/h, A = A0 cos(omega t),
// a = 2 pi / lx, c = 2 pi / lz. f and f' vanish at the walls, so the no-slip
// conditions hold exactly, and dg/dy = 0 there. The forcing is
//   F = du/dt + (u . grad) u - nu lap u + grad p.
#pragma once
#include <cmath>

#include "../src/types.hpp"

namespace softflow {

struct Manufactured {
  bool enabled = false;
  Real amp = 0, omega = 1, a = 1, c = 1, h = 1, vw = 0, nu = 1;

  struct Point {
    Real u, v, w;                             // velocity
    Real ut, vt, wt;                          // time derivatives
    Real ux, uy, uz, vx, vy, vz, wx, wy, wz;  // gradient
    Real lu, lv, lw;                          // Laplacians
    Real p;                                   // pressure
    Real px, py, pz;                          // pressure gradient
  };

  KOKKOS_INLINE_FUNCTION Point eval(Real x, Real y, Real z, Real t) const {
    const Real e = y / h;
    const Real f = (1 - e * e) * (1 - e * e);
    const Real f1 = -4 * e * (1 - e * e) / h;
    const Real f2 = -4 * (1 - 3 * e * e) / (h * h);
    const Real f3 = 24 * e / (h * h * h);
    const Real g = e - e * e * e / 3;
    const Real g1 = (1 - e * e) / h;
    const Real A = amp * Kokkos::cos(omega * t), At = -amp * omega * Kokkos::sin(omega * t);
    const Real sx = Kokkos::sin(a * x), cx = Kokkos::cos(a * x);
    const Real sz = Kokkos::sin(c * z), cz = Kokkos::cos(c * z);
    const Real k2 = a * a + c * c;
    Point q;
    q.u = vw * e - A * f1 * sx * cz / (2 * a);
    q.v = A * f * cx * cz;
    q.w = -A * f1 * cx * sz / (2 * c);
    q.ut = -At * f1 * sx * cz / (2 * a);
    q.vt = At * f * cx * cz;
    q.wt = -At * f1 * cx * sz / (2 * c);
    q.ux = -A * f1 * cx * cz / 2;
    q.uy = vw / h - A * f2 * sx * cz / (2 * a);
    q.uz = A * f1 * sx * sz * c / (2 * a);
    q.vx = -a * A * f * sx * cz;
    q.vy = A * f1 * cx * cz;
    q.vz = -c * A * f * cx * sz;
    q.wx = A * f1 * a * sx * sz / (2 * c);
    q.wy = -A * f2 * cx * sz / (2 * c);
    q.wz = -A * f1 * cx * cz / 2;
    const Real u1 = q.u - vw * e;  // the periodic part of u
    q.lu = -k2 * u1 - A * f3 * sx * cz / (2 * a);
    q.lv = -k2 * q.v + A * f2 * cx * cz;
    q.lw = -k2 * q.w - A * f3 * cx * sz / (2 * c);
    q.p = A * g * cx * sz;
    q.px = -a * A * g * sx * sz;
    q.py = A * g1 * cx * sz;
    q.pz = c * A * g * cx * cz;
    return q;
  }

  // forcing component d (0: x, 1: y, 2: z) at a point
  KOKKOS_INLINE_FUNCTION Real force(int d, Real x, Real y, Real z, Real t) const {
    const Point q = eval(x, y, z, t);
    if (d == 0) return q.ut + q.u * q.ux + q.v * q.uy + q.w * q.uz - nu * q.lu + q.px;
    if (d == 1) return q.vt + q.u * q.vx + q.v * q.vy + q.w * q.vz - nu * q.lv + q.py;
    return q.wt + q.u * q.wx + q.v * q.wy + q.w * q.wz - nu * q.lw + q.pz;
  }
};

}  // namespace softflow

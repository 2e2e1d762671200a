#!/usr/bin/env python3
"""The dilute report's order fit and Richardson extrapolation
(perf/dilute_convergence.py), on synthetic series f = f0 + C h^p whose order
and limit are known. Exits non-zero if any check failed."""
import math
import os
import sys

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
sys.path.insert(0, os.path.join(ROOT, "perf"))
import dilute_convergence as dc  # noqa: E402

PPR = (4, 5, 6, 7, 8, 12)
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from py_checks import check, finish  # noqa: E402


def series(f0, c, p, ppr=PPR):
    h = [1 / q for q in ppr]
    return h, [f0 + c * hh ** p for hh in h]


# 1. Exact data of orders 1, 0.6 and 2, from either side: the fit returns the
#    order to the golden-section search's precision (1e-6 is far inside the
#    grid step of 0.005 it refines) and the limit to round-off times C.
for f0, c, p in ((2.0675, 2.3, 1.0), (-1.5776, -1.4, 0.6), (0.4899, 5.0, 2.0)):
    h, f = series(f0, c, p)
    fit = dc.order_fit(h, f, [1e-3] * len(h))
    check(f"order {p} from {'above' if c > 0 else 'below'}",
          fit is not None and abs(fit[0] - p) < 1e-4 and abs(fit[1] - f0) < 1e-6 * abs(c)
          and fit[2][0] <= p <= fit[2][1],
          f"p = {fit and fit[0]:.6f}, f0 = {fit and fit[1]:.8f} (want {p}, {f0})")

# 2. With three resolutions the fit is the exact three-point solution.
h, f = series(1.0, 0.7, 1.3, (4, 6, 8))
fit = dc.order_fit(h, f, [1e-3] * 3)
p3 = dc.observed_order(h, f)
check("three points: fit = three-point order", fit is not None and abs(fit[0] - p3) < 1e-9
      and abs(p3 - 1.3) < 1e-6, f"fit {fit and fit[0]:.9f}, three-point {p3:.9f}")

# 3. Values that are not monotone in h have no order: None, and extrapolate
#    falls back on the two finest at order 2.
h = [1 / q for q in PPR]
f = [1.00, 0.97, 0.98, 0.95, 0.96, 0.94]
check("not monotone: no order", dc.order_fit(h, f, [1e-3] * len(h)) is None, "order_fit -> None")
recs = {q: {"q": {"x": (v, 1e-3)}} for q, v in zip(PPR, f)}
use, vals, fit, fin, err = dc.extrapolate(recs, "x")
want = 0.94 + (0.94 - 0.96) / ((12 / 8) ** 2 - 1)
check("not monotone: two finest at order 2", fit is None and abs(fin - want) < 1e-12,
      f"{fin:.6f} (want {want:.6f})")

# 4. At a given order the weighted fit is exact for data of that order
#    (the narrow-box estimate (a) rests on it); chi^2 is then zero.
h, f = series(2.5, 1.9, 0.8, (4, 5, 6, 7, 8))
chi, f0 = dc.power_fit(h, f, [2e-3, 1e-3, 3e-3, 1e-3, 2e-3], 0.8)
check("power fit at the data's order", abs(f0 - 2.5) < 1e-10 and chi < 1e-16, f"f0 = {f0:.12f}, chi2 = {chi:.1e}")

# 5. Scatter: a fixed, alternating perturbation of 3 standard errors
#    (chi^2 per degree of freedom about 9) must widen the order's range (the
#    misfit scales it) and the range must still hold the true order; at
#    half a standard error the range is the clean one's.
h, f = series(2.0, 2.3, 1.0)
se = [4e-3] * len(h)


def scattered(a):
    return dc.order_fit(h, [v + a * s * (-1) ** i for i, (v, s) in enumerate(zip(f, se))], se)


clean, small, large = dc.order_fit(h, f, se), scattered(0.5), scattered(3.0)
width = [x[2][1] - x[2][0] for x in (clean, small, large)]
check("scatter widens the order's range, which still holds p",
      large[2][0] <= 1.0 <= large[2][1] and width[2] > 2 * width[0] and abs(width[1] - width[0]) < 0.011,
      f"ranges {clean[2]}, {small[2]}, {large[2]}")

# 4. verify's pieces: every run's name parses back to the run (so any
#    committed record can be re-run by name), other names do not; and a
#    re-run that differs from its record by more than --rel in one quantity
#    is caught, one equal to it to round-off is not.
named = [(0.2, 1.0, "mthinc09", 4, 8), (0.2, 10.0, "thinc", 12, 8), (0.1, 1.0, "mthinc", 6),
         (0.2, 10.0, "thinc", 5, 16, 32), (0.4, 1.0, "weno5", 3)]
check("run names parse back to their runs",
      all(dc.run_of(dc.name_of(*r)) == r for r in named) and dc.run_of("ca0.2_k1_spline_r4") is None
      and dc.run_of("notes") is None, str([dc.run_of(dc.name_of(*r)) for r in named]))
kept = {"q": {"T": [0.2283552206, 1e-3], "intrinsic": [2.443218148, 3e-3]}}
same = {"q": {"T": [0.2283552206 * (1 + 1e-15), 1e-3], "intrinsic": [2.443218148, 3e-3]}}
moved = {"q": {"T": [0.2283552206, 1e-3], "intrinsic": [2.443218148 * (1 + 2e-9), 3e-3]}}
check("verify passes round-off and catches a 2e-9 change",
      all(r[4] for r in dc.compare_records(kept, same, 1e-9))
      and [r[4] for r in dc.compare_records(kept, moved, 1e-9)] == [True, False],
      str(dc.compare_records(kept, moved, 1e-9)))

finish()

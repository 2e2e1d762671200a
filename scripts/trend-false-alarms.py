#!/usr/bin/env python3
"""How often summary.json's trend (src/averaging.cpp fit_trend: a line
through 10 batch means, the slope's error from their scatter about it) calls
a stationary series drifting, against the correlation time. Also the
alternative it was chosen over: one line through every sample, its error
sqrt(var(residual) tau / Sxx) with tau the residuals' integrated
autocorrelation time (Sokal's window, c = 5). AR(1) series of 4000 samples
over 100 strain units, flagged where |slope| > 2 standard errors (the 1%
floor left out). Usage: scripts/trend-false-alarms.py [SERIES] (numpy;
inside the toolchain root: scripts/toolchain.sh run python3 ...)."""
import sys

import numpy as np


def ar1(rng, n, rho):
    e = rng.normal(0, 1, n)
    x = np.empty(n)
    v = 0.0
    for i in range(n):
        v = rho * v + e[i]
        x[i] = v
    return x


def integrated_time(x):
    x = x - x.mean()
    n = len(x)
    f = np.fft.rfft(x, 2 * n)
    rho = np.fft.irfft(f * np.conj(f))[:n] / n / (x * x).mean()
    tau = 1.0
    for k in range(1, n):
        tau += 2 * rho[k]
        if k >= 5 * tau:
            break
    return max(tau, 1.0)


def line(x, y):
    mx, my = x.mean(), y.mean()
    sxx = ((x - mx) ** 2).sum()
    b = ((x - mx) * (y - my)).sum() / sxx
    return b, y - my - b * (x - mx), sxx


def batch_trend(t, x, batches=10):
    n = len(x) // batches
    skip = len(x) - n * batches
    b, r, sxx = line(t[skip:].reshape(batches, n).mean(1), x[skip:].reshape(batches, n).mean(1))
    return b, np.sqrt((r ** 2).sum() / (batches - 2) / sxx)


def tau_trend(t, x):
    b, r, sxx = line(t, x)
    return b, np.sqrt(r.var(ddof=2) * integrated_time(r) / sxx)


def main():
    series = int(sys.argv[1]) if len(sys.argv) > 1 else 1000
    rng = np.random.default_rng(1)
    n = 4000
    t = np.arange(1, n + 1) / n * 100
    print("| rho | correlation time (samples) | as a share of the span | flagged: 10 batch means | flagged: residuals' tau |")
    print("|---|---|---|---|---|")
    for rho in (0.0, 0.9, 0.98, 0.995):
        flags = [0, 0]
        for _ in range(series):
            x = ar1(rng, n, rho)
            for j, fit in enumerate((batch_trend, tau_trend)):
                b, se = fit(t, x)
                flags[j] += abs(b) > 2 * se
        tau = (1 + rho) / (1 - rho)
        print(f"| {rho} | {tau:.0f} | {100 * tau / n:.2g}% | {flags[0] / series:.3f} | {flags[1] / series:.3f} |")
    print(f"({series} series each; Student's t with 8 degrees of freedom is beyond 2 with probability 0.080)")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Speed of sglab.irradiance against the C++ float batch it calls, per element,
in one process on the same arrays: 10^6 float32 points (kappa log-uniform over
[1e-3, 1e4], cosine uniform over [-1, 1], fixed seed), best of 9 runs each.
The module's time includes its checks of every point and the output array;
the C++ time is the registry's batch32 alone on the same arrays
(sglab._sglab._batch32, which only allocates the output besides).
A wall-clock benchmark, not a test:
    PYTHONPATH=build/python /usr/bin/python3 bench/python_irradiance.py [METHOD ...]"""

import os
import sys
import time

import numpy as np

import sglab
from sglab import _sglab

N, REPEATS = 1_000_000, 9


def best_seconds(f):
    best = float("inf")
    for _ in range(REPEATS):
        t0 = time.perf_counter()
        f()
        best = min(best, time.perf_counter() - t0)
    return best


def main(methods):
    rng = np.random.default_rng(20261204)
    kappa = (10.0 ** rng.uniform(-3, 4, N)).astype(np.float32)
    cosine = rng.uniform(-1, 1, N).astype(np.float32)
    print(f"{N} float32 points, best of {REPEATS}; load average before: "
          f"{os.getloadavg()[0]:.2f} ({os.cpu_count()} CPUs)")
    kappa64, cosine64 = kappa.astype(np.float64), cosine.astype(np.float64)
    print("ns per element; 'float64 in': the same points as float64 arrays, which the module "
          "checks and rounds to float32 first")
    print(f"{'method':<16} {'C++ batch32':>12} {'sglab.irradiance':>17} {'ratio':>7} "
          f"{'float64 in':>11} {'ratio':>7}")
    for method in methods:
        cpp = best_seconds(lambda: _sglab._batch32(method, kappa, cosine))
        py = best_seconds(lambda: sglab.irradiance(method, kappa, cosine))
        py64 = best_seconds(lambda: sglab.irradiance(method, kappa64, cosine64))
        print(f"{method:<16} {cpp / N * 1e9:>12.2f} {py / N * 1e9:>17.2f} {py / cpp:>7.3f} "
              f"{py64 / N * 1e9:>11.2f} {py64 / cpp:>7.3f}")
    print(f"load average after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main(sys.argv[1:] or ["tokuyoshi2024", "sglab_acc4", "sglab_fast", "hill"])

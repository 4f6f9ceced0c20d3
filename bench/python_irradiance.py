#!/usr/bin/python3
"""Speed of sglab.irradiance against the C++ float batch it calls, per element,
in one process on the same arrays: 10^6 float32 points (kappa log-uniform over
[1e-3, 1e4], cosine uniform over [-1, 1], fixed seed), best of 9 runs each.
The module's time includes its checks of every point and the output array;
the C++ time is the registry's batch32 alone on the same arrays
(sglab._sglab._batch32, which only allocates the output besides).
A wall-clock benchmark, not a test:
    PYTHONPATH=build/python /usr/bin/python3 bench/python_irradiance.py [--out FILE.md] [METHOD ...]
With --out, the table is also written to FILE.md (scripts/results.sh writes
data/results/python_speed.md)."""

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


def main(methods, out=None):
    rng = np.random.default_rng(20261204)
    kappa = (10.0 ** rng.uniform(-3, 4, N)).astype(np.float32)
    cosine = rng.uniform(-1, 1, N).astype(np.float32)
    kappa64, cosine64 = kappa.astype(np.float64), cosine.astype(np.float64)
    load_before = os.getloadavg()[0]
    rows = []
    for method in methods:
        cpp = best_seconds(lambda: _sglab._batch32(method, kappa, cosine))
        py = best_seconds(lambda: sglab.irradiance(method, kappa, cosine))
        py64 = best_seconds(lambda: sglab.irradiance(method, kappa64, cosine64))
        rows.append((method, cpp / N * 1e9, py / N * 1e9, py / cpp, py64 / N * 1e9, py64 / cpp))
    load_after = os.getloadavg()[0]
    lines = [
        f"{N} float32 points (kappa log-uniform over [1e-3, 1e4], cosine uniform over [-1, 1]), "
        f"best of {REPEATS} runs each; load average {load_before:.2f} before, {load_after:.2f} "
        f"after ({os.cpu_count()} CPUs). ns per element; 'float64 in': the same points as "
        "float64 arrays, which the module checks and rounds to float32 first. Command: "
        "`PYTHONPATH=build/python /usr/bin/python3 bench/python_irradiance.py`.",
        "",
        "| method | C++ batch32 | sglab.irradiance | ratio | float64 in | ratio |",
        "|:---|---:|---:|---:|---:|---:|",
    ]
    lines += [f"| {m} | {c:.2f} | {p:.2f} | {r:.3f} | {p64:.2f} | {r64:.3f} |"
              for m, c, p, r, p64, r64 in rows]
    text = "\n".join(lines) + "\n"
    print(text, end="")
    if out:
        tmp = f"{out}.{os.getpid()}.tmp"
        with open(tmp, "w") as f:
            f.write("# Python: sglab.irradiance against the C++ float batch\n\n" + text)
        os.replace(tmp, out)


if __name__ == "__main__":
    args = sys.argv[1:]
    out = None
    if args[:1] == ["--out"]:
        if len(args) < 2 or not args[1]:
            print("python_irradiance.py: --out needs a file", file=sys.stderr)
            sys.exit(2)
        out, args = args[1], args[2:]
        if os.path.lexists(out) and not os.path.isfile(out) or os.path.islink(out):
            print(f"python_irradiance.py: --out {out}: not a regular file; refused", file=sys.stderr)
            sys.exit(2)
    main(args or ["tokuyoshi2024", "sglab_acc4", "sglab_fast", "hill"], out)

"""Shared helpers of the Python tests: the project root, the `sglab` command
of the same build (SGLAB_BINARY_DIR, set by ctest; build/ by default) to
compare with, and seeded random points."""

import os
import pathlib
import subprocess

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
BINARY_DIR = pathlib.Path(os.environ.get("SGLAB_BINARY_DIR", ROOT / "build"))
CLI = BINARY_DIR / "sglab"


def run_cli(*args, check=True):
    """`sglab ARGS...` (an argument vector, no shell); its CompletedProcess."""
    if not CLI.exists():
        pytest.fail(f"{CLI}: the sglab command of this build is missing (cmake --build)")
    return subprocess.run([str(CLI), *map(str, args)], capture_output=True, text=True,
                          check=check, cwd=ROOT)


def random_points(n, seed=20261204, kappa_lo=-3.0, kappa_hi=4.0):
    """n points (kappa log-uniform over [10^lo, 10^hi], cosine uniform over
    [-1, 1]) plus the cosines -1, 0, 1 at kappa 1e-3, 1, 1e4."""
    rng = np.random.default_rng(seed)
    kappa = 10.0 ** rng.uniform(kappa_lo, kappa_hi, n)
    cosine = rng.uniform(-1.0, 1.0, n)
    edge_k, edge_c = np.meshgrid([1e-3, 1.0, 1e4], [-1.0, 0.0, 1.0])
    return np.concatenate([kappa, edge_k.ravel()]), np.concatenate([cosine, edge_c.ravel()])


def write_points(path, kappa, cosine):
    """A `kappa,cosine` points file of the CLI (%.17g: the doubles exactly)."""
    with open(path, "w") as f:
        f.write("kappa,cosine\n")
        for k, c in zip(kappa, cosine):
            f.write(f"{k!r},{c!r}\n")


def read_csv_column(text, column):
    lines = text.strip().splitlines()
    index = lines[0].split(",").index(column)
    return np.array([float(line.split(",")[index]) for line in lines[1:]])

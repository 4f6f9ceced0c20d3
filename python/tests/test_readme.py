"""The Python example of README.md, run exactly as written (from the
checkout, as a user pastes it), so that it cannot fall behind the API."""

import os
import re
import subprocess
import sys

import pytest

from conftest import ROOT


def readme_example():
    text = (ROOT / "README.md").read_text()
    found = re.search(r"<!-- python-example:[^>]*-->\n```python\n(.*?)```", text, re.S)
    assert found, "README.md: the python-example block is missing"
    return found.group(1)


def test_readme_example_runs():
    code = readme_example()
    assert len(code.strip().splitlines()) == 10
    pytest.importorskip("torch", reason="the README example uses PyTorch (python3-torch), "
                                        "which is not installed")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT,
                         env=dict(os.environ))
    assert out.returncode == 0, out.stderr
    lines = out.stdout.strip().splitlines()
    # The first two prints: three values each, positive.
    for line in lines[:2]:
        values = [float(v) for v in line.strip("[] ").split()]
        assert len(values) == 3 and all(v > 0 for v in values), line

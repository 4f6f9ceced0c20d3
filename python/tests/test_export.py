"""sglab.export against `sglab export`: the same code; only the header
comment may differ (the CLI adds the GPU cost and Vulkan error it reads from
the checkout's result files)."""

import pytest

import sglab
from conftest import run_cli


def code_lines(source):
    return [line for line in source.splitlines() if not line.lstrip().startswith("//")]


@pytest.mark.parametrize("method,lang,precision,split", [
    ("sglab_acc4", "glsl", "float", False), ("tokuyoshi2024", "hlsl", "float", True),
    ("sglab_fast", "glsl", "half", False), ("meder2018", "cpp", "float", False)])
def test_export_equals_the_cli(method, lang, precision, split):
    args = ["export", "--lang", lang, "--method", method, "--precision", precision]
    cli = run_cli(*args, *(["--split"] if split else [])).stdout
    mine = sglab.export(method, lang, precision, split)
    assert code_lines(mine) == code_lines(cli)
    assert len(code_lines(mine)) > 10


def test_export_errors():
    with pytest.raises(sglab.InputError, match="lang: expected glsl, hlsl or cpp, got 'x'"):
        sglab.export("sglab_acc4", "x")
    with pytest.raises(sglab.InputError, match="unknown or non-exportable method 'nope'"):
        sglab.export("nope")
    with pytest.raises(sglab.InputError, match="per-light split export is float only"):
        sglab.export("sglab_acc4", "glsl", "half", True)
    with pytest.raises(sglab.InputError, match="has no per-light split"):
        sglab.export("meder2018", split=True)

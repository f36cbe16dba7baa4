"""The worked example, examples/python/quickstart.py, runs and fits."""

from __future__ import annotations

import importlib.util
import pathlib

import pytest

pytest.importorskip("matplotlib")


def test_quickstart_recovers_its_parameters_and_writes_the_png(root: pathlib.Path, tmp_path: pathlib.Path) -> None:
    spec = importlib.util.spec_from_file_location("quickstart", root / "examples" / "python" / "quickstart.py")
    assert spec is not None and spec.loader is not None
    quickstart = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(quickstart)
    png = tmp_path / "quickstart.png"
    truth, result = quickstart.main(["--output", str(png)])
    assert result.converged, result.message
    # 1 % noise on 8000 samples: every fitted value within 1 % of the truth.
    for name, value in result.values.items():
        want = truth.params[name]
        assert abs(value - want) <= 0.01 * abs(want), (name, value, want)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert png.stat().st_size > 10_000

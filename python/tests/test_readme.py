"""The README's Python tour runs as written."""

from __future__ import annotations

import pathlib


def test_readme_python_tour_runs(root: pathlib.Path) -> None:
    text = (root / "README.md").read_text(encoding="utf-8")
    section = text.split("\n## Python\n", 1)[1]
    block = section.split("```python\n", 1)[1].split("```", 1)[0]
    namespace: dict = {}
    exec(compile(block, "README.md (Python tour)", "exec"), namespace)
    model, result = namespace["model"], namespace["result"]
    assert result.converged, result.message
    # The fit starts from f_c = 1 and finds the model's own 2.0.
    assert abs(result.values["left.mms.f_c"] - 2.0) < 1e-6
    assert namespace["same"] == model and namespace["stiffer"].params["left.mms.f_c"] == 2.5

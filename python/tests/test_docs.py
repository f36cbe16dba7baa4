"""Every shell and Python block of README.md and of the user guide runs as
written, and the spec's JSON Schema accepts every example spec.

The blocks run in the order a reader meets them, from the repository
root: README.md top to bottom (its quickstart installs the program into a
folder of the test's own and runs the main job, whose records in ``out/``,
an ignored folder, the later commands read), then the guide's chapters in
the order of docs/SUMMARY.md. A shell block runs line by line (a line ending in ``\\``
continues on the next) under ``bash -e``; a Python block runs in a fresh
namespace. Only the commands in ``NOT_RUN`` are left out, each for its
reason, and a rule there that matches no command fails the test, so the
list cannot go stale.
"""

from __future__ import annotations

import os
import pathlib
import re
import subprocess
import sys
import json
import tempfile
from typing import Dict, List, Tuple

import pytest

# Commands (by their start) that the README shows but this test does not
# run, and why.
NOT_RUN: Dict[str, str] = {
    "bash scripts/test.sh": "the test command itself, which runs this test",
    "cargo run --release -- bench": "a benchmark: measured on its own, never timed in a test",
    "cargo bench": "a benchmark: measured on its own, never timed in a test",
    "python python/bench/": "a benchmark against reference implementations outside the repository",
    "pip install": "the test command installs the package into the environment this test runs in",
    "bash scripts/brfd.sh": "regenerates the committed example specs (examples/specs/brfd*.json); "
    "its fits and scores are checked by cli/tests/brfd.rs",
}

FENCE = re.compile(r"^(?P<indent>[ \t]*)```(?P<info>[^`\n]*)$")


def blocks(text: str) -> List[Tuple[str, int, str]]:
    """The fenced blocks of a markdown text: (language, first line, code),
    the code with the fence's indentation removed."""
    out: List[Tuple[str, int, str]] = []
    lines = text.split("\n")
    i = 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if m is None or not m.group("info").strip():
            i += 1
            continue
        indent, lang = m.group("indent"), m.group("info").split()[0]
        start, body = i + 1, []
        i += 1
        while i < len(lines) and lines[i].strip() != "```":
            line = lines[i]
            body.append(line[len(indent):] if line.startswith(indent) else line.lstrip())
            i += 1
        out.append((lang, start + 1, "\n".join(body)))
        i += 1
    return out


def commands(code: str) -> List[str]:
    """The commands of a shell block: continued lines joined, comments and
    blank lines dropped."""
    joined = code.replace("\\\n", " ")
    out = []
    for line in joined.split("\n"):
        line = line.strip()
        if line and not line.startswith("#"):
            out.append(line)
    return out


def test_blocks_are_found() -> None:
    text = "a\n```sh\nx \\\n  y\n# c\nz\n```\n  ```python\n  import os\n  ```\n"
    found = blocks(text)
    assert [(lang, line) for lang, line, _ in found] == [("sh", 3), ("python", 9)]
    assert commands(found[0][2]) == ["x    y", "z"]
    assert found[1][2] == "import os"


def chapters(root: pathlib.Path) -> List[pathlib.Path]:
    """README.md, then the guide's chapters in the order of its table of
    contents (each once)."""
    summary = (root / "docs" / "SUMMARY.md").read_text(encoding="utf-8")
    out = [root / "README.md"]
    for target in re.findall(r"\]\(([^)]+\.md)\)", summary):
        path = root / "docs" / target
        if path not in out:
            out.append(path)
    return out


def test_every_documented_command_runs_as_written(root: pathlib.Path) -> None:
    env = dict(os.environ)
    # `python` and `pip` of the environment the package is installed in;
    # `cargo install` into a folder of the test's own, built in the
    # repository's target folder (the release build the commands share)
    install = tempfile.mkdtemp(prefix="hysteron-install-")
    env["CARGO_INSTALL_ROOT"] = install
    env["CARGO_TARGET_DIR"] = str(root / "target")
    env["PATH"] = os.pathsep.join(
        [str(pathlib.Path(install) / "bin"), str(pathlib.Path(sys.executable).parent), env["PATH"]]
    )
    used = {rule: 0 for rule in NOT_RUN}
    ran = {"sh": 0, "python": 0}
    checked_quickstart = False
    for chapter in chapters(root):
        text = chapter.read_text(encoding="utf-8")
        for lang, line, code in blocks(text):
            where = f"{chapter.relative_to(root)} line {line}"
            if lang == "python":
                namespace: dict = {"__name__": "__docs__"}
                old = os.getcwd()
                os.chdir(root)
                try:
                    exec(compile(code, where, "exec"), namespace)
                finally:
                    os.chdir(old)
                ran["python"] += 1
                if chapter.name == "README.md" and "result" in namespace:
                    # the Python quickstart: the fit starts from f_c = 1 and finds 2.0
                    result = namespace["result"]
                    assert result.converged, result.message
                    assert abs(result.values["left.mms.f_c"] - 2.0) < 1e-6
                    checked_quickstart = True
            if lang != "sh":
                continue
            for command in commands(code):
                rule = next((r for r in NOT_RUN if command.startswith(r)), None)
                if rule is not None:
                    used[rule] += 1
                    continue
                done = subprocess.run(
                    ["bash", "-e", "-c", command],
                    cwd=root,
                    env=env,
                    capture_output=True,
                    text=True,
                    timeout=1800,
                )
                assert done.returncode == 0, (
                    f"{where}: `{command}` exited with {done.returncode}:\n"
                    f"{done.stdout[-2000:]}\n{done.stderr[-4000:]}"
                )
                ran["sh"] += 1
    assert checked_quickstart, "the README's Python quickstart was not found"
    assert ran["sh"] >= 20 and ran["python"] >= 3, ran
    stale = [rule for rule, n in used.items() if n == 0]
    assert not stale, f"NOT_RUN rules that match no documented command: {stale}"


def test_chapters_follow_the_table_of_contents(root: pathlib.Path) -> None:
    found = chapters(root)
    assert found[0].name == "README.md" and len(found) > 10
    missing = [p for p in found if not p.exists()]
    assert not missing, missing


@pytest.fixture(scope="module")
def schema(root: pathlib.Path) -> dict:
    return json.loads((root / "docs" / "reference" / "spec.schema.json").read_text(encoding="utf-8"))


def test_the_schema_accepts_every_example_spec(root: pathlib.Path, schema: dict) -> None:
    jsonschema = pytest.importorskip("jsonschema")
    specs = sorted((root / "examples" / "specs").rglob("*.json"))
    assert len(specs) >= 10
    for path in specs:
        jsonschema.validate(json.loads(path.read_text(encoding="utf-8")), schema)


@pytest.mark.parametrize(
    "spec",
    [
        {"type": "play", "r": -1.0},  # out of its domain
        {"type": "play", "r": 1.0, "radius": 2.0},  # an unknown field
        {"type": "mms", "f_c": 1.0},  # a required field left out
        {"type": "cascade", "first": {"type": "gain", "k": 1.0}},
        {"type": "series", "left": {"type": "gain", "k": 1.0}, "right": {"type": "gain", "k": 1.0},
         "limits": {"type": "gap", "b": -0.1, "r0": 0.0}},
        {"type": "sprocket"},
    ],
)
def test_the_schema_refuses_what_the_library_refuses(
    spec: dict, schema: dict, cli: pathlib.Path, tmp_path: pathlib.Path
) -> None:
    jsonschema = pytest.importorskip("jsonschema")
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(spec, schema)
    # and the library refuses it too, naming the field
    (tmp_path / "m.json").write_text(json.dumps(spec), encoding="utf-8")
    (tmp_path / "in.csv").write_text("x\n0.1\n0.2\n", encoding="utf-8")
    done = subprocess.run(
        [str(cli), "simulate", "--model", str(tmp_path / "m.json"), "--input", str(tmp_path / "in.csv"),
         "--column", "x", "--output", str(tmp_path / "out.csv")],
        capture_output=True, text=True,
    )
    assert done.returncode == 1, done.stderr


def test_the_python_api_page_and_stub_docstrings_are_current(root: pathlib.Path) -> None:
    """docs/python-api.md and the docstrings of _native.pyi are what
    scripts/python_docs.py makes of the installed package."""
    done = subprocess.run(
        [sys.executable, str(root / "scripts" / "python_docs.py"), "--check"],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr


def test_help_shows_the_equation_and_every_parameter() -> None:
    import hysteron_rs as hy

    doc = hy.bouc_wen.__doc__ or ""
    assert "dh/dz = α − |h|^n (β sgn(ż h) + γ)" in doc
    for line in ("w (∈ [0, 1])", "n (≥ 1)", "h0 (real; default 0)"):
        assert line in doc, (line, doc)

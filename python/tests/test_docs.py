"""Every shell and Python block of README.md runs as written.

The blocks run in the order the README gives them, from the repository
root, as a reader who follows it top to bottom would run them: the main
job first, whose records in ``out/`` (an ignored folder) the later
commands read. A shell block runs line by line (a line ending in ``\\``
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
from typing import Dict, List, Tuple

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


def test_every_readme_command_runs_as_written(root: pathlib.Path) -> None:
    text = (root / "README.md").read_text(encoding="utf-8")
    env = dict(os.environ)
    # `python` and `pip` of the environment the package is installed in
    env["PATH"] = os.pathsep.join([str(pathlib.Path(sys.executable).parent), env["PATH"]])
    used = {rule: 0 for rule in NOT_RUN}
    ran = {"sh": 0, "python": 0}
    for lang, line, code in blocks(text):
        where = f"README.md line {line}"
        if lang == "python":
            namespace: dict = {"__name__": "__readme__"}
            old = os.getcwd()
            os.chdir(root)
            try:
                exec(compile(code, where, "exec"), namespace)
            finally:
                os.chdir(old)
            ran["python"] += 1
            if "result" in namespace and "model" in namespace:
                # the Python tour: the fit starts from f_c = 1 and finds 2.0
                result, model = namespace["result"], namespace["model"]
                assert result.converged, result.message
                assert abs(result.values["left.mms.f_c"] - 2.0) < 1e-6
                assert namespace["same"] == model
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
    assert ran["sh"] >= 10 and ran["python"] >= 2, ran
    stale = [rule for rule, n in used.items() if n == 0]
    assert not stale, f"NOT_RUN rules that match no README command: {stale}"

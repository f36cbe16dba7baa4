"""Shared fixtures of the C and FMI checks: the release build of
libhysteron_c.so (the C library and the FMU binary), its header, the
`hysteron` program, and a C compiler."""

from __future__ import annotations

import os
import pathlib
import shutil
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def root() -> pathlib.Path:
    return ROOT


def _release_dir() -> pathlib.Path:
    """target/release with the CLI and libhysteron_c.so built (a no-op
    when scripts/test.sh has built them)."""
    subprocess.run(
        ["cargo", "build", "--release", "-q", "-p", "hysteron-cli", "-p", "hysteron-c"],
        cwd=ROOT,
        check=True,
    )
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    return target / "release"


@pytest.fixture(scope="session")
def release() -> pathlib.Path:
    return _release_dir()


@pytest.fixture(scope="session")
def cli(release: pathlib.Path) -> pathlib.Path:
    return release / "hysteron"


@pytest.fixture(scope="session")
def cc() -> str:
    compiler = os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc")
    if compiler is None:
        pytest.fail("no C compiler (cc) on this machine")
    return compiler


@pytest.fixture(scope="session")
def build_c(cc: str, release: pathlib.Path, root: pathlib.Path, tmp_path_factory):
    """Compiles C sources against hysteron.h and libhysteron_c.so; returns
    the executable's path."""
    out_dir = tmp_path_factory.mktemp("c")

    def build(*sources: pathlib.Path, name: str, sanitize: bool = False) -> pathlib.Path:
        """`sanitize` builds with AddressSanitizer and UndefinedBehaviorSanitizer
        (the C side; the library's own allocations go through the
        sanitizer's malloc and free)."""
        exe = out_dir / name
        flags = ["-O1", "-g", "-fsanitize=address,undefined", "-fno-omit-frame-pointer"] if sanitize else ["-O2"]
        subprocess.run(
            [cc, "-std=c11", *flags, "-Wall", "-Wextra", "-Werror", "-I", str(root / "capi" / "include"),
             *map(str, sources), "-o", str(exe), "-L", str(release), "-lhysteron_c",
             f"-Wl,-rpath,{release}", "-lm"],
            check=True,
        )
        return exe

    return build

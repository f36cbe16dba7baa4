"""The C API from C: the two examples in examples/c compile cleanly
(-std=c11 -Wall -Wextra -Werror) against capi/include/hysteron.h and run,
and capi/checks/c/contract.c checks the API's contract (step/process,
trial/commit, reset, clone, parameters, every error path)."""

from __future__ import annotations

import os
import pathlib
import re
import subprocess

import pytest

# The number of `ok` lines capi/checks/c/contract.c prints when every check
# passes (update it with the checks).
CONTRACT_CHECKS = 68

NUMBER = r"([0-9.eE+-]+)"


def _run(exe, *args, cwd):
    result = subprocess.run(
        [str(exe), *map(str, args)], cwd=cwd, capture_output=True, text=True, timeout=600
    )
    assert result.returncode == 0, (
        f"{exe.name} exited with {result.returncode}\n"
        f"stdout:\n{result.stdout}\nstderr:\n{result.stderr}"
    )
    return result.stdout


def _errors(label: str, text: str) -> tuple[float, float]:
    """(max, RMS) of the line `<label>: max |y - r| = <max>   RMS = <rms>`."""
    match = re.search(rf"^{label}:\s+max \|y - r\| = {NUMBER}\s+RMS = {NUMBER}$", text, re.M)
    assert match, f"no `{label}` line in:\n{text}"
    return float(match.group(1)), float(match.group(2))


def test_pi_tracking(build_c, root):
    exe = build_c(root / "examples" / "c" / "pi_tracking.c", name="pi_tracking")
    for args in ([], [root / "examples" / "specs" / "prandtl-ishlinskii.json"]):
        out = _run(exe, *args, cwd=root)
        amplitude = float(re.search(rf"max \|r\| = {NUMBER}$", out, re.M).group(1))
        comp_max, comp_rms = _errors("compensated", out)
        open_max, open_rms = _errors("uncompensated", out)
        assert amplitude > 0.5
        # The analytic inverse of a PI bank (Krejci & Kuhnen) is exact in
        # exact arithmetic: plant(inverse(r)) = r. What remains is rounding
        # in the inverse's thresholds and weights and in each play update,
        # which does not accumulate: a moving play's output is recomputed
        # from the current input (x - r or x + r), so rounding does not
        # integrate over samples. Measured: max |y - r| = 6.7e-16 on this
        # reference of max |r| = 1.23 (about 2.4 eps relative; 8.9e-16 over
        # 400000 samples). The bound 1e-9 relative leaves six orders of
        # magnitude of room for rounding while failing for any inverse that
        # is not exact (a few percent of mis-identification gives ~1e-2).
        assert comp_max <= 1e-9 * amplitude, out
        assert comp_rms <= comp_max
        # Without the compensator the error is of the order of the signal.
        assert open_max > 0.1 * amplitude, out
        assert comp_max < 1e-6 * open_max and comp_rms < 1e-6 * open_rms, out


def test_pi_tracking_reports_a_bad_spec(build_c, root, tmp_path):
    exe = build_c(root / "examples" / "c" / "pi_tracking.c", name="pi_tracking_bad")
    spec = tmp_path / "bad.json"
    # A bank whose zero-threshold weight is negative has no inverse.
    spec.write_text('{"type": "pi_bank", "a0": -5.0, "r": [0.1], "w": [1.0]}')
    result = subprocess.run([str(exe), str(spec)], capture_output=True, text=True, timeout=60)
    assert result.returncode == 1
    assert "a0" in result.stderr, result.stderr


def test_bench_step(build_c, root):
    exe = build_c(root / "examples" / "c" / "bench_step.c", name="bench_step")
    n = 200_000
    out = _run(exe, root / "examples" / "specs" / "paper.json", n, cwd=root)
    step = re.search(
        rf"^step: {NUMBER} ns per call \(paper model, {n} calls, median of 5\)$", out, re.M
    )
    process = re.search(
        rf"^process: {NUMBER} ns per sample \(paper model, {n} samples, median of 5\)$", out, re.M
    )
    assert step and process, out
    assert float(step.group(1)) > 0 and float(process.group(1)) > 0, out
    # The checksums of step and process agree (the same samples).
    sums = re.search(rf"^checksum: step {NUMBER}, process {NUMBER}$", out, re.M)
    assert sums and sums.group(1) == sums.group(2), out


def test_contract(build_c, root):
    exe = build_c(root / "capi" / "checks" / "c" / "contract.c", name="contract")
    out = _run(exe, root / "examples" / "specs" / "paper.json", cwd=root)
    ok = [line for line in out.splitlines() if re.match(r"ok \d+ - ", line)]
    assert not re.search(r"^not ok", out, re.M), out
    assert len(ok) == CONTRACT_CHECKS, out


def test_bench_fmi(build_c, root, cli, tmp_path):
    """examples/c/bench_fmi.c drives an exported FMU as a host does and the
    same model through the C API; both give the same outputs (the program
    exits 1 if their sums differ)."""
    import zipfile

    fmu = tmp_path / "paper.fmu"
    subprocess.run([str(cli), "export-fmu", "--model", str(root / "examples" / "specs" / "paper.json"), "--output", str(fmu)], check=True, capture_output=True)
    unzipped = tmp_path / "paper"
    zipfile.ZipFile(fmu).extractall(unzipped)
    exe = build_c(root / "examples" / "c" / "bench_fmi.c", name="bench_fmi")
    out = _run(exe, unzipped, 20000, cwd=root)
    fmi = float(re.search(rf"^fmi2DoStep: {NUMBER} ns per step", out, re.M).group(1))
    capi = float(re.search(rf"^hysteron_step: {NUMBER} ns per step", out, re.M).group(1))
    assert fmi > 0 and capi > 0
    sums = re.search(rf"^checksum: fmi {NUMBER}, capi {NUMBER}$", out, re.M)
    assert sums and sums.group(1) == sums.group(2), out


@pytest.fixture
def unzipped_paper_fmu(cli, root, tmp_path) -> pathlib.Path:
    import zipfile

    fmu = tmp_path / "paper.fmu"
    subprocess.run([str(cli), "export-fmu", "--model", str(root / "examples" / "specs" / "paper.json"), "--output", str(fmu)], check=True, capture_output=True)
    unzipped = tmp_path / "paper"
    zipfile.ZipFile(fmu).extractall(unzipped)
    return unzipped


def test_the_c_checks_run_clean_under_address_and_undefined_behaviour_sanitizers(build_c, root, unzipped_paper_fmu):
    """contract.c and a short soak.c (200 cycles: the sanitizer's
    quarantine makes memory figures meaningless, so only its reports
    count) built with -fsanitize=address,undefined: no report, exit 0,
    leaks checked at exit."""
    env = dict(os.environ, ASAN_OPTIONS="detect_leaks=1", UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1")
    runs = [
        (build_c(root / "capi" / "checks" / "c" / "contract.c", name="contract_asan", sanitize=True), [root / "examples" / "specs" / "paper.json"]),
        (build_c(root / "capi" / "checks" / "c" / "soak.c", name="soak_asan", sanitize=True), [unzipped_paper_fmu, 200, 1000]),
    ]
    for exe, args in runs:
        result = subprocess.run([str(exe), *map(str, args)], cwd=root, capture_output=True, text=True, timeout=600, env=env)
        assert result.returncode == 0, result.stderr
        assert "Sanitizer" not in result.stderr and "runtime error" not in result.stderr, result.stderr


def test_ten_thousand_lives_in_one_process_keep_memory_flat(build_c, root, unzipped_paper_fmu):
    """capi/checks/c/soak.c: 10 000 cycles of instantiate, 1000 steps,
    reset, 1000 steps, free, through the FMU's fmi2 functions and through
    the C API: every run gives the first run's outputs, and resident memory
    grows by less than 1 MB after the first 100 cycles."""
    exe = build_c(root / "capi" / "checks" / "c" / "soak.c", name="soak")
    out = _run(exe, unzipped_paper_fmu, 10000, 1000, cwd=root)
    for face in ("fmi2", "capi"):
        line = re.search(
            rf"^{face}: 10000 cycles of 1000 steps, {NUMBER} us per cycle, resident (\d+) kB after 100 cycles, (\d+) kB at the end, growth (-?\d+) kB$",
            out,
            re.M,
        )
        assert line, out
        assert int(line.group(2)) > 0, out  # memory was read
        assert int(line.group(4)) < 1024, out

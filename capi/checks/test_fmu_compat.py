"""`hysteron fmu-compat`: the compatibility information of the FMU export
(per model and FMI version the FMU, `_in.csv`, `_ref.csv`, `_ref.opt` and
a ReadMe, in the FMI Cross-Check layout), checked as an importer checks
it: FMPy's validation of the FMU and of the folder (its cross-check
module), then a simulation with the input and the `_ref.opt` settings that
must reproduce the reference, which the library computed, to 1e-12
relative."""

from __future__ import annotations

import pathlib
import subprocess

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy.cross_check.validate_vendor_repo import validate_repo, validate_test_fmu  # noqa: E402
from fmpy.util import read_csv, read_ref_opt_file  # noqa: E402
from fmpy.validation import validate_fmu  # noqa: E402

MODELS = ["PaperModel", "BoucWenBenchmark"]
LAYOUT = {"2.0": "linux64", "3.0": "x86_64-linux"}


def version(cli: pathlib.Path) -> str:
    out = subprocess.run([str(cli), "--version"], check=True, capture_output=True, text=True).stdout
    return out.split()[-1]


@pytest.fixture(scope="module")
def compat(cli, tmp_path_factory) -> pathlib.Path:
    out = tmp_path_factory.mktemp("compat")
    r = subprocess.run([str(cli), "fmu-compat", str(out)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert "wrote 4 FMUs" in r.stdout, r.stdout
    return out


def folders(compat: pathlib.Path, cli: pathlib.Path):
    for fmi, platform in LAYOUT.items():
        for model in MODELS:
            yield fmi, model, compat / "fmus" / fmi / "cs" / platform / "hysteron" / version(cli) / model


def test_the_folders_hold_the_files_the_rules_ask_for_and_nothing_else(compat, cli) -> None:
    found = sorted(p.relative_to(compat).as_posix() for p in compat.rglob("*") if p.is_file())
    want = sorted(
        f"{d.relative_to(compat).as_posix()}/{name}"
        for _, model, d in folders(compat, cli)
        for name in [f"{model}.fmu", f"{model}_in.csv", f"{model}_ref.csv", f"{model}_ref.opt", "ReadMe.md"]
    )
    assert found == want
    for fmi, model, d in folders(compat, cli):
        # CSV files under 1 MB, the header quoted, `time` first
        for name, column in [(f"{model}_in.csv", "x"), (f"{model}_ref.csv", "y")]:
            text = (d / name).read_text()
            assert len(text.encode()) < 1_000_000
            assert text.splitlines()[0] == f'"time","{column}"'
        readme = (d / "ReadMe.md").read_text()
        assert f"FMI {fmi} co-simulation FMU from hysteron {version(cli)}" in readme
        assert "How the reference was made" in readme


@pytest.mark.filterwarnings("ignore:Please import:DeprecationWarning")  # FMPy's use of scipy.ndimage.filters
@pytest.mark.parametrize("fmi", list(LAYOUT))
@pytest.mark.parametrize("model", MODELS)
def test_fmpy_reproduces_the_reference_with_the_input_and_options(compat, cli, fmi, model) -> None:
    d = compat / "fmus" / fmi / "cs" / LAYOUT[fmi] / "hysteron" / version(cli) / model
    fmu = d / f"{model}.fmu"
    assert validate_fmu(str(fmu)) == []
    md = fmpy.read_model_description(str(fmu))
    assert md.fmiVersion == fmi and md.coSimulation.modelIdentifier == model
    # FMPy's check of an exporter's folder: the description, the options,
    # the CSV files and their variables, the file sizes.
    assert validate_test_fmu(str(d)) == []
    opt = read_ref_opt_file(str(d / f"{model}_ref.opt"))
    inputs = read_csv(d / f"{model}_in.csv")
    ref = read_csv(d / f"{model}_ref.csv")
    assert inputs["time"][0] == opt["StartTime"] and inputs["time"][-1] == opt["StopTime"]
    assert ref["time"][0] == opt["StartTime"] and ref["time"][-1] == opt["StopTime"]
    x = inputs["x"]
    assert np.sum(np.diff(np.sign(np.diff(x))) != 0) >= 10  # reversals
    result = fmpy.simulate_fmu(
        str(fmu),
        start_time=opt["StartTime"],
        stop_time=opt["StopTime"],
        output_interval=opt["StepSize"],
        relative_tolerance=opt["RelTol"],
        input=inputs,
        output=["y"],
    )
    assert result.size == ref.size
    np.testing.assert_allclose(result["time"], ref["time"], rtol=0, atol=1e-12 * opt["StopTime"])
    scale = np.max(np.abs(ref["y"]))
    assert scale > 0
    err = np.max(np.abs(result["y"] - ref["y"]))
    assert err <= opt["RelTol"] * scale, (err, scale)
    assert opt["RelTol"] <= 1e-12
    # and FMPy's cross-check verdict on the result (a band around the
    # reference, drawn with SciPy): no problem
    pytest.importorskip("scipy")
    from fmpy.cross_check import validate_result

    assert validate_result(result, ref, opt["StartTime"], opt["StopTime"]) is None


def test_the_fmi_2_folders_pass_fmpys_vendor_repository_check(compat) -> None:
    """validate_vendor_repo knows FMI 1.0 and 2.0 only: it finds the two
    FMI 2.0 folders."""
    fmus, results, problems = validate_repo(str(compat))
    assert (fmus, results, problems) == (4, 0, [])


def test_one_version_only(cli, tmp_path) -> None:
    r = subprocess.run([str(cli), "fmu-compat", str(tmp_path), "--fmi", "3"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert sorted(p.name for p in (tmp_path / "fmus").iterdir()) == ["3.0"]


def fails(cli: pathlib.Path, *args: str) -> str:
    r = subprocess.run([str(cli), "fmu-compat", *args], capture_output=True, text=True)
    assert r.returncode == 1 and r.stdout == "" and "panicked" not in r.stderr, r
    assert r.stderr.startswith("error: "), r.stderr
    return r.stderr


def test_bad_arguments_are_clear_errors(cli, tmp_path) -> None:
    err = fails(cli, str(tmp_path), "--fmi", "4")
    assert "invalid value '4' for '--fmi <VERSION>'" in err and "possible values: 2, 3" in err, err
    # /proc takes no new folder, even for root
    err = fails(cli, "/proc/hysteron-compat")
    assert err.count("\n") == 1 and "cannot create the folder `/proc/hysteron-compat" in err, err
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    err = fails(cli, str(blocker))
    assert err.count("\n") == 1 and f"cannot create the folder `{blocker}/fmus`" in err, err
    err = fails(cli, str(tmp_path / "out"), "--library", str(tmp_path / "missing.so"))
    assert err.count("\n") == 1 and "missing.so" in err and "--library" in err, err

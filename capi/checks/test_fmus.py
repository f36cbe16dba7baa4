"""What the FMI 2.0 and the FMI 3.0 FMU of a spec both do, checked with an
independent FMI host, FMPy, for each version: validation, simulation
against `hysteron simulate` bit for bit, the step size as the period of a
rate-dependent model, states saved and restored, and parameters changed
as start values or between steps. What only one version does, or does
in its own way, is checked in test_fmu.py (FMI 2.0) and test_fmu3.py
(FMI 3.0)."""

from __future__ import annotations

import json
import pathlib

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy.validation import validate_fmu  # noqa: E402

from fmus import CASES, H, Slave2, Slave3, benchmark_input, cli_simulate, fmpy_simulate, signal  # noqa: E402


@pytest.fixture(params=[Slave2, Slave3], ids=["fmi2", "fmi3"])
def version(request) -> type:
    """The slave class of an FMI version: it exports and drives its FMUs."""
    return request.param


@pytest.fixture
def paper_fmu(cli, root, tmp_path, version) -> pathlib.Path:
    return version.export(cli, root / "examples" / "specs" / "paper.json", tmp_path / "paper.fmu")


EXAMPLE_SPECS = sorted(p.name for p in (pathlib.Path(__file__).resolve().parents[2] / "examples" / "specs").glob("*.json"))


@pytest.mark.parametrize("spec", EXAMPLE_SPECS)
def test_every_example_spec_gives_an_fmu_fmpy_validates_and_runs(cli, root, tmp_path, version, spec) -> None:
    """FMPy's validation, which checks the structured names (`e[1,0]`, not
    `e[1][0]`) among much else, finds nothing in the FMU of any example
    spec, and FMPy's simulation of it is `hysteron simulate` at the same
    period (a step of 2^-10 s, exact in binary), bit for bit."""
    path = root / "examples" / "specs" / spec
    fmu = version.export(cli, path, tmp_path / "model.fmu")
    assert validate_fmu(str(fmu)) == []
    x = signal(1500, 0.5)
    got = fmpy_simulate(fmu, x, H)
    want = cli_simulate(cli, path, x, tmp_path, "--dt", repr(H))
    assert np.array_equal(got, want), np.max(np.abs(got - want))


def test_a_parameter_grid_has_structured_names(cli, tmp_path, version) -> None:
    """A Preisach table's triangular weights `e[i][j]` (scalars in both
    versions) are named `e[i,j]`, as the structured naming convention
    writes array subscripts, and FMPy's validation finds nothing."""
    spec = tmp_path / "grid.json"
    spec.write_text(json.dumps({"type": "preisach", "start": "from_above", "measure": {"table": {"x": [-1, 0, 1], "e": [[0.5], [2, 0.5]]}}}))
    fmu = version.export(cli, spec, tmp_path / "grid.fmu")
    assert validate_fmu(str(fmu)) == []
    names = [v.name for v in fmpy.read_model_description(str(fmu)).modelVariables]
    assert "e[1,0]" in names and not any("][" in n for n in names), names


@pytest.mark.parametrize("spec, amplitude", CASES)
def test_validates_and_reproduces_the_cli_bit_for_bit(cli, root, tmp_path, version, spec, amplitude) -> None:
    path = root / "examples" / "specs" / spec
    fmu = version.export(cli, path, tmp_path / "model.fmu")
    assert validate_fmu(str(fmu)) == []
    x = signal(3000, amplitude)
    got = fmpy_simulate(fmu, x, 1e-3)
    want = cli_simulate(cli, path, x, tmp_path)
    assert np.array_equal(got, want), np.max(np.abs(got - want))


def test_rate_dependent_model_takes_the_step_as_its_period(cli, root, tmp_path, version) -> None:
    """The Bouc-Wen benchmark (an oversampled mass-spring-damper with a
    Bouc-Wen spring in its feedback path) run by FMPy at the data rate:
    its period comes from the step size of fmi2DoStep or fmi3DoStep."""
    path = root / "examples" / "specs" / "boucwen-benchmark.json"
    fmu = version.export(cli, path, tmp_path / "bw.fmu")
    assert validate_fmu(str(fmu)) == []
    u, y_ref = benchmark_input(root, 2)
    # A step of 2^-10 s, exact in binary: FMPy's steps are all exactly H,
    # and the CLI given --dt H gives the same bits.
    got = fmpy_simulate(fmu, u[:4000] * 0.5, H)
    assert np.array_equal(got, cli_simulate(cli, path, u[:4000] * 0.5, tmp_path, "--dt", repr(H)))
    # At the data rate, 750 Hz: FMPy's step sizes are differences of
    # rounded communication points, 1/750 within a few ulps; the FMU takes
    # a step within 1e-9 (relative) of its period as that period, so the
    # outputs are the CLI's at exactly 1/750, bit for bit.
    got = fmpy_simulate(fmu, u, 1.0 / 750.0)
    want = cli_simulate(cli, path, u, tmp_path, "--dt", repr(1.0 / 750.0))
    assert np.array_equal(got, want), np.max(np.abs(got - want))
    # And it is the benchmark: the second period matches the published
    # output (the transient has died out) to 1e-5 m RMS (6.7e-4 m signal).
    err = np.sqrt(np.mean((got[y_ref.size :] - y_ref) ** 2))
    assert err <= 1e-5, err


def test_saved_states_replay_identically_and_reset_restarts(paper_fmu, version) -> None:
    s = version(paper_fmu)
    x = signal(1200)
    first = s.run(x[:500])
    state = s.get_state()
    a = s.run(x[500:])
    s.set_state(state)
    b = s.run(x[500:])
    assert np.array_equal(a, b)
    s.free_state(state)
    s.fmu.reset()
    s.start()
    assert np.array_equal(s.run(x[:500]), first)
    s.close()


def test_a_parameter_change_acts_as_the_same_change_in_the_spec(cli, root, paper_fmu, tmp_path, version) -> None:
    spec = json.loads((root / "examples" / "specs" / "paper.json").read_text())
    spec["left"]["f_c"] = 2.5
    changed = tmp_path / "changed.json"
    changed.write_text(json.dumps(spec))
    x = signal(1500)
    want = cli_simulate(cli, changed, x, tmp_path)
    # Before the start, as a start value.
    assert np.array_equal(fmpy_simulate(paper_fmu, x, 1e-3, {"left.mms.f_c": 2.5}), want)
    # Between steps: the outputs go on as the changed spec's.
    s = version(paper_fmu)
    before = s.run(x[:700])
    assert not np.array_equal(before, want[:700])
    s.set([s.vr["left.mms.f_c"]], [2.5])
    assert s.get([s.vr["left.mms.f_c"]]) == [2.5]
    assert np.array_equal(s.run(x[700:]), want[700:])
    s.close()

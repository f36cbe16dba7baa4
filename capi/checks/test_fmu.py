"""FMI 2.0 co-simulation FMUs from `hysteron export-fmu`, checked with an
independent FMI host, FMPy: validation, simulation against `hysteron
simulate`, state save/restore, parameter changes, errors, independence.

FMPy applies the input of the table at the start of each step, and
`fmi2DoStep` takes the input set last as the sample at the end of the step,
so FMPy's output row k + 1 is the CLI's output row k (row 0 is the initial
output)."""

from __future__ import annotations

import csv
import json
import pathlib
import subprocess

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy.fmi2 import FMU2Slave  # noqa: E402
from fmpy.validation import validate_fmu  # noqa: E402

H = 2.0**-10  # a step whose multiples are exact: FMPy's steps are then exactly H


def export(cli: pathlib.Path, spec: pathlib.Path, out: pathlib.Path, *extra: str) -> pathlib.Path:
    subprocess.run([str(cli), "export-fmu", "--model", str(spec), "--output", str(out), *extra], check=True, capture_output=True)
    return out


def cli_simulate(cli: pathlib.Path, spec: pathlib.Path, x: np.ndarray, tmp: pathlib.Path, *extra: str) -> np.ndarray:
    src, dst = tmp / "in.csv", tmp / "out.csv"
    with open(src, "w") as f:
        f.write("x\n")
        for v in x:
            f.write(f"{float(v)!r}\n")
    subprocess.run([str(cli), "simulate", "--model", str(spec), "--input", str(src), "--output", str(dst), *extra], check=True, capture_output=True)
    with open(dst) as f:
        return np.array([float(r["y"]) for r in csv.DictReader(f)])


def fmpy_simulate(fmu: pathlib.Path, x: np.ndarray, h: float, start_values: dict | None = None) -> np.ndarray:
    n = x.size
    t = np.arange(n) * h
    table = np.array(list(zip(t, x)), dtype=[("time", np.float64), ("x", np.float64)])
    res = fmpy.simulate_fmu(str(fmu), start_time=0.0, stop_time=n * h, output_interval=h, input=table, output=["y"], start_values=start_values or {})
    assert res.size == n + 1
    return res["y"][1:]


def signal(n: int, amplitude: float = 1.4) -> np.ndarray:
    i = np.arange(n)
    return amplitude * np.exp(-i / n) * np.sin(2 * np.pi * i / 400) + 0.1 * amplitude * np.sin(2 * np.pi * i / 37)


CASES = [
    ("paper.json", 1.4),  # the paper's model: friction in a gap, Bouc-Wen spring
    ("prandtl-ishlinskii.json", 1.0),  # a PI bank
    ("pi-inverse.json", 1.0),  # its analytic inverse
]


@pytest.mark.parametrize("spec, amplitude", CASES)
def test_validates_and_reproduces_the_cli_bit_for_bit(cli, root, tmp_path, spec, amplitude) -> None:
    path = root / "examples" / "specs" / spec
    fmu = export(cli, path, tmp_path / "model.fmu")
    assert validate_fmu(str(fmu)) == []
    x = signal(3000, amplitude)
    got = fmpy_simulate(fmu, x, 1e-3)
    want = cli_simulate(cli, path, x, tmp_path)
    assert np.array_equal(got, want), np.max(np.abs(got - want))


def benchmark_input(root: pathlib.Path, periods: int) -> tuple:
    with open(root / "data" / "boucwen-benchmark" / "val_multisine.csv") as f:
        rows = list(csv.DictReader(f))
    keys = list(rows[0])
    u = np.array([float(r[keys[1]]) for r in rows])
    y = np.array([float(r[keys[2]]) for r in rows])
    return np.tile(u, periods), y


def test_rate_dependent_model_takes_the_step_as_its_period(cli, root, tmp_path) -> None:
    """The Bouc-Wen benchmark (an oversampled mass-spring-damper with a
    Bouc-Wen spring in its feedback path) run by FMPy at the data rate:
    its period comes from fmi2DoStep's step size."""
    path = root / "examples" / "specs" / "boucwen-benchmark.json"
    fmu = export(cli, path, tmp_path / "bw.fmu")
    assert validate_fmu(str(fmu)) == []
    u, y_ref = benchmark_input(root, 2)
    n = y_ref.size
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
    err = np.sqrt(np.mean((got[n:] - y_ref) ** 2))
    assert err <= 1e-5, err


def test_a_spec_without_dt_takes_the_period_from_the_step(cli, root, tmp_path) -> None:
    """The benchmark's spec with its dt left out: an FMU of it runs at the
    host's step size, exactly as the spec with that dt written in."""
    import json

    spec = json.loads((root / "examples" / "specs" / "boucwen-benchmark.json").read_text())
    del spec["inner"]["forward"]["dt"]
    path = tmp_path / "no-dt.json"
    path.write_text(json.dumps(spec))
    fmu = export(cli, path, tmp_path / "no-dt.fmu")
    assert validate_fmu(str(fmu)) == []
    u, _ = benchmark_input(root, 1)
    got = fmpy_simulate(fmu, u[:3000], H)
    want = cli_simulate(cli, root / "examples" / "specs" / "boucwen-benchmark.json", u[:3000], tmp_path, "--dt", repr(H))
    assert np.array_equal(got, want), np.max(np.abs(got - want))


class Slave:
    """An instance driven by hand through FMPy's FMU2Slave."""

    def __init__(self, fmu: pathlib.Path, name: str = "inst") -> None:
        md = fmpy.read_model_description(str(fmu))
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.dir = fmpy.extract(str(fmu))
        self.fmu = FMU2Slave(guid=md.guid, unzipDirectory=self.dir, modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
        self.fmu.instantiate()
        self.start()
        self.t = 0.0

    def start(self) -> None:
        self.fmu.setupExperiment(startTime=0.0)
        self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()
        self.t = 0.0

    def run(self, xs) -> np.ndarray:
        out = []
        for x in xs:
            self.fmu.setReal([self.vr["x"]], [float(x)])
            self.fmu.doStep(currentCommunicationPoint=self.t, communicationStepSize=H)
            self.t += H
            out.append(self.fmu.getReal([self.vr["y"]])[0])
        return np.array(out)

    def close(self) -> None:
        self.fmu.terminate()
        self.fmu.freeInstance()


@pytest.fixture
def paper_fmu(cli, root, tmp_path) -> pathlib.Path:
    return export(cli, root / "examples" / "specs" / "paper.json", tmp_path / "paper.fmu")


def test_saved_states_replay_identically_and_reset_restarts(paper_fmu) -> None:
    s = Slave(paper_fmu)
    x = signal(1200)
    first = s.run(x[:500])
    state = s.fmu.getFMUstate()
    a = s.run(x[500:])
    s.fmu.setFMUstate(state)
    b = s.run(x[500:])
    assert np.array_equal(a, b)
    s.fmu.freeFMUstate(state)
    s.fmu.reset()
    s.start()
    assert np.array_equal(s.run(x[:500]), first)
    s.close()


def test_a_serialized_state_continues_bit_for_bit_in_a_fresh_instance(paper_fmu, capsys) -> None:
    s = Slave(paper_fmu)
    x = signal(1500)
    s.run(x[:600])
    s.fmu.setReal([s.vr["left.mms.f_c"]], [2.0])  # a parameter changed on the way
    s.run(x[600:700])
    state = s.fmu.getFMUstate()
    data = s.fmu.serializeFMUstate(state)
    s.fmu.freeFMUstate(state)
    a = s.run(x[700:])
    fresh = Slave(paper_fmu, "fresh")
    restored = fresh.fmu.deSerializeFMUstate(data)
    fresh.fmu.setFMUstate(restored)
    fresh.fmu.freeFMUstate(restored)
    fresh.t = s.t - (x.size - 700) * H
    assert fresh.fmu.getReal([fresh.vr["left.mms.f_c"]]) == [2.0]
    assert np.array_equal(fresh.run(x[700:]), a)
    # Truncated or corrupted bytes: fmi2Error with a logged message; the
    # instance is unchanged.
    capsys.readouterr()
    before = fresh.fmu.getReal([fresh.vr["y"]])
    for bad, why in [(data[:-1], "CRC-32"), (data[:40], "truncated"), (data[:60] + bytes([data[60] ^ 1]) + data[61:], "CRC-32")]:
        with pytest.raises(Exception, match="fmi2DeSerializeFMUstate"):
            fresh.fmu.deSerializeFMUstate(bad)
        assert why in capsys.readouterr().out
    assert fresh.fmu.getReal([fresh.vr["y"]]) == before
    s.close()
    fresh.close()


def test_directional_derivatives_agree_with_central_differences_of_the_fmu(paper_fmu) -> None:
    s = Slave(paper_fmu)
    x = signal(900)
    s.run(x[:-1])
    before = s.fmu.getFMUstate()
    s.run(x[-1:])
    y, f_c = s.vr["y"], s.vr["left.mms.f_c"]

    def y_after_last(value: float, vr: int) -> float:
        """y of the last step again, with `vr` set to `value` before it."""
        after = s.fmu.getFMUstate()
        s.fmu.setFMUstate(before)
        s.fmu.setReal([vr], [value])
        if vr != s.vr["x"]:
            s.fmu.setReal([s.vr["x"]], [float(x[-1])])
        s.fmu.doStep(currentCommunicationPoint=s.t - H, communicationStepSize=H)
        out = s.fmu.getReal([y])[0]
        s.fmu.setFMUstate(after)
        s.fmu.freeFMUstate(after)
        return out

    for vr, at in [(s.vr["x"], float(x[-1])), (f_c, 1.5)]:
        exact = s.fmu.getDirectionalDerivative([y], [vr], [1.0])[0]
        d = 1e-6 * abs(at)
        fd = (y_after_last(at + d, vr) - y_after_last(at - d, vr)) / (2 * d)
        assert abs(exact - fd) <= 1e-6 * abs(exact), (vr, exact, fd)
    # a combination: J · dv over two knowns
    both = s.fmu.getDirectionalDerivative([y], [s.vr["x"], f_c], [2.0, -3.0])[0]
    parts = [s.fmu.getDirectionalDerivative([y], [vr], [1.0])[0] for vr in (s.vr["x"], f_c)]
    assert both == pytest.approx(2.0 * parts[0] - 3.0 * parts[1], rel=1e-15)
    with pytest.raises(Exception, match="fmi2GetDirectionalDerivative"):
        s.fmu.getDirectionalDerivative([s.vr["x"]], [f_c], [1.0])
    s.close()


def test_a_parameter_change_acts_as_the_same_change_in_the_spec(cli, root, paper_fmu, tmp_path) -> None:
    spec = json.loads((root / "examples" / "specs" / "paper.json").read_text())
    spec["left"]["f_c"] = 2.5
    changed = tmp_path / "changed.json"
    changed.write_text(json.dumps(spec))
    x = signal(1500)
    want = cli_simulate(cli, changed, x, tmp_path)
    # Before the start, as a start value.
    assert np.array_equal(fmpy_simulate(paper_fmu, x, 1e-3, {"left.mms.f_c": 2.5}), want)
    # Between steps: the outputs go on as the changed spec's.
    s = Slave(paper_fmu)
    before = s.run(x[:700])
    assert not np.array_equal(before, want[:700])
    s.fmu.setReal([s.vr["left.mms.f_c"]], [2.5])
    assert s.fmu.getReal([s.vr["left.mms.f_c"]]) == [2.5]
    assert np.array_equal(s.run(x[700:]), want[700:])
    s.close()


def test_errors_are_fmi2Error_with_a_message_and_leave_the_instance_usable(paper_fmu, capsys) -> None:
    s = Slave(paper_fmu)
    x = signal(300)
    ok = s.run(x[:100])
    capsys.readouterr()
    with pytest.raises(Exception, match="fmi2SetReal"):
        s.fmu.setReal([s.vr["x"]], [float("nan")])
    with pytest.raises(Exception, match="fmi2SetReal"):
        s.fmu.setReal([s.vr["left.mms.f_c"]], [-1.0])
    with pytest.raises(Exception, match="fmi2SetReal"):
        s.fmu.setReal([s.vr["right.bouc_wen.z0"]], [0.3])  # tied to limits.r0
    with pytest.raises(Exception, match="fmi2SetReal"):
        s.fmu.setReal([s.vr["y"]], [1.0])
    with pytest.raises(Exception, match="fmi2DoStep"):
        s.fmu.doStep(currentCommunicationPoint=s.t, communicationStepSize=0.0)
    with pytest.raises(Exception, match="fmi2DeSerializeFMUstate"):
        s.fmu.deSerializeFMUstate(b"hysteron-state but not one")
    log = capsys.readouterr().out
    for fragment in ["x: input NaN is not finite", "f_c", "z0", "y is an output", "communicationStepSize must be positive", "the state has format version"]:
        assert fragment in log, (fragment, log)
    # Tied parameters move together in one call.
    s.fmu.setReal([s.vr["limits.r0"], s.vr["right.bouc_wen.z0"]], [0.05, -0.05])
    # Nothing else changed; the instance runs on.
    fresh = Slave(paper_fmu, "fresh")
    fresh.fmu.setReal([fresh.vr["limits.r0"], fresh.vr["right.bouc_wen.z0"]], [0.05, -0.05])
    assert np.array_equal(s.run(x[100:]), fresh.run(x)[100:])
    assert not np.array_equal(ok, fresh.run(x[:100]))
    s.close()
    fresh.close()


def test_instances_are_independent(paper_fmu) -> None:
    a, b = Slave(paper_fmu, "a"), Slave(paper_fmu, "b")
    x = signal(600)
    alone = Slave(paper_fmu, "alone").run(x)
    ya, yb = [], []
    for v in x:  # interleaved, b on a scaled input
        ya.extend(a.run([v]))
        yb.extend(b.run([0.5 * v]))
    assert np.array_equal(np.array(ya), alone)
    assert not np.array_equal(np.array(yb), alone)
    a.close()
    b.close()


def test_two_fmus_of_different_models_stepped_alternately_are_each_their_solo_run(cli, root, paper_fmu, tmp_path) -> None:
    pi_fmu = export(cli, root / "examples" / "specs" / "prandtl-ishlinskii.json", tmp_path / "pi.fmu")
    x = signal(800)
    solo_paper = Slave(paper_fmu, "solo paper").run(x)
    solo_pi = Slave(pi_fmu, "solo pi").run(0.7 * x)
    paper, pi = Slave(paper_fmu, "paper"), Slave(pi_fmu, "pi")
    ya, yb = [], []
    for v in x:
        ya.extend(paper.run([v]))
        yb.extend(pi.run([0.7 * v]))
    assert np.array_equal(np.array(ya), solo_paper)
    assert np.array_equal(np.array(yb), solo_pi)
    paper.close()
    pi.close()


def test_wrong_guid_and_model_exchange_are_refused(paper_fmu) -> None:
    md = fmpy.read_model_description(str(paper_fmu))
    unzip = fmpy.extract(str(paper_fmu))
    bad = FMU2Slave(guid="{00000000-0000-0000-0000-000000000000}", unzipDirectory=unzip, modelIdentifier=md.coSimulation.modelIdentifier, instanceName="bad")
    with pytest.raises(Exception, match="Failed to instantiate"):
        bad.instantiate()


def test_export_errors_are_one_line(cli, root, tmp_path) -> None:
    def fails(*args: str) -> str:
        r = subprocess.run([str(cli), "export-fmu", *args], capture_output=True, text=True)
        assert r.returncode == 1 and r.stdout == "" and "panicked" not in r.stderr, r
        assert r.stderr.startswith("error: ") and r.stderr.count("\n") == 1, r.stderr
        return r.stderr

    spec = str(root / "examples" / "specs" / "paper.json")
    assert "nope.json" in fails("--model", "nope.json", "--output", str(tmp_path / "a.fmu"))
    assert "--name `1x`" in fails("--model", spec, "--output", str(tmp_path / "a.fmu"), "--name", "1x")
    assert "nope.so" in fails("--model", spec, "--output", str(tmp_path / "a.fmu"), "--library", str(tmp_path / "nope.so"))
    (tmp_path / "bad.json").write_text('{"type": "play", "r": -1}')
    assert "play.r" in fails("--model", str(tmp_path / "bad.json"), "--output", str(tmp_path / "a.fmu"))
    assert "same file" in fails("--model", spec, "--output", spec)
    assert not (tmp_path / "a.fmu").exists()

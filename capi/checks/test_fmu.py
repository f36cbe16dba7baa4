"""FMI 2.0 co-simulation FMUs from `hysteron export-fmu`, checked with an
independent FMI host, FMPy, beyond what test_fmus.py checks of both
versions: a spec that leaves its period to the host, serialized states
across instances, directional derivatives against central differences,
errors (tied parameters), independent instances, a wrong GUID, and export
errors."""

from __future__ import annotations

import json
import pathlib
import subprocess

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy.fmi2 import FMU2Slave  # noqa: E402
from fmpy.validation import validate_fmu  # noqa: E402

from fmus import H, Slave2, assert_refuses_bad_values_and_steps, assert_refuses_damaged_state_bytes, benchmark_input, cli_simulate, export, fmpy_simulate, signal  # noqa: E402


def test_a_spec_without_dt_takes_the_period_from_the_step(cli, root, tmp_path) -> None:
    """The benchmark's spec with its dt left out: an FMU of it runs at the
    host's step size, exactly as the spec with that dt written in."""
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


@pytest.fixture
def paper_fmu(cli, root, tmp_path) -> pathlib.Path:
    return export(cli, root / "examples" / "specs" / "paper.json", tmp_path / "paper.fmu")


def test_a_serialized_state_continues_bit_for_bit_in_a_fresh_instance(paper_fmu, capsys) -> None:
    s = Slave2(paper_fmu)
    x = signal(1500)
    s.run(x[:600])
    s.fmu.setReal([s.vr["left.mms.f_c"]], [2.0])  # a parameter changed on the way
    s.run(x[600:700])
    state = s.fmu.getFMUstate()
    data = s.fmu.serializeFMUstate(state)
    s.fmu.freeFMUstate(state)
    a = s.run(x[700:])
    fresh = Slave2(paper_fmu, "fresh")
    restored = fresh.fmu.deSerializeFMUstate(data)
    fresh.fmu.setFMUstate(restored)
    fresh.fmu.freeFMUstate(restored)
    fresh.t = s.t - (x.size - 700) * H
    assert fresh.fmu.getReal([fresh.vr["left.mms.f_c"]]) == [2.0]
    assert np.array_equal(fresh.run(x[700:]), a)
    assert_refuses_damaged_state_bytes(fresh, data, capsys)
    s.close()
    fresh.close()


def test_directional_derivatives_agree_with_central_differences_of_the_fmu(paper_fmu) -> None:
    s = Slave2(paper_fmu)
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


def test_errors_are_fmi2Error_with_a_message_and_leave_the_instance_usable(paper_fmu, capsys) -> None:
    s = Slave2(paper_fmu)
    x = signal(300)
    ok = s.run(x[:100])
    assert_refuses_bad_values_and_steps(s, capsys)
    with pytest.raises(Exception, match="fmi2SetReal"):
        s.fmu.setReal([s.vr["right.bouc_wen.z0"]], [0.3])  # tied to limits.r0
    assert "z0" in capsys.readouterr().out
    # Tied parameters move together in one call.
    s.fmu.setReal([s.vr["limits.r0"], s.vr["right.bouc_wen.z0"]], [0.05, -0.05])
    # Nothing else changed; the instance runs on.
    fresh = Slave2(paper_fmu, "fresh")
    fresh.fmu.setReal([fresh.vr["limits.r0"], fresh.vr["right.bouc_wen.z0"]], [0.05, -0.05])
    assert np.array_equal(s.run(x[100:]), fresh.run(x)[100:])
    assert not np.array_equal(ok, fresh.run(x[:100]))
    s.close()
    fresh.close()


def test_instances_are_independent(paper_fmu) -> None:
    a, b = Slave2(paper_fmu, "a"), Slave2(paper_fmu, "b")
    x = signal(600)
    alone = Slave2(paper_fmu, "alone").run(x)
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
    solo_paper = Slave2(paper_fmu, "solo paper").run(x)
    solo_pi = Slave2(pi_fmu, "solo pi").run(0.7 * x)
    paper, pi = Slave2(paper_fmu, "paper"), Slave2(pi_fmu, "pi")
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

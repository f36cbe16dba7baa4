"""What the checks of the FMI 2.0 and FMI 3.0 FMUs (test_fmus.py for
both, test_fmu.py and test_fmu3.py for each) use: exporting a spec with
`hysteron export-fmu`, running it with `hysteron simulate` and with FMPy,
and driving an instance by hand through FMPy's FMU2Slave or FMU3Slave (a
class per version, with the same methods), and the assertions on errors
that both versions' checks make.

FMPy applies the input of the table at the start of each step, and
`fmi2DoStep`/`fmi3DoStep` take the input set last as the sample at the end
of the step, so FMPy's output row k + 1 is the CLI's output row k (row 0 is
the initial output)."""

from __future__ import annotations

import csv
import pathlib
import subprocess

import fmpy
import numpy as np
import pytest
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave

H = 2.0**-10  # a step whose multiples are exact: FMPy's steps are then exactly H

# Value reference of the independent variable `time` of the FMI 3.0 FMU.
VR_TIME = 2147483647

# (spec in examples/specs, input amplitude) of the models every version
# reproduces bit for bit.
CASES = [
    ("paper.json", 1.4),  # the paper's model: friction in a gap, Bouc-Wen spring
    ("prandtl-ishlinskii.json", 1.0),  # a PI bank
    ("pi-inverse.json", 1.0),  # its analytic inverse
]


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


def benchmark_input(root: pathlib.Path, periods: int) -> tuple:
    with open(root / "data" / "boucwen-benchmark" / "val_multisine.csv") as f:
        rows = list(csv.DictReader(f))
    keys = list(rows[0])
    u = np.array([float(r[keys[1]]) for r in rows])
    y = np.array([float(r[keys[2]]) for r in rows])
    return np.tile(u, periods), y


class Slave:
    """An instance of an FMU driven by hand, one step per input sample.
    Its subclasses, one per FMI version, export FMUs of their version
    (`export`), drive FMPy's slave of it, and give the checks the version's
    functions under the same names: `get` and `set` (Real or Float64
    values), `get_state`, `set_state`, `free_state`, `serialize` and
    `deserialize` (FMU states)."""

    FMI = ""

    @classmethod
    def export(cls, cli: pathlib.Path, spec: pathlib.Path, out: pathlib.Path, *extra: str) -> pathlib.Path:
        """Exports `spec` as an FMU of the class's version."""
        return export(cli, spec, out, "--fmi", cls.FMI, *extra)

    def __init__(self, fmu: pathlib.Path, name: str = "inst") -> None:
        md = fmpy.read_model_description(str(fmu))
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.dir = fmpy.extract(str(fmu))
        self.fmu = self.slave(md, name)
        self.fmu.instantiate()
        self.start()

    def slave(self, md, name: str):
        raise NotImplementedError

    def start(self) -> None:
        raise NotImplementedError

    def do_step(self, h: float) -> None:
        raise NotImplementedError

    def step(self, x: float, h: float) -> float:
        """Sets the input, steps by h and returns the output."""
        self.set([self.vr["x"]], [float(x)])
        self.do_step(h)
        self.t += h
        return self.get([self.vr["y"]])[0]

    def run(self, xs, hs=None) -> np.ndarray:
        hs = [H] * len(xs) if hs is None else hs
        return np.array([self.step(x, h) for x, h in zip(xs, hs)])

    def close(self) -> None:
        self.fmu.terminate()
        self.fmu.freeInstance()

    def c_function(self, method) -> str:
        """The C function that FMPy's `method` calls, which the FMU's
        messages name: `setReal` → `fmi2SetReal`."""
        name = method.__name__
        return f"fmi{self.FMI}{name[0].upper()}{name[1:]}"


class Slave2(Slave):
    """An instance of an FMI 2.0 FMU, through FMPy's FMU2Slave."""

    FMI = "2"

    def slave(self, md, name: str):
        fmu = FMU2Slave(guid=md.guid, unzipDirectory=self.dir, modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
        self.get, self.set = fmu.getReal, fmu.setReal
        self.get_state, self.set_state, self.free_state = fmu.getFMUstate, fmu.setFMUstate, fmu.freeFMUstate
        self.serialize, self.deserialize = fmu.serializeFMUstate, fmu.deSerializeFMUstate
        return fmu

    def start(self) -> None:
        self.fmu.setupExperiment(startTime=0.0)
        self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()
        self.t = 0.0

    def do_step(self, h: float) -> None:
        self.fmu.doStep(currentCommunicationPoint=self.t, communicationStepSize=h)


class Slave3(Slave):
    """An instance of an FMI 3.0 FMU, through FMPy's FMU3Slave; it checks
    that every step ends where it was asked to (no events, no early
    return), and takes the time of a restored state from the FMU."""

    FMI = "3"

    def slave(self, md, name: str):
        fmu = FMU3Slave(guid=md.instantiationToken, unzipDirectory=self.dir, modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
        self.get, self.set = fmu.getFloat64, fmu.setFloat64
        self.get_state, self.free_state = fmu.getFMUState, fmu.freeFMUState
        self.serialize, self.deserialize = fmu.serializeFMUState, fmu.deserializeFMUState
        return fmu

    def start(self) -> None:
        self.fmu.enterInitializationMode(startTime=0.0)
        self.fmu.exitInitializationMode()
        self.t = 0.0

    def do_step(self, h: float) -> None:
        event, terminate, early, last = self.fmu.doStep(currentCommunicationPoint=self.t, communicationStepSize=h)
        assert (event, terminate, early, last) == (False, False, False, self.t + h)

    def set_state(self, state) -> None:
        self.fmu.setFMUState(state)
        self.t = self.fmu.getFloat64([VR_TIME])[0]


def assert_refuses_bad_values_and_steps(s: Slave, capsys) -> None:
    """A NaN input, a parameter outside its domain, a value for the output
    and a step of size 0 are each an error of the function called, with a
    logged message saying what is wrong (naming no function of the other
    version)."""
    capsys.readouterr()
    for name, value in [("x", float("nan")), ("left.mms.f_c", -1.0), ("y", 1.0)]:
        with pytest.raises(Exception, match=s.c_function(s.set)):
            s.set([s.vr[name]], [value])
    do_step = s.c_function(s.fmu.doStep)
    with pytest.raises(Exception, match=do_step):
        s.fmu.doStep(currentCommunicationPoint=s.t, communicationStepSize=0.0)
    log = capsys.readouterr().out
    for fragment in ["x: input NaN is not finite", "f_c", "y is an output", f"{do_step}: communicationStepSize must be positive"]:
        assert fragment in log, (fragment, log)
    other = "fmi3" if s.FMI == "2" else "fmi2"
    assert other not in log


def assert_refuses_damaged_state_bytes(s: Slave, data: bytes, capsys) -> None:
    """The bytes of a state `data` truncated, corrupted or without the
    format: each an error of the deserializing function with a logged
    message saying what is wrong; the instance `s` is unchanged."""
    capsys.readouterr()
    before = s.get([s.vr["y"]])
    flipped = data[:60] + bytes([data[60] ^ 1]) + data[61:]
    for bad, why in [(data[:-1], "CRC-32"), (data[:40], "truncated"), (flipped, "CRC-32"), (b"hysteron-state but not one", "the state has format version")]:
        with pytest.raises(Exception, match=s.c_function(s.deserialize)):
            s.deserialize(bad)
        assert why in capsys.readouterr().out
    assert s.get([s.vr["y"]]) == before

"""Many lives of the paper model's FMU in one process through FMPy, as a
parametric study in a Python host runs them: per cycle a new FMPy
FMU2Slave (FMI 2.0) or FMU3Slave (FMI 3.0) on the FMU extracted once
(which loads the binary), `instantiate`, initialization, 1000 steps (set
x, `doStep`, get y), `reset` and `freeInstance` (which FMPy follows by
unloading the binary). Every cycle must give the first cycle's outputs,
and resident memory (/proc/self/statm) must grow by less than 1 MB from
the end of cycle 100 to the end of the last.

The requirement is 10 000 cycles; through Python a cycle takes tens of
milliseconds (FMPy's ctypes calls), so the test runs
HYSTERON_SOAK_CYCLES cycles (default 1000) and the full count is run by
hand:

    HYSTERON_SOAK_CYCLES=10000 target/py-venv/bin/python -m pytest -q -s capi/checks/test_fmu_soak.py

Each run prints `<face>: <cycles> cycles of 1000 steps through FMPy, <ms>
ms per cycle, resident <kB> kB after 100 cycles, <kB> kB at the end,
growth <kB> kB` (the C soak's line, capi/checks/c/soak.c) and records the
figures as test properties."""

from __future__ import annotations

import math
import os
import pathlib
import subprocess
import time

import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy.fmi2 import FMU2Slave  # noqa: E402
from fmpy.fmi3 import FMU3Slave  # noqa: E402

STEPS = 1000
H = 1e-3
WARM_UP = 100  # cycles before the first memory reading
GROWTH_LIMIT_KB = 1024


def cycles() -> int:
    n = int(os.environ.get("HYSTERON_SOAK_CYCLES", "1000"))
    if n <= WARM_UP:
        pytest.fail(f"HYSTERON_SOAK_CYCLES must exceed {WARM_UP} (got {n})")
    return n


def resident_kb() -> int:
    with open("/proc/self/statm") as f:
        pages = int(f.read().split()[1])
    return pages * os.sysconf("SC_PAGE_SIZE") // 1024


def inputs() -> list:
    return [1.4 * math.sin(2 * math.pi * i / 400) for i in range(STEPS)]


class Face:
    """One FMI version's calls on an FMU2Slave or FMU3Slave."""

    def __init__(self, fmi: str, unzipped: str, md) -> None:
        self.fmi, self.unzipped, self.md = fmi, unzipped, md
        vr = {v.name: v.valueReference for v in md.modelVariables}
        self.x, self.y = [vr["x"]], [vr["y"]]

    def slave(self):
        """A new FMU2Slave or FMU3Slave: it loads the binary, and its
        `freeInstance` unloads it."""
        md = self.md
        if self.fmi == "2":
            return FMU2Slave(guid=md.guid, unzipDirectory=self.unzipped, modelIdentifier=md.coSimulation.modelIdentifier, instanceName="soak")
        return FMU3Slave(guid=md.instantiationToken, unzipDirectory=self.unzipped, modelIdentifier=md.coSimulation.modelIdentifier, instanceName="soak")

    def life(self, xs: list) -> float:
        """load, instantiate, initialize, the steps, reset, free (and
        unload): the sum of the outputs."""
        fmu, total, t = self.slave(), 0.0, 0.0
        fmu.instantiate()
        if self.fmi == "2":
            fmu.setupExperiment(startTime=0.0)
            fmu.enterInitializationMode()
            set_x, get_y = fmu.setReal, fmu.getReal
        else:
            fmu.enterInitializationMode(startTime=0.0)
            set_x, get_y = fmu.setFloat64, fmu.getFloat64
        fmu.exitInitializationMode()
        for x in xs:
            set_x(self.x, [x])
            fmu.doStep(currentCommunicationPoint=t, communicationStepSize=H)
            t += H
            total += get_y(self.y)[0]
        fmu.reset()
        fmu.freeInstance()
        return total


@pytest.mark.parametrize("fmi", ["2", "3"])
def test_many_lives_through_fmpy_keep_memory_flat(cli, root, tmp_path, fmi, record_property) -> None:
    n = cycles()
    fmu_path = tmp_path / "paper.fmu"
    subprocess.run(
        [str(cli), "export-fmu", "--model", str(root / "examples" / "specs" / "paper.json"), "--output", str(fmu_path), "--fmi", fmi],
        check=True,
        capture_output=True,
    )
    md = fmpy.read_model_description(str(fmu_path))
    unzipped = fmpy.extract(str(fmu_path), unzipdir=str(tmp_path / "unzipped"))
    face = Face(fmi, unzipped, md)
    xs = inputs()
    first = None
    after_warm_up = 0
    start = time.perf_counter()
    for k in range(n):
        total = face.life(xs)
        if first is None:
            first = total
        assert total == first, (k, total, first)  # every life is the same
        if k == WARM_UP - 1:
            after_warm_up = resident_kb()
    per_cycle = (time.perf_counter() - start) / n
    end = resident_kb()
    growth = end - after_warm_up
    line = (
        f"fmi{fmi} (FMPy {fmpy.__version__}): {n} cycles of {STEPS} steps through FMPy, "
        f"{per_cycle * 1e3:.2f} ms per cycle, resident {after_warm_up} kB after {WARM_UP} cycles, "
        f"{end} kB at the end, growth {growth} kB"
    )
    print(line)
    record_property("soak", line)
    assert after_warm_up > 0
    assert growth < GROWTH_LIMIT_KB, line

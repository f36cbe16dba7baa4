"""FMI 3.0 co-simulation FMUs from `hysteron export-fmu --fmi 3`, checked
with an independent FMI host, FMPy, beyond what test_fmus.py checks of both
versions: the 3.0 layout and every function of the standard, a variable
communication step against the FMI 2.0 FMU, serialized states across
instances, directional derivatives, errors, the functions the FMU does
not support, and vector parameters as array variables."""

from __future__ import annotations

import ctypes
import json
import pathlib
import re

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy.fmi3 import FMU3Slave, FMU3Model  # noqa: E402
from fmpy.validation import validate_fmu  # noqa: E402

from fmus import H, VR_TIME, Slave2, Slave3, assert_refuses_bad_values_and_steps, assert_refuses_damaged_state_bytes, cli_simulate, export, fmpy_simulate, signal  # noqa: E402


def test_the_fmu_is_fmi_3_with_the_3_0_layout(cli, root, tmp_path) -> None:
    fmu = Slave3.export(cli, root / "examples" / "specs" / "paper.json", tmp_path / "paper.fmu")
    md = fmpy.read_model_description(str(fmu))
    assert md.fmiVersion == "3.0"
    assert md.modelExchange is None and md.coSimulation is not None
    import xml.etree.ElementTree as ET
    import zipfile

    cs = ET.fromstring(zipfile.ZipFile(fmu).read("modelDescription.xml")).find("CoSimulation")
    for flag in ["canHandleVariableCommunicationStepSize", "canGetAndSetFMUState", "canSerializeFMUState", "providesDirectionalDerivatives"]:
        assert cs.get(flag) == "true", flag
    by_name = {v.name: v for v in md.modelVariables}
    assert [v.name for v in md.modelVariables if v.causality == "independent"] == ["time"]
    assert by_name["time"].valueReference == VR_TIME
    assert (by_name["x"].valueReference, by_name["y"].valueReference) == (0, 1)
    assert all(v.type == "Float64" for v in md.modelVariables)
    # The parameters and their start values are those of the FMI 2.0 FMU,
    # the Bouc-Wen stiffness's vectors z and s as arrays.
    md2 = fmpy.read_model_description(str(export(cli, root / "examples" / "specs" / "paper.json", tmp_path / "paper2.fmu")))
    assert [v.shape for v in md.modelVariables if v.name.endswith((".stiffness.z", ".stiffness.s"))] == [(6,), (6,)]
    assert elements(md) == elements(md2) and len(elements(md)) > 5
    assert md.instantiationToken == md2.guid
    assert sorted(zipfile.ZipFile(fmu).namelist()) == ["binaries/x86_64-linux/paper.so", "modelDescription.xml", "resources/model.json"]


def elements(md) -> dict:
    """Name → (value reference, start) of every parameter of the
    description `md`, an array's elements listed as FMI 2.0 names them
    (`w[k]`, at the array's value reference + k, with its k-th start)."""
    out = {}
    for v in md.modelVariables:
        if v.causality != "parameter":
            continue
        if not v.shape:
            out[v.name] = (v.valueReference, v.start)
            continue
        assert len(v.shape) == 1, v
        starts = v.start.split()
        assert len(starts) == v.shape[0], v
        out.update((f"{v.name}[{k}]", (v.valueReference + k, start)) for k, start in enumerate(starts))
    return out


def test_the_binary_exports_every_fmi3_function_of_the_standard(cli, root, tmp_path) -> None:
    """Every function type of the standard's fmi3FunctionTypes.h (as FMPy
    ships it) has its function in the binary."""
    header = pathlib.Path(fmpy.__file__).parent / "c-code" / "fmi3FunctionTypes.h"
    names = sorted(set(re.findall(r"\b(fmi3\w+)TYPE\b", header.read_text())))
    assert len(names) == 75, names
    fmu = Slave3.export(cli, root / "examples" / "specs" / "paper.json", tmp_path / "paper.fmu")
    lib = ctypes.CDLL(str(pathlib.Path(fmpy.extract(str(fmu))) / "binaries" / "x86_64-linux" / "paper.so"))
    missing = [n for n in names if not hasattr(lib, n)]
    assert missing == []


def varying_steps(n: int) -> list:
    """Step sizes that change at every few steps, over a factor of 5."""
    rng = np.random.default_rng(7)
    return list(1e-3 * rng.choice([0.5, 1.0, 1.3, 2.5], size=n))


@pytest.mark.parametrize("spec", ["paper.json", "boucwen-benchmark.json"])
def test_a_variable_communication_step_gives_the_fmi2_fmus_outputs_bit_for_bit(cli, root, tmp_path, spec) -> None:
    """Driven by hand with a varying step size, the FMI 3.0 FMU gives the
    FMI 2.0 FMU's outputs; for the rate-dependent benchmark they are the
    model stepped at those periods (checked for the 2.0 FMU in
    test_fmu.py and in the instance's tests), and differ from a constant
    step's."""
    path = root / "examples" / "specs" / spec
    fmu3 = Slave3.export(cli, path, tmp_path / "m3.fmu")
    fmu2 = export(cli, path, tmp_path / "m2.fmu")
    x = signal(2000, 1.4 if spec == "paper.json" else 0.5) * (1.0 if spec == "paper.json" else 40.0)
    hs = varying_steps(x.size)
    s3 = Slave3(fmu3)
    got = s3.run(x, hs)
    want = Slave2(fmu2, "fmi2").run(x, hs)
    assert np.array_equal(got, want)
    assert s3.fmu.getFloat64([VR_TIME]) == [s3.t]
    if spec == "boucwen-benchmark.json":
        assert not np.array_equal(got, Slave3(fmu3, "constant").run(x, [1e-3] * x.size))
    s3.close()


@pytest.fixture
def paper_fmu(cli, root, tmp_path) -> pathlib.Path:
    return Slave3.export(cli, root / "examples" / "specs" / "paper.json", tmp_path / "paper.fmu")


def test_a_serialized_state_continues_bit_for_bit_in_a_fresh_instance(paper_fmu, capsys) -> None:
    s = Slave3(paper_fmu)
    x = signal(1500)
    hs = varying_steps(x.size)
    s.run(x[:600], hs[:600])
    s.fmu.setFloat64([s.vr["left.mms.f_c"]], [2.0])  # a parameter changed on the way
    s.run(x[600:700], hs[600:700])
    state = s.fmu.getFMUState()
    data = s.fmu.serializeFMUState(state)
    s.fmu.freeFMUState(state)
    t_saved = s.t
    a = s.run(x[700:], hs[700:])
    fresh = Slave3(paper_fmu, "fresh")
    restored = fresh.fmu.deserializeFMUState(data)
    fresh.fmu.setFMUState(restored)
    fresh.fmu.freeFMUState(restored)
    assert fresh.fmu.getFloat64([VR_TIME]) == [t_saved]
    fresh.t = t_saved
    assert fresh.fmu.getFloat64([fresh.vr["left.mms.f_c"]]) == [2.0]
    assert np.array_equal(fresh.run(x[700:], hs[700:]), a)
    assert_refuses_damaged_state_bytes(fresh, data, capsys)
    s.close()
    fresh.close()


def test_directional_derivatives_are_the_fmi2_fmus(cli, root, paper_fmu, tmp_path) -> None:
    """The same exact derivatives as the FMI 2.0 FMU (which test_fmu.py
    checks against central differences), through FMI 3.0's seed and
    sensitivity arrays."""
    x = signal(900)
    s3 = Slave3(paper_fmu)
    s3.run(x)
    s2 = Slave2(export(cli, root / "examples" / "specs" / "paper.json", tmp_path / "paper2.fmu"), "fmi2")
    s2.run(x, [H] * x.size)
    y, xv, f_c = s3.vr["y"], s3.vr["x"], s3.vr["left.mms.f_c"]
    for knowns, seed in [([xv], [1.0]), ([f_c], [1.0]), ([xv, f_c], [2.0, -3.0])]:
        got = s3.fmu.getDirectionalDerivative([y], knowns, seed)
        want = s2.fmu.getDirectionalDerivative([y], knowns, seed)
        assert list(got) == list(want) and got[0] != 0.0, (knowns, got, want)
    with pytest.raises(Exception, match="fmi3GetDirectionalDerivative"):
        s3.fmu.getDirectionalDerivative([xv], [f_c], [1.0])
    s3.close()


def test_errors_are_fmi3Error_with_a_message_and_leave_the_instance_usable(paper_fmu, capsys) -> None:
    s = Slave3(paper_fmu)
    x = signal(300)
    s.run(x[:100])
    assert_refuses_bad_values_and_steps(s, capsys)
    with pytest.raises(Exception, match="fmi3SetFloat64"):
        s.fmu.setFloat64([VR_TIME], [1.0])
    with pytest.raises(Exception, match="fmi3GetFloat64"):
        s.fmu.getFloat64([s.vr["x"]], nValues=2)
    log = capsys.readouterr().out
    for fragment in ["time is the independent variable", "2 values for 1 value references"]:
        assert fragment in log, (fragment, log)
    # Nothing changed; the instance runs on as one that never erred.
    fresh = Slave3(paper_fmu, "fresh")
    assert np.array_equal(s.run(x[100:]), fresh.run(x)[100:])
    s.close()
    fresh.close()


def test_unsupported_calls_are_fmi3Error_with_a_message(paper_fmu, capsys) -> None:
    s = Slave3(paper_fmu)
    s.run(signal(10))
    capsys.readouterr()
    calls = {
        "fmi3EnterEventMode": lambda: s.fmu.enterEventMode(),
        "fmi3UpdateDiscreteStates": lambda: s.fmu.updateDiscreteStates(),
        "fmi3GetAdjointDerivative": lambda: s.fmu.getAdjointDerivative([s.vr["y"]], [s.vr["x"]], [1.0]),
        "fmi3GetOutputDerivatives": lambda: s.fmu.getOutputDerivatives([s.vr["y"]], [1]),
        "fmi3EnterConfigurationMode": lambda: s.fmu.enterConfigurationMode(),
        "fmi3GetInt32": lambda: s.fmu.getInt32([s.vr["y"]]),
        "fmi3SetBoolean": lambda: s.fmu.setBoolean([0], [True]),
        "fmi3GetClock": lambda: s.fmu.getClock([0]),
        # FMPy's wrapper of this one passes a type for the count: called directly.
        "fmi3GetNumberOfVariableDependencies": lambda: s.fmu.fmi3GetNumberOfVariableDependencies(s.fmu.component, s.vr["y"], ctypes.byref(ctypes.c_size_t())),
        "fmi3SetTime": lambda: s.fmu.fmi3SetTime(s.fmu.component, 1.0),
    }
    for name, call in calls.items():
        with pytest.raises(Exception, match=name):
            call()
        log = capsys.readouterr().out
        assert "[ERROR]" in log and ("not supported" in log or "has no" in log), (name, log)
    # Getters and setters of the types the FMU has none of, with no value
    # references: nothing to do.
    assert list(s.fmu.getInt32([])) == []
    s.fmu.setString([], [])
    # Still usable; Step Mode again is accepted and changes nothing.
    s.fmu.enterStepMode()
    s.run(signal(10))
    s.close()


def test_model_exchange_event_mode_and_a_wrong_token_are_refused(paper_fmu, capsys) -> None:
    md = fmpy.read_model_description(str(paper_fmu))
    unzip = fmpy.extract(str(paper_fmu))
    ident = md.coSimulation.modelIdentifier
    capsys.readouterr()
    me = FMU3Model(guid=md.instantiationToken, unzipDirectory=unzip, modelIdentifier=ident, instanceName="me")
    with pytest.raises(Exception, match="Failed to instantiate"):
        me.instantiate()
    assert "Model Exchange is not supported" in capsys.readouterr().out
    bad = FMU3Slave(guid="{00000000-0000-0000-0000-000000000000}", unzipDirectory=unzip, modelIdentifier=ident, instanceName="bad")
    with pytest.raises(Exception, match="Failed to instantiate"):
        bad.instantiate()
    assert "does not match" in capsys.readouterr().out
    events = FMU3Slave(guid=md.instantiationToken, unzipDirectory=unzip, modelIdentifier=ident, instanceName="events")
    with pytest.raises(Exception, match="Failed to instantiate"):
        events.instantiate(eventModeUsed=True)
    assert "hasEventMode is false" in capsys.readouterr().out


# Models with vector parameters, one of their vectors, and other values for
# it: a PI bank's weights, a Maxwell-slip model's element stiffnesses.
ARRAYS = [
    ("prandtl-ishlinskii.json", "w", [1.2, 0.5, 0.45, 0.25, 0.2, 0.1, 0.12, 0.02]),
    ("maxwell-slip.json", "k", [20.0, 12.5, 5.0, 4.5, 2.0, 1.25]),
]


@pytest.mark.parametrize("spec, name, values", ARRAYS)
def test_vector_parameters_are_array_variables_that_validate(cli, root, tmp_path, spec, name, values) -> None:
    path = root / "examples" / "specs" / spec
    fmu = Slave3.export(cli, path, tmp_path / "model.fmu")
    assert validate_fmu(str(fmu)) == []
    md = fmpy.read_model_description(str(fmu))
    md2 = fmpy.read_model_description(str(export(cli, path, tmp_path / "model2.fmu")))
    by_name = {v.name: v for v in md.modelVariables}
    assert by_name[name].shape == (len(values),)
    assert not any("[" in v.name for v in md.modelVariables)
    # The elements are the FMI 2.0 FMU's parameters, under their value
    # references and with their start values.
    assert elements(md) == elements(md2)


@pytest.mark.parametrize("spec, name, values", ARRAYS)
def test_changed_array_start_values_give_the_cli_outputs_of_the_spec_with_them(cli, root, tmp_path, spec, name, values) -> None:
    path = root / "examples" / "specs" / spec
    fmu = Slave3.export(cli, path, tmp_path / "model.fmu")
    changed = json.loads(path.read_text())
    changed[name] = values
    changed_path = tmp_path / "changed.json"
    changed_path.write_text(json.dumps(changed))
    x = signal(3000, 1.0)
    want = cli_simulate(cli, changed_path, x, tmp_path)
    got = fmpy_simulate(fmu, x, 1e-3, {name: values})
    assert np.max(np.abs(got - want)) <= 1e-12 * np.max(np.abs(want)), np.max(np.abs(got - want))
    # The start values changed the outputs.
    assert np.max(np.abs(fmpy_simulate(fmu, x, 1e-3) - want)) > 1e-3 * np.max(np.abs(want))


@pytest.fixture
def pi_fmu(cli, root, tmp_path) -> pathlib.Path:
    return Slave3.export(cli, root / "examples" / "specs" / "prandtl-ishlinskii.json", tmp_path / "pi.fmu")


def test_an_array_round_trips_through_set_and_get_float64(cli, root, pi_fmu, tmp_path) -> None:
    """fmi3SetFloat64 and fmi3GetFloat64 take an array's values after one
    another (nValues the sum of the variables' sizes), and an array set
    between steps acts as the same change in the spec."""
    s = Slave3(pi_fmu)
    md = fmpy.read_model_description(str(pi_fmu))
    w, a0, y, xv = s.vr["w"], s.vr["a0"], s.vr["y"], s.vr["x"]
    start = [float(v) for v in next(v for v in md.modelVariables if v.name == "w").start.split()]
    assert s.get([w], 8) == start
    new = ARRAYS[0][2]
    s.set([w], new)
    assert s.get([w], 8) == new
    # Scalars and arrays in one call, in the order of their value references
    # as given.
    assert s.get([a0, w, y], 10) == [s.get([a0])[0], *new, s.get([y])[0]]
    s.set([xv, w, a0], [0.25, *start, 0.3])
    assert s.get([w, xv, a0], 10) == [*start, 0.25, 0.3]
    s.close()
    # Between steps: the outputs go on as those of the spec with the new
    # weights.
    spec = json.loads((root / "examples" / "specs" / "prandtl-ishlinskii.json").read_text())
    spec["w"] = new
    changed = tmp_path / "changed.json"
    changed.write_text(json.dumps(spec))
    x = signal(1200, 1.0)
    want = cli_simulate(cli, changed, x, tmp_path)
    s = Slave3(pi_fmu, "between steps")
    assert not np.array_equal(s.run(x[:500]), want[:500])
    s.set([w], new)
    assert np.array_equal(s.run(x[500:]), want[500:])
    s.close()


def test_a_wrong_count_of_values_or_an_unknown_reference_is_fmi3Error_with_a_message(pi_fmu, capsys) -> None:
    s = Slave3(pi_fmu)
    x = signal(300, 1.0)
    s.run(x[:100])
    w, y = s.vr["w"], s.vr["y"]
    capsys.readouterr()
    refused = [
        ("fmi3SetFloat64", lambda: s.set([w], [1.0] * 7), "7 values for 1 value references holding 8"),
        ("fmi3SetFloat64", lambda: s.set([w, y], [1.0] * 8), "8 values for 2 value references holding 9"),
        ("fmi3GetFloat64", lambda: s.get([w]), "1 values for 1 value references holding 8"),
        ("fmi3GetFloat64", lambda: s.get([w], 9), "9 values for 1 value references holding 8"),
        ("fmi3GetFloat64", lambda: s.get([w + 1]), f"value reference {w + 1} is an element of the array w"),
        ("fmi3SetFloat64", lambda: s.set([w + 7], [1.0]), f"value reference {w + 7} is an element of the array w"),
        ("fmi3GetFloat64", lambda: s.get([12345], 1), "no Float64 variable with value reference 12345"),
        ("fmi3GetDirectionalDerivative", lambda: s.fmu.getDirectionalDerivative([y], [w], [1.0]), "knowns and seed: 1 values for 1 value references holding 8"),
        # NULL values with values to write or read.
        ("fmi3GetFloat64", lambda: s.fmu.fmi3GetFloat64(s.fmu.component, (ctypes.c_uint * 1)(w), 1, None, 8), "valueReferences or values: NULL"),
        ("fmi3SetFloat64", lambda: s.fmu.fmi3SetFloat64(s.fmu.component, (ctypes.c_uint * 1)(w), 1, None, 8), "valueReferences or values: NULL"),
    ]
    for function, call, message in refused:
        with pytest.raises(Exception, match=function):
            call()
        log = capsys.readouterr().out
        assert "[ERROR]" in log and message in log, (function, message, log)
    # Nothing changed; the instance runs on as one that never erred.
    fresh = Slave3(pi_fmu, "fresh")
    assert np.array_equal(s.run(x[100:]), fresh.run(x)[100:])
    s.close()
    fresh.close()


def test_directional_derivatives_of_an_array_are_the_fmi2_fmus_over_its_elements(cli, root, pi_fmu, tmp_path) -> None:
    """A seed of an array's size for its value reference gives the FMI 2.0
    FMU's directional derivative for its elements' value references with
    that seed."""
    x = signal(900, 1.0)
    s3 = Slave3(pi_fmu)
    s3.run(x)
    s2 = Slave2(export(cli, root / "examples" / "specs" / "prandtl-ishlinskii.json", tmp_path / "pi2.fmu"), "fmi2")
    s2.run(x)
    y, xv, w, r = s3.vr["y"], s3.vr["x"], s3.vr["w"], s3.vr["r"]
    seed_w = list(np.linspace(-1.0, 2.0, 8))
    seed_r = list(np.linspace(0.5, -0.5, 8))
    for knowns, seed, flat in [
        ([w], seed_w, [w + k for k in range(8)]),
        ([xv, w, r], [0.5, *seed_w, *seed_r], [xv, *(w + k for k in range(8)), *(r + k for k in range(8))]),
    ]:
        got = s3.fmu.getDirectionalDerivative([y], knowns, seed)
        want = s2.fmu.getDirectionalDerivative([s2.vr["y"]], flat, seed)
        assert list(got) == list(want) and got[0] != 0.0, (knowns, got, want)
    s3.close()

"""Every error class, and no Rust panic reaching Python on bad input."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

import hysteron_rs as hy


def test_the_hierarchy() -> None:
    for cls in [hy.SpecError, hy.ParameterError, hy.InputError, hy.SolverError, hy.AnalysisError, hy.FitError]:
        assert issubclass(cls, hy.HysteronError)
    assert issubclass(hy.HysteronError, ValueError)


@pytest.mark.parametrize(
    "bad, message",
    [
        (np.array([0.0, 1.0, np.nan]), "at sample 2: input sample NaN is not finite"),
        (np.array([0.0, np.inf]), "at sample 1: input sample inf is not finite"),
        (np.array([-np.inf]), "at sample 0"),
        (np.zeros((2, 3)), "x: must be 1-D, got shape (2, 3)"),
        (np.zeros(0), "x: is empty"),
        ([], "x: is empty"),
        (np.array(["a", "b"]), "x: cannot be read as an array of float64"),
        ("abc", "x: cannot be read as an array of float64"),
        ([[1.0], [2.0, 3.0]], "x: cannot be read as an array of float64"),
        (np.array([1 + 2j]), "x: cannot be read as an array of float64"),
        (None, "x: cannot be read as an array of float64: its dtype is object"),
        (3.0, "x: must be 1-D, got shape ()"),
    ],
)
def test_bad_inputs_are_input_errors(bad, message) -> None:
    model = hy.paper_model()
    with pytest.raises(hy.InputError) as err:
        model.run(bad)
    assert message in str(err.value)


def test_sample_index_attribute_and_state_kept() -> None:
    model = hy.play(0.5)
    with pytest.raises(hy.InputError) as err:
        model.run([1.0, 2.0, np.nan, 3.0])
    assert err.value.sample == 2
    # The state is that after sample 1 (y = 1.5).
    assert model.step(1.5) == 1.5


def test_other_dtypes_and_layouts_are_converted() -> None:
    model = hy.gain(2.0)
    assert list(model.run(np.arange(3))) == [0.0, 2.0, 4.0]
    assert list(model.run(np.arange(3, dtype=np.float32))) == [0.0, 2.0, 4.0]
    strided = np.arange(10.0)[::3]
    assert list(model.run(strided)) == [0.0, 6.0, 12.0, 18.0]
    fortran = np.asfortranarray(np.arange(4.0))
    assert list(model.run(fortran)) == [0.0, 2.0, 4.0, 6.0]
    assert list(model.run((1.0, 2.0))) == [2.0, 4.0]


def test_step_and_trial_reject_non_finite() -> None:
    model = hy.mms(1.0, 5.0)
    for call in (model.step, model.trial):
        with pytest.raises(hy.InputError, match="not finite"):
            call(float("nan"))
    with pytest.raises(TypeError):
        model.step("x")  # type: ignore[arg-type]


def test_spec_errors_name_the_path() -> None:
    with pytest.raises(hy.SpecError, match=r"^play: missing field `r`"):
        hy.Model.from_spec({"type": "play"})
    with pytest.raises(hy.SpecError, match="unknown"):
        hy.Model.from_spec({"type": "nope"})
    with pytest.raises(hy.SpecError):
        hy.Model.from_spec("{not json")
    with pytest.raises(hy.SpecError, match="cannot be written as JSON"):
        hy.Model.from_spec({"type": "play", "r": object()})
    with pytest.raises(hy.ParameterError, match=r"^scaled\.inner\.play\.r: must be ≥ 0 \(got -1\)"):
        hy.Model.from_spec({"type": "scaled", "w": 2, "inner": {"type": "play", "r": -1}})
    with pytest.raises(hy.ParameterError, match="w"):
        hy.bouc_wen(w=2.0, alpha=1.0, beta=0.5, gamma=0.5, n=1.0, stiffness={"z": [0.0], "s": [1.0]})
    with pytest.raises(hy.ParameterError, match=r"^r: must be finite \(got NaN\)"):
        hy.play(float("nan"))
    with pytest.raises(hy.ParameterError, match=r"^stiffness\.s\[1\]: must be finite \(got inf\)"):
        hy.bouc_wen(0.5, 1.0, 0.5, 0.5, 1.0, stiffness={"z": [0.0, 1.0], "s": [1.0, 1e309]})
    deep: dict = {"type": "gain", "k": 1.0}
    for _ in range(300):
        deep = {"type": "scaled", "w": 1.0, "inner": deep}
    with pytest.raises(hy.SpecError, match="nested deeper than"):
        hy.Model.from_spec(deep)


def test_combinators_refuse_chains_deeper_than_max_depth() -> None:
    # 120 nodes on one path build and run; the 121st is a ParameterError
    # naming the nesting, not a stack overflow (nor a model that cannot
    # be read back from its spec).
    model = hy.gain(1.0)
    for _ in range(119):
        model = model.then(hy.gain(1.0))
    assert list(model.run([0.25])) == [0.25]
    assert hy.Model.from_spec(model.to_spec()).run([0.5])[0] == 0.5
    with pytest.raises(hy.ParameterError, match=r"nesting: .*at most 120 operators"):
        model.then(hy.gain(1.0))


def test_solver_errors() -> None:
    # A saturation's outputs end at 1: its inverse cannot reach 2.
    inverse = hy.saturation(-1.0, 1.0).inverse()
    with pytest.raises(hy.SolverError) as err:
        inverse.run([0.5, 2.0])
    assert err.value.sample == 1


def test_analysis_errors() -> None:
    with pytest.raises(hy.AnalysisError, match="amplitude"):
        hy.describing_function(hy.play(0.5), -1.0)
    with pytest.raises(hy.AnalysisError, match="not periodic"):
        hy.loop_energy(hy.viscous_damper(1.0, 0.01).plus(hy.mass_spring_damper(1.0, 0.0, 1.0, 0.37)), 1.0, settle_periods=2)


def test_batch_errors_name_the_record() -> None:
    with pytest.raises(hy.InputError) as err:
        hy.run_batch(hy.play(0.1), [[1.0, 2.0], [0.0, np.nan]])
    assert "record 1" in str(err.value) and err.value.index == 1 and err.value.sample == 1
    with pytest.raises(hy.InputError, match="record 0: is empty"):
        hy.run_batch(hy.play(0.1), [[]])
    with pytest.raises(hy.InputError, match="threads"):
        hy.run_batch(hy.play(0.1), [[1.0]], threads=0)
    with pytest.raises(hy.ParameterError, match="must be ≥ 0"):
        hy.run_parameter_sets(hy.play(0.1), [{"r": -1.0}], [1.0])


def test_errors_pickle_as_the_package_classes() -> None:
    # Their module is hysteron_rs, so multiprocessing and Dask hand them
    # back as the same classes, with their attributes.
    with pytest.raises(hy.InputError) as err:
        hy.gain(1.0).run([0.0, np.nan])
    back = pickle.loads(pickle.dumps(err.value))
    assert type(back) is hy.InputError and isinstance(back, hy.HysteronError)
    assert str(back) == str(err.value) and back.sample == 1
    for cls in (hy.HysteronError, hy.SpecError, hy.ParameterError, hy.InputError, hy.SolverError, hy.AnalysisError, hy.FitError):
        assert cls.__module__ == "hysteron_rs"
        assert type(pickle.loads(pickle.dumps(cls("m")))) is cls


def test_strided_and_converted_arrays_read_as_their_values() -> None:
    base = np.sin(np.linspace(0.0, 30.0, 90_001))
    for view in (base[::2], base[::-1], base[10::3], base.astype(np.float32), (base * 100).astype(np.int64)):
        want = hy.paper_model().run(np.ascontiguousarray(view, dtype=np.float64))
        assert np.array_equal(hy.paper_model().run(view), want)


@pytest.mark.parametrize("stride", [1, 3])
def test_an_error_past_the_first_chunk_names_its_sample_in_the_whole_run(stride: int) -> None:
    # run() works in chunks of 32768 samples; the index is the run's own.
    x = np.repeat(np.sin(np.linspace(0.0, 40.0, 100_000)), stride)
    x[70_001 * stride] = np.nan
    view = x[::stride]
    model = hy.paper_model()
    with pytest.raises(hy.InputError) as err:
        model.run(view)
    assert err.value.sample == 70_001 and "at sample 70001" in str(err.value)
    # Every sample before it was committed: the next sample continues from
    # sample 70000's state.
    fresh = hy.paper_model()
    want = fresh.run(np.append(view[:70_001], 0.25))[-1]
    assert model.run([0.25])[0] == want

"""Models from specs and constructors, composition, runs, parameters."""

from __future__ import annotations

import copy
import csv
import json
import pickle
import subprocess

import numpy as np
import pytest

import hysteron_rs as hy


def test_every_registered_leaf_has_a_constructor_with_its_equation() -> None:
    kinds = hy.leaf_kinds()
    assert len(kinds) >= 18
    for entry in kinds:
        make = getattr(hy, entry["type"])
        assert entry["type"] in hy.__all__
        assert entry["equation"] in make.__doc__
        model = make(**entry["example"])
        assert model.name == entry["type"]
        assert model.to_spec()["type"] == entry["type"]
        # The constructor builds what the spec builds.
        assert model == hy.Model.from_spec(dict(entry["example"], type=entry["type"]))


def test_positional_arguments_follow_the_declaration() -> None:
    assert hy.play(0.5).params == {"r": 0.5, "y0": 0.0}
    assert hy.play(0.5, 0.25).params == {"r": 0.5, "y0": 0.25}
    assert hy.dead_zone(-1.0, 1.0).params == hy.dead_zone(b_l=-1.0, b_r=1.0).params
    with pytest.raises(TypeError, match="unexpected keyword argument 'q'"):
        hy.play(0.5, q=1)
    with pytest.raises(TypeError, match="at most 2 positional"):
        hy.play(0.5, 0.0, 1.0)


def test_composition_matches_the_spec_and_the_closed_form() -> None:
    model = hy.play(0.5).then(hy.dead_zone(-1.0, 1.0))
    spec = model.to_spec()
    assert spec["type"] == "cascade"
    assert spec["first"]["type"] == "play" and spec["second"]["type"] == "dead_zone"
    # play -> 2.5, dead zone -> 1.5; back to 0: play holds 2.5 until x < 2.
    assert list(model.run([3.0, 2.0, 0.0])) == [1.5, 1.5, 0.0]
    springs = hy.gain(2.0).series(hy.gain(3.0))
    assert abs(springs.run([1.0])[0] - 1.2) < 1e-14  # k1 k2 / (k1 + k2)
    assert hy.gain(2.0).plus(hy.gain(3.0)).run([1.0])[0] == 5.0
    assert hy.gain(2.0).scaled(4.0).run([1.0])[0] == 8.0
    inv = hy.gain(4.0).inverse()
    assert abs(inv.run([2.0])[0] - 0.5) < 1e-9
    fb = hy.gain(1.0).feedback(hy.gain(1.0))  # y = x - y
    assert abs(fb.run([2.0])[0] - 1.0) < 1e-9
    gap = hy.mms(1.0, 30.0).series(hy.gain(10.0), limits={"type": "gap", "b": 0.2, "r0": 0.0})
    assert gap.to_spec()["limits"] == {"type": "gap", "b": 0.2, "r0": 0.0}
    with pytest.raises(hy.SpecError):
        hy.gain(1.0).series(hy.gain(1.0), limits={"type": "wall"})


def test_spec_round_trips_as_dict_and_json(root) -> None:
    for path in sorted((root / "examples" / "specs").glob("*.json")):
        text = path.read_text()
        model = hy.Model.from_spec(text)
        assert hy.Model.from_spec(model.to_spec()) == model, path.name
        assert hy.Model(json.loads(model.to_json())) == model, path.name


def test_step_trial_commit_reset_agree_with_run() -> None:
    x = np.sin(np.linspace(0.0, 12.0, 400)) * 2.0
    model = hy.paper_model()
    want = model.run(x)
    model.reset()
    stepped = np.array([model.step(v) for v in x])
    assert np.array_equal(stepped, want)
    model.reset()
    for v in x[:10]:
        model.trial(v + 5.0)  # never committed
        model.trial(v)
        model.commit()
    assert np.array_equal(model.run(x[10:]), want[10:])


def test_params_round_trip_and_with_params() -> None:
    model = hy.paper_model()
    params = model.params
    assert list(params) == model.param_names
    assert hy.Model.from_spec(model.to_spec()).params == params
    changed = model.with_params({"left.mms.f_c": 2.5}, k=40.0)
    assert changed.params["left.mms.f_c"] == 2.5
    assert changed.params["left.mms.k"] == 40.0
    assert model.params == params  # the original is unchanged
    assert changed.with_params(model.params) == model
    with pytest.raises(hy.ParameterError, match="unknown parameter `nope`"):
        model.with_params(nope=1.0)
    with pytest.raises(hy.ParameterError, match="`r` is ambiguous: left.play.r, right.play.r"):
        hy.play(0.5).plus(hy.play(0.2)).with_params(r=0.1)
    with pytest.raises(hy.ParameterError, match="must be ≥ 0"):
        hy.play(0.5).with_params(r=-1.0)
    assert model.tied_params == ["limits.r0", "right.bouc_wen.z0"]


def test_copies_are_independent_and_pickle_through_the_spec() -> None:
    x = np.linspace(0.0, 2.0, 50)
    model = hy.mms(1.0, 20.0)
    model.run(x)
    twin = copy.deepcopy(model)  # keeps the state
    assert np.array_equal(twin.run(-x), model.run(-x))
    twin.reset()
    assert not np.array_equal(twin.run(x), model.run(x))  # different states now
    again = pickle.loads(pickle.dumps(model))
    assert again == model
    fresh = hy.mms(1.0, 20.0)
    assert np.array_equal(again.run(x), fresh.run(x))  # from the initial state
    shallow = copy.copy(model)
    shallow.run(x)
    assert shallow is not model


def _simulate_cli(cli, tmp_path, spec_path, x):
    inp = tmp_path / "in.csv"
    out = tmp_path / "out.csv"
    with inp.open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["x"])
        for v in x:
            w.writerow([repr(float(v))])
    subprocess.run(
        [str(cli), "simulate", "--model", str(spec_path), "--input", str(inp), "--column", "x", "--output", str(out)],
        check=True,
        capture_output=True,
    )
    with out.open() as f:
        rows = list(csv.DictReader(f))
    return np.array([float(r["y"]) for r in rows])


@pytest.mark.parametrize(
    "name",
    ["paper.json", "play-deadzone.json", "prandtl-ishlinskii.json", "maxwell-slip.json", "preisach.json", "dahl.json", "pi-inverse.json", "friction-spring-feedback.json"],
)
def test_bit_identical_to_the_cli(cli, root, tmp_path, name) -> None:
    spec_path = root / "examples" / "specs" / name
    rng = np.random.default_rng(3)
    t = np.linspace(0.0, 1.0, 3000)
    x = 1.2 * np.sin(2 * np.pi * 3 * t) * (1 - 0.6 * t) + 0.05 * rng.standard_normal(t.size)
    model = hy.Model.from_spec(spec_path.read_text())
    try:
        want = _simulate_cli(cli, tmp_path, spec_path, x)
    except subprocess.CalledProcessError as e:  # the model rejects this input: so must Python
        with pytest.raises(hy.HysteronError):
            model.run(x)
        assert e.returncode == 1
        return
    got = model.run(x)
    assert got.tobytes() == want.tobytes(), name

"""`hy.compare`: candidate structures fitted on training records, scored on
held-out ones and ranked, on records of a known structure (MMS friction)
with noise; the same ranking as `hysteron compare` on the same files."""

from __future__ import annotations

import csv
import json
import pathlib
import subprocess
from typing import List, Tuple

import numpy as np
import pytest

import hysteron_rs as hy

Records = List[Tuple[np.ndarray, np.ndarray]]


def records(seed: int = 7) -> Tuple[Records, Records]:
    rng = np.random.default_rng(seed)
    truth = hy.mms(f_c=1.5, k=20.0)

    def one(a: float, cycles: float) -> Tuple[np.ndarray, np.ndarray]:
        x = a * np.sin(2.0 * np.pi * cycles * np.arange(1500) / 1500.0)
        truth.reset()
        return x, truth.run(x) + rng.normal(0.0, 0.03, x.size)

    train = [one(1.0, 2.0), one(0.3, 3.0)]
    held = [one(a, c) for a, c in [(0.5, 2.0), (0.8, 1.0), (0.2, 4.0), (1.2, 2.0), (0.6, 3.0), (0.4, 1.0)]]
    return train, held


def candidates() -> list:
    return [
        {"name": "elastoplastic", "model": hy.elastoplastic(k=10.0, f_b=1.0), "free": ["k", "f_b"]},
        {
            "name": "mms-spring",
            "model": hy.mms(f_c=1.0, k=10.0).plus(hy.gain(0.1)),
            "free": ["f_c", "left.mms.k", "right.gain.k"],
        },
        {"name": "mms", "model": hy.mms(f_c=1.0, k=10.0), "free": ["f_c", "k"]},
    ]


def test_the_true_structure_wins_by_bic_and_the_richer_one_gains_nothing_real() -> None:
    train, held = records()
    rows = hy.compare(candidates(), train, held)
    by = {r["candidate"]: r for r in rows}
    assert [r["rank"] for r in rows] == [1, 2, 3]
    assert by["mms"]["bic"] < by["mms-spring"]["bic"] < by["elastoplastic"]["bic"]
    assert by["elastoplastic"]["rank"] == 3
    assert rows[0]["candidate"].startswith("mms") and rows[0]["p_vs_next"] > 0.05
    assert rows[1]["p_vs_next"] == pytest.approx(2.0 / 64.0)
    assert by["mms"]["k"] == 2 and by["mms"]["n"] == 3000
    assert len(by["mms"]["heldout_nrmse"]) == 6
    assert by["mms"]["heldout_nrmse_mean"] == pytest.approx(np.mean(by["mms"]["heldout_nrmse"]))
    fitted = by["mms"]["model"]
    assert fitted.params["f_c"] == pytest.approx(1.5, abs=0.02)
    assert all(r["error"] is None for r in rows)


def test_cross_validation_scores_every_record_from_the_fit_without_it() -> None:
    train, held = records()
    rows = hy.compare(candidates(), train + held, cross_validate=4)
    by = {r["candidate"]: r for r in rows}
    assert [r["rank"] for r in rows] == [1, 2, 3]
    assert by["elastoplastic"]["rank"] == 3
    assert rows[1]["p_vs_next"] == pytest.approx(2.0 / 256.0)
    assert all(len(r["heldout_nrmse"]) == 8 for r in rows)
    # the training figures come from the fit on all eight records
    assert by["mms"]["n"] == 12000


def test_bad_requests_are_typed_errors_naming_the_field() -> None:
    train, held = records()
    with pytest.raises(hy.ParameterError, match=r"candidates\[1\]: missing `free`"):
        hy.compare([candidates()[0], {"name": "b", "model": hy.gain(1.0)}], train, held)
    with pytest.raises(hy.ParameterError, match="at least two"):
        hy.compare(candidates()[:1], train, held)
    with pytest.raises(hy.ParameterError, match="used twice"):
        hy.compare([candidates()[2], candidates()[2]], train, held)
    with pytest.raises(hy.ParameterError, match=r"candidates\[0\]\.free: a list of names"):
        hy.compare([{**candidates()[0], "free": "k"}, candidates()[2]], train, held)
    with pytest.raises(hy.InputError, match="lowpass needs the sample period"):
        hy.compare(candidates(), train, held, lowpass=5.0)
    with pytest.raises(hy.FitError, match="at most the 2 training records"):
        hy.compare(candidates(), train, cross_validate=3)
    with pytest.raises(hy.FitError, match="no held-out record"):
        hy.compare(candidates(), train)
    with pytest.raises(hy.InputError, match=r"validate\[0\]\.y"):
        hy.compare(candidates(), train, [(held[0][0], np.full(1500, np.nan))])


def test_a_candidate_that_cannot_run_keeps_its_row() -> None:
    train, held = records()
    rows = hy.compare([{**candidates()[0], "free": ["nope"]}, candidates()[2]], train, held)
    assert rows[0]["candidate"] == "mms" and rows[0]["rank"] == 1
    assert rows[1]["rank"] is None and "nope" in rows[1]["error"]
    assert rows[1]["model"] is None


def test_a_failed_fit_keeps_its_row() -> None:
    train, held = records()
    # a hardening spring whose state blows up within the records' travel
    spring = hy.bouc_wen(w=0.0, alpha=1.0, beta=-5.0, gamma=-5.0, n=2.0, stiffness=1.0)
    bad = {"name": "diverges", "model": spring, "free": ["alpha"]}
    rows = hy.compare([candidates()[2], bad], train, held)
    by = {r["candidate"]: r for r in rows}
    assert by["mms"]["rank"] == 1
    assert by["diverges"]["rank"] is None and by["diverges"]["error"].startswith("fit")
    assert rows[-1]["candidate"] == "diverges"


def test_the_same_ranking_as_the_command_line(
    tmp_path: pathlib.Path, cli: pathlib.Path
) -> None:
    train, held = records()
    names = []
    for i, (x, y) in enumerate(train + held):
        path = tmp_path / f"r{i}.csv"
        np.savetxt(path, np.column_stack([x, y]), delimiter=",", header="x,F", comments="")
        names.append(path.name)
    specs = []
    for c in candidates():
        (tmp_path / f"{c['name']}.json").write_text(c["model"].to_json(), encoding="utf-8")
        specs.append({"name": c["name"], "model": f"{c['name']}.json", "free": c["free"]})
    (tmp_path / "c.json").write_text(json.dumps({"candidates": specs}), encoding="utf-8")
    args = [str(cli), "compare", "--candidates", "c.json", "--work-dir", "fitted", "--csv", "t.csv"]
    for n in names[:2]:
        args += ["--train", n]
    for n in names[2:]:
        args += ["--validate", n]
    subprocess.run(args, cwd=tmp_path, check=True, capture_output=True)
    with open(tmp_path / "t.csv", newline="") as f:
        table = list(csv.DictReader(f))
    rows = hy.compare(candidates(), train, held)
    assert [r["candidate"] for r in rows] == [t["candidate"] for t in table]
    for r, t in zip(rows, table):
        # the CSV's shortest round-trip numbers of the same computation
        assert r["heldout_nrmse_mean"] == pytest.approx(float(t["heldout_nrmse_mean"]), rel=1e-9)
        assert r["bic"] == pytest.approx(float(t["bic"]), rel=1e-9)

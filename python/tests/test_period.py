"""The sample period of rate-dependent models: given by the spec, by
``dt=`` or by ``time=``, never silently, and stated in every result."""

from __future__ import annotations

import numpy as np
import pytest

import hysteron_rs as hy

LUGRE = dict(sigma0=1000.0, sigma1=5.0, sigma2=0.2, f_c=1.0, f_s=1.5, v_s=0.5)


def drive(n: int = 3000, dt: float = 1e-3) -> tuple[np.ndarray, np.ndarray]:
    t = np.arange(n) * dt
    return t, 0.05 * np.sin(2 * np.pi * t) + 0.02 * np.sin(2 * np.pi * 3.3 * t)


def test_a_constructor_may_leave_dt_to_the_data() -> None:
    t, x = drive()
    pending = hy.lugre(**LUGRE)
    assert pending.dt is None
    assert "dt" not in pending.to_spec()
    # never run at a stand-in period: every run says what is missing
    for call in (lambda: pending.run(x), lambda: pending.step(0.1), lambda: pending.trial(0.1)):
        with pytest.raises(hy.SpecError, match=r"^lugre\.dt: the sample period is not given"):
            call()
    expected = hy.lugre(**LUGRE, dt=1e-3).run(x)
    by_dt = hy.lugre(**LUGRE)
    assert np.array_equal(by_dt.run(x, dt=1e-3), expected)
    assert by_dt.dt == 1e-3
    by_time = hy.lugre(**LUGRE)
    assert np.array_equal(by_time.run(x, time=t), expected)
    assert by_time.dt == pytest.approx(1e-3, rel=1e-12)
    # a rate-independent model ignores both
    play = hy.play(0.1)
    assert np.array_equal(play.run(x, dt=5.0), hy.play(0.1).run(x))
    assert play.dt is None


def test_bad_periods_name_the_argument_and_sample() -> None:
    t, x = drive(100)
    model = hy.lugre(**LUGRE)
    with pytest.raises(hy.ParameterError, match="^dt: .*positive and finite"):
        model.run(x, dt=-1.0)
    with pytest.raises(hy.ParameterError, match="not both"):
        model.run(x, dt=1e-3, time=t)
    with pytest.raises(hy.InputError, match="^time: has 99 stamps, but the input has 100"):
        model.run(x, time=t[:-1])
    bent = t.copy()
    bent[50] += 5e-4
    with pytest.raises(hy.InputError, match=r"^time\[50\]: the step"):
        model.run(x, time=bent)
    with pytest.raises(hy.InputError, match=r"^time\[1\]: time does not increase"):
        model.run(x, time=t[::-1].copy())
    assert model.dt is None  # nothing was run


def test_a_fit_states_its_period_and_takes_it_from_time() -> None:
    t, x = drive()
    y = hy.lugre(**LUGRE, dt=1e-3).run(x)
    start = dict(LUGRE, f_c=2.0)
    # the spec's period is used and stated
    r = hy.fit(hy.lugre(**start, dt=1e-3), x, y, ["f_c"])
    assert r.dt == 1e-3 and "sample period: 0.001 s" in str(r)
    assert abs(r.values["f_c"] - 1.0) < 1e-6
    # a spec without dt: from time=, or refused
    r = hy.fit(hy.lugre(**start), x, y, ["f_c"], time=t)
    assert r.dt == pytest.approx(1e-3, rel=1e-12)
    assert abs(r.values["f_c"] - 1.0) < 1e-6
    assert r.model.dt == pytest.approx(1e-3, rel=1e-12)
    with pytest.raises(hy.SpecError, match="sample period is not given"):
        hy.fit(hy.lugre(**start), x, y, ["f_c"])
    # dt= overrides a wrong spec period (0.5 s on 1 ms data)
    r = hy.fit(hy.lugre(**start, dt=0.5), x, y, ["f_c"], dt=1e-3)
    assert r.dt == 1e-3 and abs(r.values["f_c"] - 1.0) < 1e-6
    # several records share one period
    r = hy.fit_records(hy.lugre(**start), [(x, y)], ["f_c"], dt=1e-3)
    assert r.dt == 1e-3
    # a rate-independent model has none
    assert hy.fit(hy.gain(1.0), x, 2 * x, ["k"]).dt is None


def test_other_runners_refuse_a_missing_period() -> None:
    _, x = drive(50)
    pending = hy.viscous_damper(2.0)
    with pytest.raises(hy.SpecError, match="viscous_damper.dt"):
        hy.run_batch(pending, [x])
    with pytest.raises(hy.SpecError, match="viscous_damper.dt"):
        hy.run_parameter_sets(pending, [{"c": 1.0}], x)
    with pytest.raises(hy.SpecError, match="viscous_damper.dt"):
        hy.describing_function(pending, 0.5)
    with pytest.raises(hy.SpecError, match="viscous_damper.dt"):
        hy.sensitivity(pending, x, ["c"])
    # with_dt gives it
    assert hy.run_batch(pending.with_dt(0.01), [x])[0].shape == x.shape


def test_constructors_raise_type_error_for_missing_arguments() -> None:
    with pytest.raises(TypeError, match=r"^play\(\) missing 1 required argument: 'r'$"):
        hy.play()  # type: ignore[call-arg]
    with pytest.raises(TypeError, match=r"lugre\(\) missing 2 required arguments: 'f_s' and 'v_s'"):
        hy.lugre(sigma0=1.0, sigma1=0.0, sigma2=0.0, f_c=1.0)  # type: ignore[call-arg]
    # the period is not required: it may come from the data
    hy.mass_spring_damper(1.0, 0.5, 100.0)


def test_docstrings_are_plain_text() -> None:
    doc = hy.lugre.__doc__ or ""
    assert doc.count("Not a fitted parameter.") == 1, doc
    assert "](" not in doc and "[`" not in doc, doc
    assert "SamplePeriod::set_sample_period" in doc


def test_a_constant_stiffness_is_a_number() -> None:
    _, x = drive(200)
    kw = dict(w=0.4, alpha=1.0, beta=3.0, gamma=1.0, n=1.0)
    number = hy.bouc_wen(**kw, stiffness=5.0)
    knots = hy.bouc_wen(**kw, stiffness={"z": [0.0], "s": [5.0]})
    assert number == knots
    assert np.array_equal(number.run(x), knots.run(x))


def test_spec_errors_name_the_root_by_its_type() -> None:
    with pytest.raises(hy.SpecError, match=r"^play: missing field `r`"):
        hy.Model.from_spec({"type": "play"})
    with pytest.raises(hy.SpecError, match=r"^spec: "):
        hy.Model.from_spec("[1, 2]")

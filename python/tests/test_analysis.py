"""describing_function and loop_energy against closed forms."""

from __future__ import annotations

import math

import hysteron_rs as hy


def test_play_describing_function_closed_form() -> None:
    r, a = 0.5, 2.0
    rho = r / a
    s = 1 - 2 * rho
    re = (math.pi / 2 + math.asin(s) + s * math.sqrt(1 - s * s)) / math.pi
    im = -4 / math.pi * rho * (1 - rho)
    n = hy.describing_function(hy.play(r), a, samples_per_period=4096)
    assert abs(n.re - re) < 1e-4 and abs(n.im - im) < 1e-4
    assert abs(n.gain - math.hypot(re, im)) < 1e-4
    assert len(n.harmonics) == 6


def test_stop_loop_energy_closed_form() -> None:
    r, a = 0.25, 1.0
    e = hy.loop_energy(hy.stop(r), a)
    assert abs(e.work - 4 * r * (a - r)) < 1e-5  # clockwise parallelogram
    p = hy.loop_energy(hy.play(r), a)
    assert p.work < 0 and abs(p.area - 4 * r * (a - r)) < 1e-5  # counterclockwise

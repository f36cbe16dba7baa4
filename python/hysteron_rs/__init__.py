"""hysteron_rs: hysteresis operators and their algebra, from numpy.

Build a model from a spec (a dict or JSON text, as the ``hysteron`` CLI
reads it) or from constructors and combinator methods, run it on float64
arrays, and fit its parameters to records::

    import numpy as np
    import hysteron_rs as hy

    model = hy.play(0.5).then(hy.dead_zone(-1.0, 1.0))
    y = model.run(np.sin(np.linspace(0, 20, 2000)))
    same = hy.Model.from_spec(model.to_spec())

Every leaf operator of the Rust registry has a constructor of the same
name (``play``, ``bouc_wen``, ``maxwell_slip``, ...), whose docstring gives
its equation and parameters. Errors are subclasses of ``HysteronError``
(a ``ValueError``) carrying the library's messages.

The distribution is ``hysteron-rs`` (the PyPI name ``hysteron`` belongs to
an unrelated package); the import name is ``hysteron_rs``.
"""

from __future__ import annotations

from ._native import (
    AnalysisError,
    Band,
    DescribingFunction,
    Ensemble,
    FitError,
    FitResult,
    HysteronError,
    InputError,
    LoopEnergy,
    Model,
    ParameterError,
    SolverError,
    SpecError,
    __version__,
    compare,
    describing_function,
    fit,
    fit_records,
    leaf_kinds,
    loop_energy,
    paper_model,
    run_batch,
    run_parameter_sets,
    sensitivity,
)
# BEGIN generated: constructors (scripts/generate.sh)
from ._operators import (
    asymmetric_friction,
    backlash_contact,
    bouc_wen,
    bouc_wen_degrading,
    bouc_wen_degrading_energy,
    bwbn,
    bwbn_energy,
    dahl,
    dead_zone,
    duhem,
    elastoplastic,
    envelope,
    envelope_inverse,
    gain,
    gms,
    jiles_atherton,
    krasnoselskii_pokrovskii,
    lugre,
    mass_spring_damper,
    maxwell_slip,
    mms,
    offset,
    pi_bank,
    pi_inverse,
    play,
    preisach,
    rate_dependent_pi,
    relay,
    saturation,
    stop,
    transient_friction,
    viscous_damper,
)
# END generated: constructors

__all__ = [
    "AnalysisError",
    "Band",
    "DescribingFunction",
    "Ensemble",
    "FitError",
    "FitResult",
    "HysteronError",
    "InputError",
    "LoopEnergy",
    "Model",
    "ParameterError",
    "SolverError",
    "SpecError",
    "__version__",
    "compare",
    "describing_function",
    "fit",
    "fit_records",
    "leaf_kinds",
    "loop_energy",
    "paper_model",
    "run_batch",
    "run_parameter_sets",
    "sensitivity",
]
__all__ += [
    # BEGIN generated: constructor names (scripts/generate.sh)
    "asymmetric_friction",
    "backlash_contact",
    "bouc_wen",
    "bouc_wen_degrading",
    "bouc_wen_degrading_energy",
    "bwbn",
    "bwbn_energy",
    "dahl",
    "dead_zone",
    "duhem",
    "elastoplastic",
    "envelope",
    "envelope_inverse",
    "gain",
    "gms",
    "jiles_atherton",
    "krasnoselskii_pokrovskii",
    "lugre",
    "mass_spring_damper",
    "maxwell_slip",
    "mms",
    "offset",
    "pi_bank",
    "pi_inverse",
    "play",
    "preisach",
    "rate_dependent_pi",
    "relay",
    "saturation",
    "stop",
    "transient_friction",
    "viscous_damper",
    # END generated: constructor names
]

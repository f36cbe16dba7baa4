"""One constructor per leaf operator of the Rust registry.

The constructors are made at import from ``leaf_kinds()``, the registry's
own declaration of every leaf (its ``type``, equation and fields), so a
leaf added in Rust gets its Python constructor with no Python change.
Arguments follow the declaration order; a field with a default in the
spec may be left out (``None`` means "the spec's default"), and so may
the sample period ``dt`` of a rate-dependent operator, which then comes
from the data (``run(x, dt=...)``, ``fit(..., time=...)``). A required
argument left out is a ``TypeError``, as for any Python function.
"""

from __future__ import annotations

import inspect
from typing import Any, Callable, Dict, List

from ._native import Model, leaf, leaf_kinds

__all__: List[str] = []


def _make(entry: Dict[str, Any]) -> Callable[..., Model]:
    kind: str = entry["type"]
    fields: List[Dict[str, Any]] = entry["fields"]
    names = [f["name"] for f in fields]

    def construct(*args: Any, **kwargs: Any) -> Model:
        if len(args) > positional:
            raise TypeError(
                f"{kind}() takes at most {positional} positional arguments "
                f"({len(args)} given)"
            )
        params: Dict[str, Any] = {}
        for name, value in zip(names, args):
            params[name] = value
        for name, value in kwargs.items():
            if name not in names:
                raise TypeError(
                    f"{kind}() got an unexpected keyword argument {name!r} "
                    f"(its fields: {', '.join(names)})"
                )
            if name in params:
                raise TypeError(f"{kind}() got multiple values for argument {name!r}")
            params[name] = value
        missing = [n for n in required if params.get(n) is None]
        if missing:
            listed = " and ".join(repr(n) for n in missing)
            raise TypeError(
                f"{kind}() missing {len(missing)} required argument"
                f"{'s' if len(missing) > 1 else ''}: {listed}"
            )
        return leaf(kind, {k: v for k, v in params.items() if v is not None})

    # Required fields after an optional one can only be given by keyword.
    parameters = []
    seen_optional = keyword_only = False
    for f in fields:
        keyword_only = keyword_only or (f["required"] and seen_optional)
        seen_optional = seen_optional or not f["required"]
        parameters.append(
            inspect.Parameter(
                f["name"],
                inspect.Parameter.KEYWORD_ONLY
                if keyword_only
                else inspect.Parameter.POSITIONAL_OR_KEYWORD,
                default=inspect.Parameter.empty if f["required"] else None,
            )
        )
    positional = sum(
        p.kind is inspect.Parameter.POSITIONAL_OR_KEYWORD for p in parameters
    )
    required = [f["name"] for f in fields if f["required"]]
    construct.__signature__ = inspect.Signature(parameters)  # type: ignore[attr-defined]
    construct.__name__ = kind
    construct.__qualname__ = kind
    construct.__module__ = "hysteron_rs"
    construct.__doc__ = entry["doc"]
    return construct


for _entry in leaf_kinds():
    globals()[_entry["type"]] = _make(_entry)
    __all__.append(_entry["type"])
del _entry

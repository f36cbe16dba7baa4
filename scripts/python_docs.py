"""Writes the Python documentation that the compiled module already knows.

* ``python/hysteron_rs/_native.pyi``: every class, method, property and
  function of the stubs gets the docstring of the compiled object it
  describes (the Rust doc comment PyO3 attaches), so that an IDE shows on
  hover what ``help()`` shows.
* ``docs/python-api.md``: the guide's API page, from the same stubs
  (signatures) and docstrings, plus the constructors of the registry's
  operators and ``hysteron_rs.dask``.

Run it with the package installed (``bash scripts/test.sh`` makes
``target/py-venv``)::

    target/py-venv/bin/python scripts/python_docs.py          # write both
    target/py-venv/bin/python scripts/python_docs.py --check  # fail if stale

``python/tests/test_docs.py`` runs the check.
"""

from __future__ import annotations

import argparse
import ast
import inspect
import pathlib
import sys
import textwrap
from typing import Any, List, Optional, Tuple

import hysteron_rs
import hysteron_rs._native as native
import hysteron_rs.dask as hdask

ROOT = pathlib.Path(__file__).resolve().parents[1]
STUBS = ROOT / "python" / "hysteron_rs" / "_native.pyi"
PAGE = ROOT / "docs" / "python-api.md"


def doc_of(obj: Any) -> Optional[str]:
    doc = getattr(obj, "__doc__", None)
    if not doc or doc.startswith("Create and return a new object."):
        return None  # none of its own (Python's generic `__new__` text)
    return inspect.cleandoc(doc)


def runtime(path: List[str]) -> Any:
    obj: Any = native
    for name in path:
        obj = inspect.getattr_static(obj, name, None) if inspect.isclass(obj) else getattr(obj, name, None)
        if obj is None:
            return None
    return obj


def docstring_lines(doc: str, indent: str) -> List[str]:
    body = doc.replace("\\", "\\\\").replace('"""', '\\"\\"\\"')
    lines = body.split("\n")
    if len(lines) == 1:
        return [f'{indent}"""{lines[0]}"""']
    return [f'{indent}"""{lines[0]}'] + [f"{indent}{l}" if l else "" for l in lines[1:]] + [f'{indent}"""']


def with_docstrings(source: str) -> str:
    """The stubs with each node's docstring set from the compiled module
    (an existing docstring replaced, a `...` body replaced)."""
    tree = ast.parse(source)
    lines = source.split("\n")
    edits: List[Tuple[int, int, List[str]]] = []  # (first, last) 0-based, inclusive

    def visit(body: List[ast.stmt], path: List[str]) -> None:
        for node in body:
            if not isinstance(node, (ast.FunctionDef, ast.ClassDef)):
                continue
            if node.name.startswith("__") and node.name != "__new__":
                continue
            obj = runtime(path + [node.name])
            if isinstance(obj, (property, staticmethod, classmethod)):
                obj = obj.fget if isinstance(obj, property) else obj.__func__
            doc = doc_of(obj)
            if isinstance(node, ast.ClassDef) and doc == doc_of(object):
                doc = None
            if isinstance(node, ast.ClassDef) and path == [] and issubclass(
                getattr(native, node.name, object), BaseException
            ):
                doc = doc_of(getattr(native, node.name))
            first = node.body[0]
            has_doc = isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant) and isinstance(first.value.value, str)
            header_end = first.lineno - 1  # 0-based line of the first body statement
            if doc is not None:
                indent = " " * (node.col_offset + 4)
                if has_doc:
                    edits.append((first.lineno - 1, first.end_lineno - 1, docstring_lines(doc, indent)))  # type: ignore[operator]
                elif len(node.body) == 1 and isinstance(first, ast.Expr) and first.value.__class__ is ast.Constant and first.value.value is Ellipsis:
                    line = lines[header_end]
                    if line.rstrip().endswith(": ..."):
                        head = line.rstrip()[: -len(" ...")]
                        edits.append((header_end, header_end, [head] + docstring_lines(doc, indent)))
                    else:  # `...` on its own line
                        edits.append((header_end, header_end, docstring_lines(doc, indent)))
                else:
                    edits.append((header_end, header_end - 1, docstring_lines(doc, indent)))
            if isinstance(node, ast.ClassDef):
                visit(node.body, path + [node.name])

    visit(tree.body, [])
    for first, last, new in sorted(edits, key=lambda e: e[0], reverse=True):
        lines[first : last + 1] = new
    return "\n".join(lines)


def signature(node: ast.FunctionDef) -> str:
    args = ast.unparse(node.args)
    ret = f" -> {ast.unparse(node.returns)}" if node.returns else ""
    return f"{node.name}({args}){ret}"


def page() -> str:
    tree = ast.parse(STUBS.read_text(encoding="utf-8"))
    out = [
        "# Python API",
        "",
        "The package `hysteron_rs` (distribution `hysteron-rs`, installed with",
        "`pip install ./python`). This page is generated from the package's stubs",
        "and docstrings by `scripts/python_docs.py`; `help()` shows the same text.",
        "The [Python chapter](python.md) shows them at work.",
        "",
        "## Operators",
        "",
        "One constructor per registered operator, with the operator's parameters as",
        "keyword arguments; each returns a `Model`. Its docstring gives the equation",
        "and every parameter with its domain and default, as its reference page does.",
        "",
        "| constructor | reference |",
        "|---|---|",
    ]
    for name in hysteron_rs._operators.__all__:
        out.append(f"| `hysteron_rs.{name}(...)` | [{name}](reference/{name}.md) |")
    classes = [n for n in tree.body if isinstance(n, ast.ClassDef)]
    functions = [n for n in tree.body if isinstance(n, ast.FunctionDef)]
    errors = [c for c in classes if c.bases and not c.name == "Model" and issubclass(getattr(native, c.name), BaseException)]
    for cls in classes:
        if cls in errors:
            continue
        out += ["", f"## `{cls.name}`", ""]
        doc = doc_of(getattr(native, cls.name))
        if doc:
            out += [doc, ""]
        for node in cls.body:
            if not isinstance(node, ast.FunctionDef) or node.name.startswith("__"):
                continue
            is_property = any(isinstance(d, ast.Name) and d.id == "property" for d in node.decorator_list)
            obj = runtime([cls.name, node.name])
            if isinstance(obj, property):
                obj = obj.fget
            elif isinstance(obj, (staticmethod, classmethod)):
                obj = obj.__func__
            title = f"`{cls.name}.{node.name}`" + (" (property)" if is_property else f": `{signature(node)}`")
            out += [f"### {title}", ""]
            d = doc_of(obj)
            out += [d if d else "(no documentation)", ""]
        if out[-1] == "":
            out.pop()
    out += ["", "## Functions", ""]
    for node in functions:
        if node.name.startswith("_"):
            continue
        out += [f"### `{node.name}`", "", "```text", f"{signature(node)}", "```", ""]
        d = doc_of(getattr(native, node.name, None))
        out += [d if d else "(no documentation)", ""]
    out += ["## Errors", "", "| exception | raised for |", "|---|---|"]
    for cls in errors:
        d = (doc_of(getattr(native, cls.name)) or "").split("\n\n")[0].replace("\n", " ")
        out.append(f"| `{cls.name}` | {d} |")
    out += ["", "## `hysteron_rs.dask`", ""]
    for name in ("map_records",):
        fn = getattr(hdask, name)
        out += [f"### `{name}`", "", "```text", f"{name}{inspect.signature(fn)}", "```", "", doc_of(fn) or "", ""]
    return "\n".join(out).rstrip() + "\n"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true", help="fail if a file differs from what would be written")
    args = parser.parse_args()
    stubs_now = STUBS.read_text(encoding="utf-8")
    # the page reads the stubs' signatures, which the docstrings leave as
    # they are
    wanted = {STUBS: with_docstrings(stubs_now), PAGE: page()}
    stale = []
    for path, text in wanted.items():
        old = path.read_text(encoding="utf-8") if path.exists() else ""
        if old != text:
            if args.check:
                stale.append(str(path.relative_to(ROOT)))
            else:
                path.write_text(text, encoding="utf-8")
    if stale:
        print(f"stale: {stale}; run: python scripts/python_docs.py", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())

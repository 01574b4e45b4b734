"""What the Python API's results share: a record of a command's JSON (fields by attribute or key)
and tables that become pandas DataFrames (pandas is optional: ``pip install pandas``)."""

from __future__ import annotations

import json
from typing import Any, Mapping, Sequence

PANDAS_HINT = "to_pandas() needs pandas, an optional dependency of vlab: pip install pandas"


def pandas():
    """The pandas module, or an ImportError that says how to install it."""
    try:
        import pandas as pd
    except ImportError:
        raise ImportError(PANDAS_HINT) from None
    return pd


def frame(columns: Mapping[str, Sequence] | None = None, rows: Sequence[Sequence] | None = None,
          headers: Sequence[str] | None = None):
    """A DataFrame from named columns, or from ``rows`` under ``headers`` (one row per run/model)."""
    pd = pandas()
    if columns is not None:
        return pd.DataFrame({k: list(v) for k, v in columns.items()})
    return pd.DataFrame([list(r) for r in rows], columns=list(headers))


def as_json(data: Any) -> Any:
    """``data`` as the command's JSON file holds it (json.dumps with default=str, read back): the
    fields and values a reader of sweep.json or cost.json sees, nothing Python-only."""
    return json.loads(json.dumps(data, default=str))


class Record:
    """A command's JSON record: ``record.data`` (the dict), each top-level field as an attribute
    (``record.converged``) or a key (``record["converged"]``), ``record.fields``."""

    _what = "record"

    def __init__(self, data: dict):
        self.data = data

    def __getattr__(self, name: str):
        if name.startswith("_") or name == "data":
            raise AttributeError(name)
        try:
            return self.data[name]
        except KeyError:
            raise AttributeError(f"{type(self).__name__} has no field {name!r}; the fields are "
                                 f"{', '.join(self.data)}") from None

    def __getitem__(self, name: str):
        return self.data[name]

    def __dir__(self):
        return sorted(set(super().__dir__()) | {k for k in self.data if k.isidentifier()})

    @property
    def fields(self) -> tuple[str, ...]:
        return tuple(self.data)

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self._what}: {', '.join(self.data)})"


def loaded_scene(scene) -> tuple[Any, str | None, str]:
    """(parsed scene, its file text or None, its name in the records) of a path or a vlab.Scene;
    the records name a file as the command line does (``str(path)``)."""
    from vlab.scene import load_scene_text

    if hasattr(scene, "parsed"):  # a vlab.Scene
        return scene.parsed, getattr(scene, "_text", None), str(scene.origin)
    parsed, text = load_scene_text(scene)
    return parsed, text, str(scene)

"""Runs one Gmsh job in a process of its own: ``python -m vlab.geometry.gmsh_worker`` reads a
pickled (module, function, args) from stdin and writes the pickled ("ok", result) or
("error", field, message) to stdout (see vlab.geometry.cad.in_own_process for why)."""

from __future__ import annotations

import importlib
import pickle
import sys


def main() -> None:
    module, name, args = pickle.load(sys.stdin.buffer)
    out = sys.stdout.buffer
    sys.stdout = sys.stderr  # anything printed by the job stays off the result channel
    try:
        result = ("ok", getattr(importlib.import_module(module), name)(*args))
    except Exception as exc:  # sent back and raised in the caller, with the field it names
        result = ("error", getattr(exc, "field", "specimen.file"), str(exc))
    pickle.dump(result, out)
    out.flush()


if __name__ == "__main__":
    main()

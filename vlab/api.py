"""vlab from Python: build a scene, run the test, read the curve and the constants, write the
report when you want one. The same code as the command line (``vlab run``), without the terminal.

>>> import vlab
>>> scene = vlab.Scene.from_dict({
...     "name": "api-block",
...     "specimen": {"shape": "block", "size": [10.0, 10.0, 10.0]},
...     "mesh": {"size": 5.0, "cell": "hex"},
...     "material": {"model": "neo-hookean", "E": 10.0, "nu": 0.3},
...     "test": {"kind": "uniaxial", "grips": "roller", "stretch": 1.2, "steps": 4},
... })
>>> result = scene.run()
>>> result.converged
True
>>> round(result.E, 1), round(result.nu, 3)        # MPa, 1: fitted like a lab (ISO 527-1 window)
(10.0, 0.3)
>>> strain, stress = result.curve["strain"], result.curve["stress"]   # numpy arrays
>>> bool(stress[-1] > stress[0] > 0)
True
>>> sorted(result.constants)[:3]
['E', 'E_crosshead', 'nu']

A scene file, one key changed (dotted names, as ``vlab sweep --set``), a biaxial test's y axis:

>>> sheet = vlab.Scene.from_file("specimens/sheet-equibiaxial.toml").with_values({"test.steps": 2})
>>> biaxial = sheet.run()
>>> biaxial.curve.axes
('x', 'y')
>>> bool(abs(biaxial.curve.y["stress"][-1] - biaxial.curve["stress"][-1]) < 1e-6)   # equibiaxial
True

``result.write_report("reports/api-block")`` writes the same folder as ``vlab run``; in Jupyter a
result shows as a table (``_repr_html_``).
"""

from __future__ import annotations

import html
from pathlib import Path
from typing import Any, Mapping

import numpy as np

#: curve columns of the load axis x, as results.json names them (units: mm/mm, MPa, N, s)
AXIS_COLUMNS = ("stretch", "strain", "stress", "force", "true_strain", "true_stress")
SHARED_COLUMNS = ("crosshead_strain", "transverse_strain", "thickness_strain", "time")


class Curve(Mapping):
    """The recorded curve as numpy arrays by name (one entry per load level, unloaded state not
    included): ``curve["strain"]`` (extensometer, engineering), ``"stress"`` (force / A0, MPa),
    ``"force"`` (N), ``"transverse_strain"``, ``"thickness_strain"``, ``"true_strain"``,
    ``"true_stress"``, ``"stretch"`` (grip), ``"time"`` (s, timed tests) — along x; ``curve.y``
    holds a biaxial test's y axis under the same names. A kind's own columns keep their
    results.json names (simple shear: ``"shear"``, ``"shear_stress"`` (MPa), ``"normal_force"`` (N),
    …; a cruciform: ``"centre_stress_x"``, …)."""

    def __init__(self, columns: dict, axis: str = "x"):
        self._raw, self.axis = columns, axis
        sfx = "" if axis == "x" else f"_{axis}"
        self._columns = {name: np.asarray(columns[name + sfx], dtype=float)
                         for name in AXIS_COLUMNS if name + sfx in columns}
        self._columns |= {name: np.asarray(columns[name], dtype=float) for name in SHARED_COLUMNS
                          if columns.get(name) is not None}
        if axis == "x":  # the kind's own columns by their results.json names (a shear test's shear,
            # shear_stress, normal_force, …; a cruciform's centre_stress_x, …), never the y axis'
            y_names = {name + "_y" for name in AXIS_COLUMNS}
            self._columns |= {name: np.asarray(values, dtype=float) for name, values in columns.items()
                              if isinstance(values, list) and name not in y_names and name not in self._columns}
        self.units = columns.get("units", {})

    def __getitem__(self, name: str) -> np.ndarray:
        try:
            return self._columns[name]
        except KeyError:
            raise KeyError(f"no curve column {name!r}; the columns are {', '.join(self._columns)}") from None

    def __iter__(self):
        return iter(self._columns)

    def __len__(self) -> int:
        return len(self._columns)

    def to_pandas(self):
        """The columns as a pandas DataFrame, one row per load level (pandas: ``pip install pandas``)."""
        from vlab.api_tables import frame

        return frame(self._columns)

    @property
    def levels(self) -> int:
        """The number of recorded load levels."""
        return len(next(iter(self._columns.values()), []))

    @property
    def axes(self) -> tuple[str, ...]:
        return ("x", "y") if "strain_y" in self._raw else ("x",)

    @property
    def y(self) -> "Curve":
        if "y" not in self.axes:
            raise AttributeError("a uniaxial test has no y axis")
        return Curve(self._raw, "y")

    def __repr__(self) -> str:
        return f"Curve(axis {self.axis!r}: {', '.join(self._columns)}; {self.levels} levels)"


class Result:
    """One test's outcome: ``converged``, ``E`` (MPa), ``nu``, ``constants`` (every measured
    constant: E, ν, the crosshead modulus, a cruciform's nominal E and ν, noise intervals),
    ``curve`` (numpy arrays), ``data`` (the results.json dict) and ``write_report(folder)``."""

    def __init__(self, run_result, data: dict, scene_text: str | None):
        self._run, self.data, self._text = run_result, data, scene_text

    @property
    def converged(self) -> bool:
        return bool(self.data["converged"])

    @property
    def failure(self) -> dict | None:
        return self.data.get("failure")

    @property
    def E(self) -> float | None:
        return self.data["measured"]["E"]

    @property
    def nu(self) -> float | None:
        return self.data["measured"]["nu"]

    @property
    def curve(self) -> Curve:
        return Curve(self.data["curve"])

    @property
    def constants(self) -> dict[str, float]:
        m, out = self.data["measured"], {}
        for key in ("E", "nu", "E_crosshead"):
            if m.get(key) is not None:
                out[key] = float(m[key])
        cruciform = self.data.get("cruciform") or {}
        for key in ("E_nominal", "nu_nominal"):
            if cruciform.get(key) is not None:
                out[key] = float(cruciform[key])
        for key, interval in (m.get("uncertainty") or {}).items():
            if isinstance(interval, dict) and "low" in interval:
                out[f"{key}_low"], out[f"{key}_high"] = float(interval["low"]), float(interval["high"])
        return out

    def write_report(self, folder: str | Path, render: bool = True) -> Path:
        """The report folder ``vlab run`` writes (results.json, curve.csv, PNGs, 3-D view, HTML);
        returns its index.html."""
        from vlab.report.writer import ReportOptions, write_run

        if self._run is None:
            raise ValueError("this result is one model of a comparison: write the comparison's report "
                             "(vlab.compare(...).write_report(folder))")
        folder = Path(folder)
        write_run(self._run, folder, self._text, ReportOptions(render=render))
        return folder / "index.html"

    def _rows(self) -> list[tuple[str, str]]:
        from vlab.report.html import summary_rows

        return summary_rows(self.data)

    def _repr_html_(self) -> str:
        status = "completed" if self.converged else f"stopped: {html.escape(str(self.failure.get('reason')))}"
        rows = "".join(f"<tr><th style='text-align:left'>{html.escape(k)}</th><td style='text-align:left'>{v}</td></tr>"
                       for k, v in self._rows())
        return (f"<b>{html.escape(self.data['scene']['name'])}</b>: {status}"
                f"<table>{rows}</table>")

    def __repr__(self) -> str:
        state = "completed" if self.converged else "stopped"
        E, nu = self.E, self.nu
        fitted = f"E = {E:.6g} MPa, nu = {nu:.6g}" if E is not None else "E, nu not measured"
        return f"Result({self.data['scene']['name']!r}: {state}, {fitted}, {self.curve.levels} levels)"


class Scene:
    """A validated scene (the TOML file's content): ``Scene.from_file(path)``, ``Scene.from_dict(d)``,
    ``scene.with_values({"mesh.size": 2.0})``, ``scene.run()``. Invalid input raises
    ``vlab.SceneError`` naming the field and its allowed range."""

    def __init__(self, raw: dict, base_dir: str | Path | None = None, origin: str = "<dict>",
                 text: str | None = None):
        from vlab.scene import parse_scene

        self.raw, self.base_dir, self.origin, self._text = raw, base_dir, origin, text
        self.parsed = parse_scene(raw, origin=origin, base_dir=base_dir)

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], base_dir: str | Path | None = None) -> "Scene":
        return cls(dict(data), base_dir)

    @classmethod
    def from_file(cls, path: str | Path) -> "Scene":
        from vlab.scene.file import parse_toml, read_scene_file

        path = Path(path)
        text = read_scene_file(path)
        raw = parse_toml(text, str(path), "scene file")
        return cls(raw, path.parent, path.name, text)

    @property
    def name(self) -> str:
        return self.parsed.name

    def with_values(self, values: Mapping[str, object]) -> "Scene":
        """A copy with dotted keys set, e.g. ``{"material.nu": 0.45, "mesh.size": 2}``."""
        from vlab.scene import apply_overrides

        return Scene(apply_overrides(self.raw, values), self.base_dir, self.origin)

    def run(self, estimate: bool = False) -> Result:
        """Mesh, solve and measure (``estimate``: also the accuracy estimate of ``vlab run``)."""
        from vlab.report.results import result_to_dict
        from vlab.run import run_scene

        result = run_scene(self.parsed)
        if estimate:
            from vlab.study.estimate import accuracy_estimate

            result.diagnostics.accuracy_estimate = accuracy_estimate(result)
        return Result(result, result_to_dict(result), self._text)

    def __repr__(self) -> str:
        p = self.parsed
        return f"Scene({p.name!r}: {p.specimen.shape}, {p.material.model}, {p.test.kind} to {p.test.targets})"

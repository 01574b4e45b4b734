"""Random fit files and CSVs for tests/test_fit_fuzz.py: a fixed seed gives the same cases on every
machine. Each case is a fit file text and its data files (name -> bytes); most are plausible
(closed-form curves of a library model with noise) and each key or cell is broken with a small
probability, so that both the fit and the input checks are exercised."""

from __future__ import annotations

import numpy as np

MODELS = ["neo-hookean", "mooney-rivlin", "yeoh", "gent", "arruda-boyce", "ogden-1", "ogden-2", "ogden-3",
          "ogden", "mooney", "", 3]
KINDS = ["uniaxial", "equibiaxial", "planar", "biaxial", "simple-shear", "volumetric", "uniaxal", "specimen"]
UNITS = ["MPa", "kPa", "Pa", "N/mm2", "kgf/cm2", "psi"]
ODD_NUMBERS = ["nan", "inf", "-inf", "1e300", "-1e300", "1e-320", "abc", "", "0x10", "1,5", " 2 "]


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, float):
        return repr(v) if np.isfinite(v) else ("nan" if np.isnan(v) else ("inf" if v > 0 else "-inf"))
    if isinstance(v, dict):
        return "{ " + ", ".join(f'{k} = {_toml_value(x)}' for k, x in v.items()) + " }"
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    return str(v)


def _table(name: str, items: dict, array: bool = False) -> str:
    head = f"[[{name}]]" if array else f"[{name}]"
    return "\n".join([head] + [f"{k} = {_toml_value(v)}" for k, v in items.items()]) + "\n"


def _grid(rng, kind: str, n: int) -> np.ndarray:
    """A control column: mostly a rising grid, sometimes with λ = 1, a repeat, a fall or a wild value."""
    if kind == "simple-shear":
        lo, hi = 0.0 if rng.random() < 0.3 else 0.05, rng.uniform(0.2, 2.0)
    elif kind == "volumetric":
        lo, hi = rng.uniform(0.9, 0.99), 1.0
    else:
        lo, hi = (1.0 if rng.random() < 0.3 else rng.uniform(1.01, 1.1)), rng.uniform(1.2, 4.0)
        if rng.random() < 0.1:
            lo, hi = rng.uniform(0.5, 0.8), rng.uniform(0.9, 0.99)  # compression
    g = np.linspace(lo, hi, n)
    r = rng.random()
    if r < 0.05 and n > 2:
        g[n // 2] = g[n // 2 - 1]
    elif r < 0.08:
        g = g[::-1].copy()
    elif r < 0.10 and n:
        g[-1] = rng.choice([1e300, 1e-300, -1.0, 0.0])
    return g


def _stress(rng, kind: str, a: np.ndarray) -> np.ndarray:
    """A stress column: a neo-Hookean-like curve with noise, or something no card follows."""
    mu = 10.0 ** rng.uniform(-3, 3)
    a = np.clip(a, 1e-100, 1e100)  # a wild stretch's stress is its own case (not numpy's overflow)
    if kind == "simple-shear":
        y = mu * a
    elif kind == "volumetric":
        y = mu * 1e3 * np.log(a)
    else:
        y = mu * (a - a ** -2) * (2.0 if kind == "equibiaxial" else 1.0)
    y = y * (1 + rng.choice([0.0, 0.01, 0.2]) * rng.standard_normal(len(a)))
    r = rng.random()
    if r < 0.05:
        y = -y
    elif r < 0.10:
        y = np.zeros_like(y)
    elif r < 0.13:
        y = y[::-1].copy()  # softening
    elif r < 0.16:
        y = y * 1e300
    elif r < 0.19:
        y = np.full_like(y, mu)
    return y


def _cell(rng, v: float, wild: bool) -> str:
    return str(rng.choice(ODD_NUMBERS)) if wild and rng.random() < 0.02 else f"{v:.9g}"


def _csv(rng, kind: str, cols: dict, wild: bool) -> bytes:
    """The data file of one set: header and rows (rarely broken bytes, a BOM or a missing column)."""
    n = int(rng.choice([0, 1, 2, 3, 5, 8, 12, 20]))
    a = _grid(rng, kind, n)
    values = {cols[k]: v for k, v in _columns_of(rng, kind, a).items() if k in cols}
    header = list(values)
    if wild and rng.random() < 0.05 and header:
        header[0] = header[0] + "x"
    lines = [",".join(header)] + [",".join(_cell(rng, values[h][i], wild) for h in values) for i in range(n)]
    text = "\n".join(lines) + "\n"
    r = rng.random() if wild else 1.0
    if r < 0.02:
        return b"\xff\xfe\x00garbage\x80\x81"
    if r < 0.04:
        return ("\ufeff" + text).encode("utf-8")
    if r < 0.05:
        return b""
    return text.encode("utf-8")


def _columns_of(rng, kind: str, a: np.ndarray) -> dict:
    y = _stress(rng, kind, a)
    if kind == "biaxial":
        b = np.linspace(1.0, rng.uniform(1.0, 2.0), len(a))
        return {"stretch": a, "stretch2": b, "stress": y, "stress2": 0.5 * y}
    control = {"simple-shear": "shear", "volumetric": "volume_ratio"}.get(kind, "stretch")
    return {control: a, "stress": y}


def _dataset(rng, i: int, wild: bool) -> tuple[dict, str, bytes]:
    """One [[data]] table and its file; ``wild``: keys and cells may be broken."""
    kind = str(rng.choice(KINDS, p=[0.35, 0.12, 0.12, 0.08, 0.12, 0.09, 0.06, 0.06] if wild else
                          [0.4, 0.14, 0.14, 0.1, 0.12, 0.1, 0.0, 0.0]))
    from vlab.identify.datasets import COLUMN_KEYS

    required = COLUMN_KEYS.get(kind, (("stretch", "stress"), ()))[0]
    cols = {k: f"c{k}" for k in required}
    name = f"d{i}.csv"
    item = {"file": name, "kind": kind, "columns": dict(cols)}
    if rng.random() < 0.3:
        item["units"] = str(rng.choice(UNITS[:None if wild else -1]))
    if rng.random() < 0.2:
        item["role"] = str(rng.choice(["fit", "validate", "test"][:None if wild else -1]))
    if rng.random() < 0.1:
        item["weight"] = float(rng.choice([0.5, 2.0, 1e300, 0.0, -1.0][:None if wild else -2]))
    if rng.random() < 0.1:
        item["stress_measure"] = str(rng.choice(["nominal", "true", "cauchy"][:None if wild else -1]))
    if wild and rng.random() < 0.05:
        item["colour"] = 1
    return item, name, _csv(rng, kind, cols, wild)


def _model(rng, wild: bool) -> dict:
    """The [model] table; ``wild``: a name, terms, K or combination may be refused."""
    p = [0.15, 0.15, 0.12, 0.1, 0.1, 0.08, 0.08, 0.08, 0.05, 0.03, 0.03, 0.03] if wild else \
        [0.16, 0.16, 0.13, 0.11, 0.11, 0.09, 0.09, 0.09, 0.06, 0.0, 0.0, 0.0]
    m = {"name": MODELS[int(rng.choice(len(MODELS), p=np.array(p) / sum(p)))]}
    if m["name"] == "ogden" or wild and rng.random() < 0.05:
        m["terms"] = int(rng.choice([1, 2, 3, 0, 7][:None if wild else -2]))
    r = rng.random()
    if r < 0.15:
        m["fit_K"] = True
        if rng.random() < 0.3:
            m["incompressible"] = wild and bool(rng.random() < 0.3)  # true: refused with fit_K
    elif r < 0.3:
        m["K"] = float(rng.choice([100.0, 1e4, 1e300, 0.0, -5.0][:None if wild else -2]))
        if rng.random() < 0.5:
            m["incompressible"] = False
    elif r < 0.35:
        m["K_over_mu"] = float(rng.choice([100.0, 1.0, 1e9][:None if wild else 1]))
    return m


def fit_case(rng) -> tuple[str, dict[str, bytes]]:
    """One random fit file (its text) and its data files."""
    wild = bool(rng.random() < 0.4)  # else only valid keys: the case tests the data and the fit
    sets = [_dataset(rng, i, wild) for i in range(int(rng.choice([1, 1, 2, 3])))]
    opts = {"starts": int(rng.choice([1, 2, 3])), "max_evaluations": int(rng.choice([30, 100, 200]))}
    if rng.random() < 0.15:
        opts["confidence"] = float(rng.choice([0.9, 0.99, 0.2, 1.5][:None if wild else 2]))
    if rng.random() < 0.1:
        opts["residual"] = str(rng.choice(["absolute", "relative", "log"][:None if wild else 2]))
    if wild and rng.random() < 0.05:
        opts["starts"] = int(rng.choice([0, 5000]))
    top = 'name = "a/b"\n' if wild and rng.random() < 0.05 else 'name = "fz"\n'
    if wild and rng.random() < 0.05:
        top += "colour = 2\n"
    text = top + _table("model", _model(rng, wild)) + "".join(_table("data", s[0], array=True) for s in sets) + \
        _table("options", opts)
    return text, {name: data for _, name, data in sets}

"""One virtual test of the budget: the perturbed scene the FE run solves, and the lab's analysis.

A sample is a dict d of deviations, one per source (vlab.uncertainty.spec.Source, by name). The
FE run sees the true specimen and instruments: width W = W0 + δW, thickness T = T0 + δT (the
specimen remeshed), the extensometer's true gauge length L_e = (L0 + δL)(1 + e_g), the card's
constants c (1 + e_c), the modulus window shifted by s, and the readings quantised at the
classes' resolution (an [effects.noise] table), the misaligned grip (test.misalignment) and
the grips' slip (test.grip_slip, which the crosshead reads and the extensometer does not). It
measures E_run = (F/A_true)/(ΔL/L_e), ν_run = −ε_t/ε_a and the crosshead modulus E_c,run over the
window. The lab divides by what it believes:

    E = E_run · (W T)/(W_lab T_lab) · (L0/L_e) · (1 + e_F)/(1 + e_L)
    ν = ν_run · (L_e/L0) · (1 + e_T)/(1 + e_L)
    E_c = E_c,run · (W T)/(W_lab T_lab) · (1 + e_F)

with W_lab, T_lab the nominal dimensions, or the micrometer's readings W + δ_mW, T + δ_mT;
e_F, e_L, e_T the relative errors of the load cell and the axial and transverse extensometers
(exactly: a reading F̃ = F (1 + e_F) scales the slope by 1 + e_F).

Resolution (quantisation of the readings, applied by the run): the load cell at r_F = a · F_lo
(a the class's relative resolution, F_lo ≈ E A0 ε_lo the force at the window's start, where the
class must hold), the extensometer at r_L = max(a_rel · L0 ε_lo, a_abs) (ISO 9513: the greater).
"""

from __future__ import annotations

import copy

import numpy as np

from vlab.scene.test import misalignment_pair
from vlab.uncertainty.spec import UncertaintySpec

__all__ = ["sample_deltas", "scene_source", "lab_values", "resolutions"]


def sample_deltas(spec: UncertaintySpec, i: int) -> dict[str, float]:
    """Sample i's deviations, drawn from default_rng([seed, i]) in the sources' order (so a sample
    is the same however many are drawn, and a resumed budget finds its runs in the cache)."""
    rng = np.random.default_rng([spec.seed, i])
    return {s.name: s.draw(rng) for s in spec.sources}


def _by_kind(spec: UncertaintySpec, d: dict[str, float], kind: str) -> float:
    return sum(d.get(s.name, 0.0) for s in spec.sources if s.kind == kind)


def true_geometry(spec: UncertaintySpec, d: dict) -> tuple[float, float, float]:
    """(W, T, L_e) of a sample, mm."""
    n = spec.nominal
    return (n["width"] + _by_kind(spec, d, "width"), n["thickness"] + _by_kind(spec, d, "thickness"),
            (n["gauge_length"] + _by_kind(spec, d, "gauge")) * (1.0 + _by_kind(spec, d, "gauge_rel")))


def _r(x: float) -> float:
    return float(f"{x:.12g}")  # a stable scene hash: no trailing round-off digits


def scene_source(source: dict, spec: UncertaintySpec, d: dict, noise: dict | None = None) -> dict:
    """The raw scene of a sample: ``source`` without [uncertainty], perturbed by d; ``noise``: the
    [effects.noise] resolutions (and the seed) of a Monte Carlo sample, None for a paired run."""
    out = copy.deepcopy(source)
    out.pop("uncertainty", None)
    W, T, Le = true_geometry(spec, d)
    sp = out["specimen"]
    if sp["shape"] == "block":
        size = list(sp["size"])
        size[1], size[2] = _r(W), _r(T)
        sp["size"] = size
    else:
        sp["width"], sp["thickness"] = _r(W), _r(T)
    measure = out.setdefault("measure", {})
    measure["gauge_length"] = _r(Le)
    for s in spec.sources:
        if s.kind == "material":
            out["material"][s.key] = _r(out["material"][s.key] * (1.0 + d.get(s.name, 0.0)))
        if s.kind == "window" and d.get(s.name, 0.0):
            lo, hi = measure.get("modulus_window", (0.0005, 0.0025))
            measure["modulus_window"] = [_r(lo + d[s.name]), _r(hi + d[s.name])]
    _grips(out, spec, d)
    if noise:
        effects = out.setdefault("effects", {})
        effects["noise"] = dict(effects.get("noise", {})) | noise
    return out


def _grips(out: dict, spec: UncertaintySpec, d: dict) -> None:
    """test.misalignment of a sample: the scene's (0 if absent) plus the drawn offsets and tilts;
    test.grip_slip: the drawn slip compliance (its centre plus the deviation)."""
    test = out["test"]
    for s in spec.sources:
        if s.kind == "slip":
            test["grip_slip"] = _r(s.centre + d.get(s.name, 0.0))
    if not any(s.kind.startswith(("offset_", "tilt_")) for s in spec.sources):
        return
    base = dict(test.get("misalignment", {}))
    offset, tilt = (misalignment_pair(k, base.get(k, 0.0)) for k in ("offset", "tilt"))
    test["misalignment"] = {
        "offset": [_r(offset[0] + _by_kind(spec, d, "offset_y")), _r(offset[1] + _by_kind(spec, d, "offset_z"))],
        "tilt": [_r(tilt[0] + _by_kind(spec, d, "tilt_y")), _r(tilt[1] + _by_kind(spec, d, "tilt_z"))]}


def lab_values(measured: dict, spec: UncertaintySpec, d: dict) -> tuple[float | None, float | None, float | None]:
    """(E, ν, E_crosshead) the lab reports from a run's measured E_run, ν_run and crosshead modulus
    E_c,run (module docstring; E_c = E_c,run (W T)/(W_lab T_lab) (1 + e_F): the crosshead's own
    reading is taken as exact, the slip is in the run's)."""
    n = spec.nominal
    W, T, Le = true_geometry(spec, d)
    if spec.micrometer is not None:
        W_lab, T_lab = W + _by_kind(spec, d, "micrometer_width"), T + _by_kind(spec, d, "micrometer_thickness")
    else:
        W_lab, T_lab = n["width"], n["thickness"]
    eF, eL, eT = (_by_kind(spec, d, k) for k in ("load_cell", "extensometer", "transverse"))
    E, nu, Ec = measured.get("E"), measured.get("nu"), measured.get("E_crosshead")
    area = (W * T) / (W_lab * T_lab) * (1 + eF)
    E = None if E is None else E * area * (n["gauge_length"] / Le) / (1 + eL)
    nu = None if nu is None else nu * (Le / n["gauge_length"]) * (1 + eT) / (1 + eL)
    return E, nu, None if Ec is None else Ec * area


def resolutions(spec: UncertaintySpec, E_nominal: float, window_lo: float) -> dict:
    """The [effects.noise] resolutions (N, mm) of the readings (module docstring); {} if off."""
    if not spec.resolution:
        return {}
    n = spec.nominal
    out = {}
    if spec.load_cell is not None:
        out["load_cell_resolution"] = _r(spec.load_cell["a"] * E_nominal * n["width"] * n["thickness"] * window_lo)
    if spec.extensometer is not None:
        ex = spec.extensometer
        out["extensometer_resolution"] = _r(max(ex["res_rel"] * n["gauge_length"] * window_lo, ex["res_abs"]))
    return out

"""The end-to-end identification error of a field fit on virtual data: the constants recovered from
rendered and correlated images against the constants that made them.

`vlab run` of a scene with [instruments.dic] writes in dic.json a "source" entry (the scene's name
and its [material] table as given; vlab.report.dic_report.source_entry). When the fitted model is
the source's (same law, same volumetric energy, same number of terms), the source's table is
parsed like a scene's (vlab.materials.card, vlab.moduli: a Neo-Hookean given by E and ν becomes
μ = E/(2(1 + ν)), K = E/(3(1 − 2ν))) into the fit's flat constants, and per fitted constant p:

    relative error   e_rel = p̂ / p_true − 1
    in standard errors   z = (p̂ − p_true) / SE(p̂)      (None when the fit gave p̂ no interval)

The constants the fit held fixed are listed with their source values: a held constant off its
source value biases the fitted ones. Another model (or a table that does not parse) is said, not
compared. Real images (`vlab dic`) have no "source": nothing is reported.
"""

from __future__ import annotations

import math

from vlab.fields import SceneError

__all__ = ["end_to_end", "summary_lines"]

HELD_MATCH = 1e-9  # relative: a held constant this close to its source value is the source's


def end_to_end(field, fe: dict, parameters: dict, uncertainty: dict) -> dict | None:
    """fit.json's end_to_end of one field data set (module docstring); None without a source."""
    source = field.source
    if source is None:
        return None
    head = {"scene": source.get("scene"), "source_model": source["material"].get("model"), "fitted_model": fe["model"]}
    truth, why = _truth(source["material"], fe)
    if truth is None:
        return head | {"comparable": False, "note": why}
    constants = {n: _error(v, truth[n], uncertainty.get(n, {}).get("standard_error")) for n, v in parameters.items()}
    held = {n: {"value": float(v), "source": truth[n], "matches_source": _same(v, truth[n])}
            for n, v in fe["fixed"].items() if n not in parameters}
    return head | {"comparable": True, "constants": constants, "held": held,
                   "note": "relative_error = fitted/true - 1; standard_errors = (fitted - true)/standard_error"}


def _truth(material: dict, fe: dict) -> tuple[dict | None, str]:
    """(the source's flat constants, "") when they are the fit's kind of constants, else (None, why)."""
    from vlab.identify.fe_stress import flat_constants
    from vlab.materials.card import parse_material

    name = material.get("model")
    if name != fe["model"]:
        return None, (f"the images were made with material.model = {name!r}, the fit's model is {fe['model']!r}: "
                      "their constants are not the same quantities, so no end-to-end error is given")
    try:
        made = parse_material(material, "source.material")
    except SceneError as exc:
        return None, f"dic.json's source.material does not parse as a material card ({exc}): no comparison"
    if made.volumetric != fe.get("volumetric"):
        return None, (f"the images' {name} has volumetric = {made.volumetric!r}, the fit's {fe.get('volumetric')!r}: "
                      "no comparison")
    truth = flat_constants(made)
    if set(truth) != set(fe["fixed"]):
        return None, (f"the images' {name} has the constants {', '.join(truth)}, the fit's {', '.join(fe['fixed'])}: "
                      "no comparison")
    return truth, ""


def _error(fitted: float, true: float, se) -> dict:
    z = None if se is None or not se > 0 or not math.isfinite(se) else (fitted - true) / se
    return {"true": true, "fitted": float(fitted), "relative_error": fitted / true - 1.0, "standard_errors": z}


def _same(a: float, b: float) -> bool:
    return abs(a - b) <= HELD_MATCH * max(abs(a), abs(b))


def summary_lines(e2e: dict | None) -> list[str]:
    """One line per fitted constant (and per held constant off its source value), or the reason
    there is no comparison; [] without a source."""
    if e2e is None:
        return []
    if not e2e["comparable"]:
        return [f"end to end: {e2e['note']}"]
    lines = []
    for n, c in e2e["constants"].items():
        z = "" if c["standard_errors"] is None else f", {c['standard_errors']:+.2f} standard errors"
        lines.append(f"end to end {n}: {c['fitted']:.6g} against {c['true']:.6g} that made the images "
                     f"({100 * c['relative_error']:+.3f} %{z})")
    for n, h in e2e["held"].items():
        if not h["matches_source"]:
            lines.append(f"end to end: {n} held at {h['value']:.6g}, the images' {n} is {h['source']:.6g}")
    return lines

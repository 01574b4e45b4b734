"""Table rows of what planar, simple-shear, confined-compression and torsion tests measure, from
results dicts (html reports)."""

from __future__ import annotations

from vlab.loading.kinds import KINDS

__all__ = ["kind_of_data", "kind_rows"]


def kind_of_data(data: dict):
    """The test kind of a results dict (from the scene as run)."""
    return KINDS[data["scene"]["source"]["test"]["kind"]]


def _f(value, digits: int = 5) -> str:
    return "—" if value is None else f"{value:.{digits}g}"


def kind_rows(models: list[dict]) -> list[tuple[str, list[str]]]:
    """The table rows of what planar, simple-shear, confined-compression, torsion and inflation tests
    measure (none for other kinds)."""
    rows = _ROWS.get(kind_of_data(models[0]).name)
    return rows(models) if rows else []


def _final(d: dict, key: str):
    """The homogeneity measure ``key`` at the last level (None where not recorded)."""
    return ((d.get("homogeneity") or {}).get("final") or {}).get(key)


def _planar_rows(models: list[dict]) -> list[tuple[str, list[str]]]:
    """Planar tension: the planar modulus against E/(1 − ν²), the distance from pure shear and the
    nominal over the pure-shear stress at the end."""
    return [
        ("planar modulus measured / E/(1−ν²) input [MPa]",
         [f"{_f(d['measured'].get('planar_modulus'))} / {_f(d['input']['E'] / (1 - d['input']['nu'] ** 2))}"
          for d in models]),
        ("distance from pure shear at the end (max |ε_yy| / ε_xx, gauge centre)",
         [_f(_final(d, "distance_from_pure_shear"), 3) for d in models]),
        ("nominal stress / pure-shear stress at the end", [_f(_final(d, "nominal_over_pure_shear"), 4) for d in models]),
    ]


def _shear_rows(models: list[dict]) -> list[tuple[str, list[str]]]:
    """Simple shear: G (gauge marks, plate travel, fit R²), the normal stress and N₁ at the largest
    |γ|, the distance from simple shear and the centre over the nominal shear stress at the end."""
    return [
        ("G measured (gauge marks) / μ input [MPa]", [f"{_f(d['measured'].get('G'))} / {_f(d['input']['mu'])}"
                                                      for d in models]),
        ("G from plate travel [MPa]", [_f(d["measured"].get("G_plate")) for d in models]),
        ("G fit R²", [_f((d["measured"].get("G_fit") or {}).get("r2"), 8) for d in models]),
        ("normal stress σ_n at the largest |γ| [MPa]", [_f(d["measured"].get("normal_stress_at_peak")) for d in models]),
        ("N₁ = σ₁₁ − σ₂₂ at the largest |γ| (FE centre) [MPa]",
         [_f(d["measured"].get("normal_stress_difference")) for d in models]),
        ("distance from simple shear at the end (centre)", [_f(_final(d, "distance_from_simple_shear"), 3) for d in models]),
        ("centre / nominal shear stress at the end", [_f(_final(d, "centre_over_nominal"), 4) for d in models]),
    ]


def _confined_rows(models: list[dict]) -> list[tuple[str, list[str]]]:
    """Confined compression: K and M = K + 4G/3 against the input, G, E, ν derived from them, J and
    p at the end."""
    return [
        ("bulk modulus K measured / input [MPa]",
         [f"{_f(d['measured'].get('bulk_modulus'))} / {_f(d['input'].get('K'))}" for d in models]),
        ("constrained modulus M = K + 4G/3 measured / input [MPa]",
         [f"{_f(d['measured'].get('constrained_modulus'))} / {_f(d['input'].get('M'))}" for d in models]),
        ("G, E, ν derived from M and K", [f"{_f(d['measured'].get('G_derived'))}, {_f(d['measured'].get('E_derived'))}, "
                                         f"{_f(d['measured'].get('nu_derived'), 4)}" for d in models]),
        ("volume ratio J and pressure p at the end [–, MPa]",
         [f"{_f(d['measured'].get('volume_ratio_at_end'))}, {_f(d['measured'].get('pressure_at_end'))}"
          for d in models]),
    ]


def _torsion_rows(models: list[dict]) -> list[tuple[str, list[str]]]:
    """Torsion: G from the torsional stiffness against μ, the torque, axial force and axial stretch
    at the end."""
    return [
        ("G from the torsional stiffness / μ input [MPa]",
         [f"{_f(d['measured'].get('G'))} / {_f(d['input'].get('mu'))}" for d in models]),
        ("torque at the end [N·mm]", [_f(d["measured"].get("torque_at_end")) for d in models]),
        ("axial force at the end [N] (length held; Poynting: < 0)",
         [_f(d["measured"].get("axial_force_at_end")) for d in models]),
        ("axial stretch at the end (free end: > 1)", [_f(d["measured"].get("axial_stretch_at_end"), 7)
                                                      for d in models]),
    ]


def _limit_point(d: dict) -> str:
    """The pressure maximum (stretch, pressure, the bracket of recorded levels it lies in), or why
    there is none."""
    lp = d["measured"].get("limit_point")
    if not lp:
        return "none in the recorded range"
    lo, hi = lp.get("bracket") or (None, None)
    lam = "pole λ" if "pole_stress_at_end" in d["measured"] else "λ_a"  # a bulge's pole, a balloon's wall
    return f"{lam} = {_f(lp['stretch'])}, p = {_f(lp['pressure'])} MPa (between recorded {lam} {_f(lo)} and {_f(hi)})"


def _inflation_rows(models: list[dict]) -> list[tuple[str, list[str]]]:
    """Inflation: the pressure maximum (a property of the balloon), the initial slope dp/dλ_a and
    the pressure and inner stretch at the end; a bulge test's pole readings at the end instead of
    the initial slope (a flat sheet's dp/dλ at rest is 0)."""
    if all("pole_stress_at_end" in d["measured"] for d in models):
        return [
            ("pressure maximum (limit point)", [_limit_point(d) for d in models]),
            ("pressure p at the end [MPa], pole stretch λ",
             [f"{_f(d['measured'].get('pressure_at_end'))}, {_f(d['measured'].get('stretch_at_end'))}" for d in models]),
            ("pole height h at the end [mm], volume ratio",
             [f"{_f(d['measured'].get('pole_height_at_end'))}, {_f(d['measured'].get('volume_ratio_at_end'))}"
              for d in models]),
            ("pole stress at the end [MPa]: lab p R_c / (2t), FE",
             [f"{_f(d['measured'].get('pole_stress_at_end'))}, {_f(d['measured'].get('pole_stress_fe_at_end'))}"
              for d in models]),
        ]
    return [
        ("pressure maximum (limit point)", [_limit_point(d) for d in models]),
        ("initial slope dp/dλ_a [MPa]", [_f(d["measured"].get("initial_slope")) for d in models]),
        ("pressure p at the end [MPa], inner stretch λ_a",
         [f"{_f(d['measured'].get('pressure_at_end'))}, {_f(d['measured'].get('stretch_at_end'))}" for d in models]),
    ]


_ROWS = {"planar": _planar_rows, "simple-shear": _shear_rows, "confined-compression": _confined_rows,
         "torsion": _torsion_rows, "inflation": _inflation_rows}

"""The figures of the stretch-controlled test kinds (planar and simple shear draw theirs in
vlab/report/kind_plots.py). Uniaxial: stress–strain overlay with the fit-window inset, lateral strain and
the apparent Poisson's ratio. Biaxial: both axes' stress–strain curves and the thickness strain.
Every figure is drawn without offset notation on its tick labels (a 2.5e−1 ± 1e−5 range reads
0.24999 … 0.25001, not "1e−5 + 2.499e−1")."""

from __future__ import annotations

from pathlib import Path

import matplotlib


NO_OFFSET = {"axes.formatter.useoffset": False}


def kind_of(data: dict) -> str:
    from vlab.report.kind_rows import kind_of_data

    return kind_of_data(data).name


def kind_figures(datas: list[dict], folder: Path, true: bool, departures: dict) -> list:
    """Draw the kind's figures into ``folder``; returns their Figure entries for the page."""
    with matplotlib.rc_context(NO_OFFSET):
        if kind_of(datas[0]) == "biaxial":
            return _biaxial(datas, Path(folder), true)
        return _uniaxial(datas, Path(folder), true, departures)


def _uniaxial(datas, folder: Path, true: bool, departures: dict) -> list:
    from vlab.report.comparison_plots import plot_lateral, plot_overlay
    from vlab.report.html import Figure

    kind = "true" if true else "engineering"
    plot_overlay(datas, folder / "stress_strain.png", true, departures)
    plot_lateral(datas, folder / "lateral_strain.png")
    return [
        Figure("stress_strain.png", f"{kind.capitalize()} stress against extensometer strain for every "
               "model; dashed: the analytic homogeneous solution where the specimen has one; shaded: "
               "the E fit window (inset: zoom on it); ○/✕: where a model's stress first differs from "
               "Neo-Hookean's by 5 %/10 %. Right: the machine's own record, load-cell force "
               "against crosshead (grip) displacement Δ = (λ − 1) L₀ over the whole test, the first plot a "
               "lab looks at; it stretches the whole length between the grips (a dogbone's shoulders too), "
               "which is why E is read from the extensometer."),
        Figure("lateral_strain.png", "Lateral against axial strain and the apparent Poisson's ratio "
               "−ε_lat/ε_axial as the strain grows."),
    ]


def _biaxial(datas, folder: Path, true: bool) -> list:
    from vlab.report.biaxial_plots import plot_biaxial_stress_strain, plot_thickness
    from vlab.report.html import Figure

    kind = "true" if true else "engineering"
    plot_biaxial_stress_strain(datas, folder / "stress_strain.png", true)
    plot_thickness(datas, folder / "thickness_strain.png")
    return [
        Figure("stress_strain.png", f"Biaxial {kind} stress against extensometer strain along x (left) "
               "and y (right) for every model; dashed: the analytic homogeneous solution where the specimen "
               "has one; dotted: a cruciform's FE centre stress against its centre strain."),
        Figure("thickness_strain.png", "Thickness strain against the in-plane strain sum ε_x + ε_y, with "
               "the input's small-strain line −ν/(1 − ν)(ε_x + ε_y) (σ_z = 0); the legend gives the E and ν "
               "each model's test measured."),
    ]

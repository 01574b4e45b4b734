"""Identification from full fields: FE model updating on DIC strain maps and the load-cell force
(`vlab fit` data of kind = "field", vlab.identify.field_data).

Residuals, per level k (the data's grip displacement Δ_k) and data set of weight w:

    strain   r = √w (E_FE,c(X_n) − E_DIC,c(X_n)) / σ_E   c ∈ {xx, yy, xy}, n the usable subsets
    force    r = √w (F_FE(Δ_k) − F_k) / σ_F             (Δ_k > 0)

E_FE is the FE field levelled (vlab.identify.field_model: the FE displacement at the subset
centres through the DIC's strain window), a usable subset one whose DIC strain is finite and whose
window holds no valid subset off the FE face. σ_E (data.strain_noise, default 1e-4) and σ_F
(data.force_resolution, default 1e-3 max|F|) set the balance of the two; the uncertainty scales
by the residual variance s² as for every fit. J = ∂r/∂p exactly: ∂u/∂p of the face from the
converged level's factor (vlab.identify.field_sim) through the linear levelling operator.
Levenberg–Marquardt, the convergence tests and the uncertainty are vlab.identify.fe_loop's.
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from vlab.fields import SceneError
from vlab.identify.card import card_of
from vlab.identify.drucker import kind_stability
from vlab.identify.fe_loop import _card_space, _identifiability, _model_entry, _one_start, closed_form, lm_fit
from vlab.identify.field_model import face_points, interpolation, levelled, subset_interpolation, usable
from vlab.identify.field_sim import simulate_field
from vlab.identify.field_truth import end_to_end

__all__ = ["fit_field", "field_residuals", "field_section"]

OPTIMISTIC = ("field fit: the standard errors treat every DIC strain value as independent; neighbouring subsets "
              "and strain windows overlap, so they are optimistic (docs/dic.md: the error of μ on virtual images "
              "was 0.7 to 6 of them)")
OFFSETS = 16  # directions probed around a subset centre off the face (is the subset on the face at all?)


class _Geometry:
    """A data set's fixed geometry on the face: P (subsets × face vertices), on_face (grid)."""

    def __init__(self, d, face):
        f = d.extra["field"]
        self.shape = (f.ys.size, f.xs.size)
        X1, X2 = face_points(f.camera, f.xs, f.ys)
        self.P, found = subset_interpolation(face, X1, X2, f.subset, f.camera["mm_per_px"])
        self.on_face = found.reshape(self.shape)
        _check_on_face(d, face, self.on_face, X1, X2)


def _check_on_face(d, face, on_face, X1, X2) -> None:
    """SceneError when a converged subset lies wholly off the face (its centre farther than half a
    subset from it: the camera's centre, pitch or face must be wrong), naming the file and row."""
    f = d.extra["field"]
    half = 0.5 * (f.subset or 0) * f.camera["mm_per_px"]
    for lv in f.levels:
        stray = np.argwhere(lv.valid & ~on_face)
        if stray.size == 0:
            continue
        a = 2 * np.pi * np.arange(OFFSETS) / OFFSETS
        i, j = stray[:, 0], stray[:, 1]
        px = (X1[i, j][:, None] + half * np.cos(a)).ravel()
        py = (X2[i, j][:, None] + half * np.sin(a)).ravel()
        near = interpolation(face, px, py)[1].reshape(-1, OFFSETS).any(axis=1) if half > 0 else np.zeros(len(i), bool)
        if not near.all():
            n = int(np.argmin(near))
            lo, hi = face.bounds
            raise SceneError(
                f"{lv.file} row {lv.rows[i[n], j[n]]} columns 'x_px', 'y_px' = ({f.xs[j[n]]:g}, {f.ys[i[n]]:g}): this "
                f"converged subset maps to the face point ({X1[i[n], j[n]]:.4g}, {X2[i[n], j[n]]:.4g}) mm, off the "
                f"FE face (x₁ {lo[0]:.4g}…{hi[0]:.4g}, x₂ {lo[1]:.4g}…{hi[1]:.4g} mm) by more than half a subset: "
                "check the camera's centre, mm_per_px, pixels and face")


def field_residuals(sim, d, geo: _Geometry, names):
    """(r, J, summary) of one field data set against a simulation; summary: the levelled FE
    strains, the usable masks and the FE forces at the data's levels (for fit.json and the figure)."""
    f = d.extra["field"]
    u, du, F, dF = sim.at(d.a, d.name)
    rs, Js, maps = [], [], []
    for k, lv in enumerate(f.levels):
        E, dE = levelled(geo.P, u[k], du[k], lv.valid & geo.on_face, f.camera["mm_per_px"], f.step, f.window)
        dic = np.stack([lv.exx, lv.eyy, lv.exy])
        use = usable(lv.valid, geo.on_face, f.window) & np.all(np.isfinite(dic), 0) & np.all(np.isfinite(E), 0)
        rs.append((E[:, use] - dic[:, use]).ravel() / f.strain_noise)
        Js.append(dE[:, :, use].reshape(len(names), -1).T / f.strain_noise)
        maps.append((E, use))
    if not sum(r.size for r in rs):
        raise SceneError(f"{d.name}: no subset has a DIC strain on the FE face to fit (all empty or off the face)")
    loaded = d.a > 0
    rs.append((F[loaded] - d.y[loaded]) / f.force_resolution)
    Js.append(dF[loaded] / f.force_resolution)
    w = np.sqrt(d.weight)
    return w * np.concatenate(rs), w * np.vstack(Js), {"maps": maps, "force": F}


class _Problem:
    """fe_loop._lm's problem: evaluate(p) → (r, J, (sim, summaries)) from one whole-test solve."""

    def __init__(self, spec):
        self.spec, self.fe = spec, spec.fe
        self.sets = [d for d in spec.datasets if d.kind == "field"]
        faces = {d.extra["field"].camera["face"] for d in self.sets}
        if len(faces) > 1:
            raise SceneError(f"the field data sets look at different faces {sorted(faces)}: one field fit takes one face")
        self.face_side = faces.pop()
        self.names = self.fe["parameters"]
        self.solves, self.cached, self.counts = 0, 0, {}
        self.geometry = None

    def values(self, p):
        return self.fe["fixed"] | dict(zip(self.names, map(float, p)))

    def evaluate(self, p):
        self.solves += 1
        sim = simulate_field(self.fe, self.values(p), self.face_side)
        for k, v in sim.counts.items():
            self.counts[k] = self.counts.get(k, 0) + v
        if self.geometry is None:  # the reference face is the same at every p
            self.geometry = [_Geometry(d, sim.face) for d in self.sets]
        parts = [field_residuals(sim, d, g, self.names) for d, g in zip(self.sets, self.geometry)]
        return (np.concatenate([q[0] for q in parts]), np.vstack([q[1] for q in parts]),
                (sim, [q[2] for q in parts]))


def fit_field(spec, execution=None):
    """The field fit of spec (one process: ``execution`` on Dask is refused)."""
    from vlab.identify.fitting import FitOutcome, _information, trust_of

    if execution is not None:
        raise SceneError("--workers/--scheduler: a field fit runs its whole-test solves in this process")
    t0 = time.perf_counter()
    prob = _Problem(spec)
    names = prob.names
    (p, r, J, (sim, summaries), trail, converged, reason), (cov, s2, dof, cond, reasons, stats) = lm_fit(prob, spec)
    t_fit = time.perf_counter() - t0
    values = prob.values(p)
    model = closed_form(spec.fe, "fit")
    x, cov_x = _card_space(model, values, names, cov)
    errors = [_dataset_errors(d, s) for d, s in zip(prob.sets, summaries)]
    for row, d in zip(errors, prob.sets):  # virtual images: the constants that made them (field_truth)
        row["end_to_end"] = end_to_end(d.extra["field"], spec.fe, dict(zip(names, map(float, p))), stats["uncertainty"])
    data = {
        "name": spec.name, "converged": bool(converged), "reason": reason,
        "model": _model_entry(spec, model, values, names),
        "parameters": {n: float(v) for n, v in zip(names, p)}, "uncertainty": stats["uncertainty"],
        "confidence": spec.confidence, "correlation": stats["correlation"], "datasets": errors,
        "information": _information(r, len(p), s2, dof), "starts": _one_start(),
        "identifiability": _identifiability(stats, reasons, cond), "stability": _stability(model, x, errors),
        "card": card_of(model, model.card_vector(x), None if "K" in names else "K held at the scene's value"),
        "fe": _fe_record(spec, prob, trail, errors, sim),
        "warnings": [f"vlab run: {w}" for w in sim.warnings] + [OPTIMISTIC],
        "options": {"residual": "field"}, "timing": {"fit_s": t_fit, "total_s": time.perf_counter() - t0}}
    data["trust"] = trust_of(data)
    outcome = FitOutcome(data, dataclasses.replace(spec, model=model), x, cov_x, stats["t_quantile"])
    outcome.extras["writers"] = [("field.png", lambda path: _plot(prob.sets[0], summaries[0], path))]
    outcome.extras["figures"] = [("field.png", "The last level of the first field: DIC strain E_xx, the FE's "
                                  "levelled E_xx at the fitted constants, their difference; force against grip "
                                  "displacement (points: load cell; line: FE).")]
    return outcome


def _dataset_errors(d, summary) -> dict:
    """fit.json's row of a field data set: the force's relative errors (rms_relative, max_relative)
    and the strains' absolute ones over the usable subsets of every level."""
    f = d.extra["field"]
    diffs = [E[:, use] - np.stack([lv.exx, lv.eyy, lv.exy])[:, use] for (E, use), lv in zip(summary["maps"], f.levels)]
    e = np.concatenate([x.ravel() for x in diffs])
    loaded = d.a > 0
    rel = (summary["force"][loaded] - d.y[loaded]) / np.abs(d.y[loaded]) if loaded.any() else np.zeros(1)
    strains = np.concatenate([np.stack([lv.exx, lv.eyy, lv.exy])[:, use].ravel()
                              for (_, use), lv in zip(summary["maps"], f.levels)])
    return {"name": d.name, "file": d.file, "kind": "field", "role": d.role,
            "points": int(e.size + loaded.sum()), "levels": len(f.levels),
            "subsets_used": [int(use.sum()) for _, use in summary["maps"]],
            "rms_relative": float(np.sqrt(np.mean(rel ** 2))), "max_relative": float(np.max(np.abs(rel))),
            "strain_rms": float(np.sqrt(np.mean(e ** 2))), "strain_max": float(np.max(np.abs(e))),
            "strain_range": [float(np.min(strains)), float(np.max(strains))],
            "strain_noise": f.strain_noise, "force_resolution_N": f.force_resolution}


def _stability(model, x, errors) -> dict:
    """Drucker stability on the uniaxial path over the stretches the DIC saw, λ = √(1 + 2E)."""
    lo = min(e["strain_range"][0] for e in errors)
    hi = max(e["strain_range"][1] for e in errors)
    span = (float(np.sqrt(max(1 + 2 * min(lo, 0.0), 1e-6))), float(np.sqrt(1 + 2 * max(hi, 0.0))))
    kinds = {k: kind_stability(model, x, k, span if k == "uniaxial" else None)
             for k in ("uniaxial", "equibiaxial", "planar")}
    judged = [v["stable_over_fitted_range"] for v in kinds.values() if "stable_over_fitted_range" in v]
    return {"kinds": kinds, "stable_over_all_fitted_ranges": bool(all(judged)),
            "basis": "stretch √(1 + 2E) over the DIC's Green–Lagrange strains, on the uniaxial path"}


def _fe_record(spec, prob, trail, errors, sim) -> dict:
    return {"scene": spec.fe["scene_path"], "solves": prob.solves, "from_cache": 0, "axes": ["x"],
            "counts": prob.counts, "execution": {"dask": False}, "cache": None, "trail": trail, "dofs": sim.dofs,
            "field": {"face": {"axis": prob.face_side[0], "side": prob.face_side[1]},
                      "weights": {e["name"]: {"strain_noise": e["strain_noise"],
                                              "force_resolution_N": e["force_resolution_N"]} for e in errors},
                      "note": "strains levelled through the DIC's strain window; the FE's vertex displacement "
                              "interpolated at the subset centres; fe.cache is not used by field fits"}}


def field_section(d: dict) -> str:
    """The report's section of a field fit: solves, weights and the strain and force errors."""
    import html

    fe = d["fe"]
    rows = "".join(f"<tr><td>{html.escape(e['name'])}</td><td>{e['levels']}</td><td>{sum(e['subsets_used'])}</td>"
                   f"<td>{e['strain_noise']:.3g}</td><td>{e['force_resolution_N']:.3g}</td>"
                   f"<td>{e['strain_rms']:.3g}</td><td>{e['strain_max']:.3g}</td>"
                   f"<td>{100 * e['rms_relative']:.3g} %</td></tr>" for e in d["datasets"] if e["kind"] == "field")
    return (f"<h2>FE model updating on full fields</h2><p>{fe['solves']} whole-test solves of "
            f"{html.escape(fe['scene'])} ({fe['dofs']} DOFs); the FE strains levelled through the DIC's strain "
            "window at each subset, against the DIC strains, and the load cell.</p><table><tr><th>data</th>"
            "<th>levels</th><th>strain values (subsets × levels)</th><th>σ_E</th><th>σ_F (N)</th>"
            f"<th>strain rms error</th><th>strain max error</th><th>force rms relative</th></tr>{rows}</table>"
            + "".join(_truth_section(e) for e in d["datasets"] if e.get("end_to_end")))


def _truth_section(row: dict) -> str:
    """The end-to-end error of one data set made by vlab run (vlab.identify.field_truth)."""
    import html

    e = row["end_to_end"]
    head = (f"<h3>End to end: {html.escape(row['name'])}</h3><p>The images were rendered and correlated by vlab run "
            f"of the scene {html.escape(str(e['scene']))} ({html.escape(str(e['source_model']))}).")
    if not e["comparable"]:
        return head + f" {html.escape(e['note'][:1].upper() + e['note'][1:])}</p>"
    rows = "".join(f"<tr><td>{html.escape(n)}</td><td>{c['true']:.6g}</td><td>{c['fitted']:.6g}</td>"
                   f"<td>{100 * c['relative_error']:+.3f} %</td><td>"
                   f"{'—' if c['standard_errors'] is None else format(c['standard_errors'], '+.2f')}</td></tr>"
                   for n, c in e["constants"].items())
    held = "".join(f" {html.escape(n)} was held at {h['value']:.6g} against the images' {h['source']:.6g}."
                   for n, h in e["held"].items() if not h["matches_source"])
    return (head + f" The identified constants against those that made the images:{held}</p><table><tr>"
            "<th>constant</th><th>made the images</th><th>identified</th><th>relative error</th>"
            f"<th>error in standard errors</th></tr>{rows}</table>")


def _plot(d, summary, path) -> None:
    """Three maps of the last level (DIC E_xx, FE levelled E_xx, FE − DIC) beside force–displacement."""
    import matplotlib.pyplot as plt

    f = d.extra["field"]
    (E, use), lv = summary["maps"][-1], f.levels[-1]
    dic, fe = np.where(use, lv.exx, np.nan), np.where(use, E[0], np.nan)
    extent = (f.xs[0], f.xs[-1], f.ys[-1], f.ys[0])
    fig = plt.figure(figsize=(11, 7), constrained_layout=True)
    grid = fig.add_gridspec(3, 2, width_ratios=(1.6, 1))
    lo, hi = np.nanmin([dic, fe]), np.nanmax([dic, fe])
    panels = ((dic, f"DIC E_xx ({lv.image})", "viridis", (lo, hi)), (fe, "FE levelled E_xx", "viridis", (lo, hi)),
              (fe - dic, "FE − DIC, E_xx", "RdBu_r", (None, None)))
    for row, (data, title, cmap, (vmin, vmax)) in enumerate(panels):
        ax = fig.add_subplot(grid[row, 0])
        im = ax.imshow(data, extent=extent, cmap=cmap, vmin=vmin, vmax=vmax, interpolation="nearest")
        fig.colorbar(im, ax=ax, shrink=0.9)
        ax.set_title(title, fontsize=10)
        ax.set_ylabel("y (px)")
    ax.set_xlabel("x (px)")
    ax = fig.add_subplot(grid[:, 1])
    ax.plot(d.a, d.y, "o", label="load cell")
    ax.plot(np.r_[0, d.a], np.r_[0, summary["force"]], "k-", label="FE at the fitted constants")
    ax.set_xlabel("grip displacement (mm)")
    ax.set_ylabel("force (N)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.savefig(path, dpi=90)
    plt.close(fig)

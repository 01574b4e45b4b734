"""FE in the loop: fit the scene's material constants until vlab's own test reproduces the
specimen's readings: per channel (vlab.identify.fe_readings) a control e_i (extensometer strain,
twist, stretch, volume ratio, pole height) and a reading F_i (load-cell force in N, torque in N·mm,
axial force, a free end's stretch, pressure or stress in MPa).

The simulated reading at a measured control is the cubic spline F(e) through the recorded levels
(and the unloaded state: e = 0 for a strain or a twist, 1 for a stretch or a volume ratio, F = 0,
or 1 for a stretch reading); its sensitivity at fixed control is S_k = dF_k/dp − F'(e_k) de_k/dp (an
extensometer's strain or a bulge's pole height itself moves with p; a prescribed control does not),
splined the same way. Residuals r_i = (F(e_i) − F_i)/s_i (s_i = max(|F_i|, 0.01 max|F|) relative
(of F − 1 for a stretch reading: its change), 1 unit absolute; the spline extends at most 10 % of
the control's range beyond the last level, since a measured end control moves with p),
J_i = S(e_i)/s_i. Levenberg–Marquardt:
(JᵀJ + λ diag JᵀJ) δ = −Jᵀr, a step that lowers Σ r² is kept (λ/10), else λ×10; every trial
point is one whole-test solve; a trial that would leave the admissible box (vlab.identify.fe_spec.
admissible) is halved first, a trial whose test fails is a rejected step. Converged when every
|δ_j| ≤ 0.01 standard errors (or 1e-8 p_j), i.e. the last step moved nothing the data can resolve,
or when the rms weighted residual is below MATCHED (noise-free readings reproduced). A cruciform's
two axes each have their own spline and residuals. Uncertainty as for homogeneous fits.
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np
from scipy.interpolate import CubicSpline

from vlab.fields import SceneError
from vlab.identify import uncertainty as unc
from vlab.identify.card import card_of
from vlab.identify.drucker import kind_stability
from vlab.identify.fe_sensitivity import simulate
from vlab.identify.fe_spec import admissible
from vlab.identify.laws import law_for
from vlab.identify.states import Constitutive

__all__ = ["fit_specimen", "residuals", "closed_form", "lm_fit"]

EXTRAPOLATION = 0.1  # data may reach 10 % of the simulated strain range beyond its end
MATCHED = 1e-9  # rms weighted residual at which noise-free readings count as reproduced (solver rtol 1e-8)


UNSTRAINED = {"stretch": 1.0, "volume_ratio": 1.0, "axial_stretch": 1.0}  # a key's value unloaded (else 0)


def _axis(sim, a: int, e_data, F_data, weight: float, relative: bool, name: str, keys=("strain", "force")):
    """(r, J, F(e_i)) of one channel: the spline of the simulated reading at the data's controls."""
    e0, F0 = UNSTRAINED.get(keys[0], 0.0), UNSTRAINED.get(keys[1], 0.0)
    e = np.r_[e0, sim.strain[:, a]]
    F = np.r_[F0, sim.force[:, a]]
    step = np.diff(e)
    if not (np.all(step > 0) or np.all(step < 0)):
        raise RuntimeError(f"the simulated {keys[0]} of channel {a} is not monotonic; cannot match the data's "
                           f"{keys[0]}")
    order = slice(None) if step[0] > 0 else slice(None, None, -1)  # a compression runs down
    lo, hi = e.min(), e.max()
    reach = EXTRAPOLATION * (hi - lo)  # a measured end control moves with the constants
    if np.min(e_data) < lo - reach or np.max(e_data) > hi + reach:
        raise SceneError(f"{name}: the data's {keys[0]} range {np.min(e_data):.4g}..{np.max(e_data):.4g} (channel "
                         f"{keys[1]} against {keys[0]}) is not covered by the scene's test ({lo:.4g}..{hi:.4g}): "
                         "change the scene's test load (stretch, twist, volume_ratio)")
    spline = CubicSpline(e[order], F[order])
    dF, de = sim.dforce[:, a, :], sim.dstrain[:, a, :]
    S = np.vstack([np.zeros(dF.shape[1]), dF - spline(sim.strain[:, a], 1)[:, None] * de])
    Fi = spline(e_data)
    Si = CubicSpline(e[order], S[order], axis=0)(e_data)
    size = np.abs(F_data - F0)
    scale = np.maximum(size, 0.01 * np.max(size)) if relative else np.ones_like(F_data)
    w = np.sqrt(weight) / scale
    return (Fi - F_data) * w, Si * w[:, None], Fi


def channel_keys(d) -> tuple[tuple[str, str], ...]:
    """(control key, reading key) of each channel of data set d (an extension test's by default)."""
    default = (("strain", "force"), ("strain2", "force2"))[: 1 if d.b is None else 2]
    return tuple((d.extra or {}).get("channels", default))


def residuals(sim, d, relative: bool):
    """(r, J, F(e_i)) of data set d against a simulation: channel after channel (a cruciform's axis
    x then y; torsion's torque then axial force), each reading relative to its own readings."""
    n = d.points
    keys = channel_keys(d)
    parts = [_axis(sim, 0, d.a, d.y[:n], d.weight, relative, d.name, keys[0])]
    if d.b is not None:
        parts.append(_axis(sim, 1, d.b, d.y[n:], d.weight, relative, d.name, keys[1]))
    return tuple(np.concatenate([q[k] for q in parts]) for k in range(3))


def _relative_error(Fi, y):
    return (Fi - y) / np.maximum(np.abs(y), 0.01 * np.max(np.abs(y)))


class _Problem:
    def __init__(self, spec, run=None):
        self.spec, self.fe, self.run = spec, spec.fe, run
        self.sets = [d for d in spec.datasets if d.kind == "specimen" and d.role == "fit"]
        self.names = self.fe["parameters"]
        self.solves = 0   # evaluations of the whole test (solved, or read back from the cache)
        self.cached = 0
        self.counts: dict = {}  # factorizations and back-substitutions summed over the solves

    def values(self, p):
        return self.fe["fixed"] | dict(zip(self.names, map(float, p)))

    def evaluate(self, p):
        self.solves += 1
        sim = simulate(self.fe, self.values(p), run=self.run)
        self.cached += sim.cached
        for k, v in sim.counts.items():
            self.counts[k] = self.counts.get(k, 0) + v
        parts = [residuals(sim, d, self.spec.residual == "relative") for d in self.sets]
        return np.concatenate([q[0] for q in parts]), np.vstack([q[1] for q in parts]), sim


def _lm(prob: _Problem, p0):
    p, lam = np.asarray(p0, float), 1e-3
    r, J, sim = prob.evaluate(p)
    trail = [{"solve": 1, "parameters": p.tolist(), "objective": float(0.5 * r @ r), "accepted": True}]
    while prob.solves < prob.fe["max_solves"]:
        A, g = J.T @ J, J.T @ r
        delta = np.linalg.solve(A + lam * np.diag(np.diag(A)), -g)
        while not admissible(prob.names, p + delta, p):  # no solve spent on an inadmissible card
            delta *= 0.5
        try:
            r2, J2, sim2 = prob.evaluate(p + delta)
            ok, note = r2 @ r2 < r @ r, None
        except (RuntimeError, SceneError) as exc:  # no test at the trial constants (Gent chains lock, ...)
            ok, note = False, str(exc)
        trail.append({"solve": prob.solves, "parameters": (p + delta).tolist(),
                      "objective": float(0.5 * r2 @ r2) if note is None else None, "accepted": bool(ok)}
                     | ({"failed": note} if note else {}))
        if ok:
            cov, *_ = unc.covariance(J2, r2)
            se = np.sqrt(np.clip(np.diag(cov), 0, None))
            p, r, J, sim, lam = p + delta, r2, J2, sim2, lam / 10
            if np.all(np.abs(delta) <= np.maximum(0.01 * se, 1e-8 * np.abs(p))):
                return p, r, J, sim, trail, True, "the last step moved every constant by < 0.01 standard errors"
            if r @ r <= MATCHED ** 2 * len(r):
                return p, r, J, sim, trail, True, f"the readings are matched to {MATCHED:g} (relative rms)"
        else:
            lam *= 10
    return p, r, J, sim, trail, False, f"not converged within fe.max_solves = {prob.fe['max_solves']} whole-test solves"


def _homogeneous_comparison(spec, sim, p, se, names) -> dict:
    """The closed-form fit of the same readings, as if the specimen were ideal (the scene kind's
    ``closed_form`` in vlab.identify.fe_readings: stress = F/A0 and stretch = 1 + e of an extension
    test, Rivlin's torsion of the scene's radius, the thick sphere, the die's homogeneous state)."""
    from vlab.identify.datasets import Dataset
    from vlab.identify.fe_readings import SPECIMEN_KINDS
    from vlab.identify.fitting import fit_homogeneous

    kind = SPECIMEN_KINDS[spec.fe["scene"].test.kind]
    incompressible = not kind.closed_form_has_K  # Rivlin's cylinder, the thick sphere: K is not in them
    model = closed_form(spec.fe, "fit" if "K" in names and not incompressible else "fixed")
    sets = []
    for d in (d for d in spec.datasets if d.kind == "specimen" and d.role == "fit"):
        c = kind.closed_form(d, spec.fe["scene_raw"], sim.area0)
        if c is None:
            return {"kind": None, "note": f"no closed form of these readings ({_channels_text(d)}) on this "
                                          f"{spec.fe['scene'].specimen.shape}"}
        sets.append(Dataset(d.name, d.file, c["kind"], "fit", d.weight, "nominal", c["a"], c["b"], c["y"],
                            c["extra"]))
    hom = fit_homogeneous(dataclasses.replace(spec, model=model, datasets=tuple(sets), fe=None, starts=3))
    values = spec.fe["fixed"] | dict(zip(model.names, model.card_vector(hom.x)))
    compared = [(n, v, s) for n, v, s in zip(names, p, se) if not (incompressible and n == "K")]
    out = {"kind": sets[0].kind, "parameters": {n: float(values[n]) for n, _, _ in compared},
           "area0_mm2": sim.area0.tolist()}
    out["difference_in_standard_errors"] = {n: float((values[n] - v) / s) if s > 0 else None for n, v, s in compared}
    out["relative_difference"] = {n: float(values[n] / v - 1) for n, v, _ in compared}
    if incompressible:
        out["note"] = "the closed form is incompressible: K held at the scene's value and not compared"
    return out


def _channels_text(d) -> str:
    return ", ".join(f"{r} against {c}" for c, r in channel_keys(d))


def closed_form(fe: dict, bulk: str) -> Constitutive:
    """The identification library's form of the scene's law (vlab's Neo-Hookean, or a card model
    with the scene's volumetric energy); bulk "fit" or "fixed" at the scene's K."""
    terms = sum(1 for n in fe["fixed"] if n.startswith("alpha[")) or 1
    return Constitutive(law_for(fe.get("model", "neo-hookean"), terms), bulk,
                        None if bulk == "fit" else fe["fixed"]["K"], fe.get("volumetric") or "quadratic")


def _card_space(model: Constitutive, values: dict, names, cov):
    """Internal coordinates x of the card (values) and the covariance of the fitted constants
    mapped to x (zero for the constants held fixed): card = T x, Cov_x = T⁻¹ Cov T⁻ᵀ."""
    order = list(model.names)
    card = np.array([values[n] for n in order])
    T_inv = np.linalg.inv(model.transform)
    cov_card = np.zeros((len(order), len(order)))
    idx = [order.index(n) for n in names]
    cov_card[np.ix_(idx, idx)] = cov
    return T_inv @ card, T_inv @ cov_card @ T_inv.T


def fit_specimen(spec, execution=None):
    """The FE-in-the-loop fit of spec's specimen data sets; ``execution`` (vlab.study.sweep.Execution)
    runs the whole-test solves on Dask (vlab.identify.fe_dask), None in this process."""
    t0 = time.perf_counter()
    if execution is None:
        return _fit_specimen(spec, None, t0)
    from vlab.identify.fe_dask import DaskSolves

    with DaskSolves(execution) as run:
        return _fit_specimen(spec, run, t0)


def _fit_specimen(spec, run, t0):
    from vlab.identify.fitting import FitOutcome, _information, trust_of

    prob = _Problem(spec, run)
    names = prob.names
    (p, r, J, sim, trail, converged, reason), (cov, s2, dof, cond, reasons, stats) = lm_fit(prob, spec)
    t_fit = time.perf_counter() - t0
    se = np.sqrt(np.clip(np.diag(cov), 0, None))
    values = prob.values(p)
    model = closed_form(spec.fe, "fit")
    x, cov_x = _card_space(model, values, names, cov)
    datasets = [_dataset_errors(sim, d) for d in spec.datasets if d.kind == "specimen"]
    data = {
        "name": spec.name, "converged": bool(converged), "reason": reason,
        "model": _model_entry(spec, model, values, names),
        "parameters": {n: float(v) for n, v in zip(names, p)}, "uncertainty": stats["uncertainty"],
        "confidence": spec.confidence, "correlation": stats["correlation"], "datasets": datasets,
        "information": _information(r, len(p), s2, dof),
        "starts": _one_start(), "identifiability": _identifiability(stats, reasons, cond),
        "stability": _specimen_stability(model, x, spec),
        "card": card_of(model, model.card_vector(x), None if "K" in names else "K held at the scene's value"),
        "fe": _fe_record(spec, prob, run, trail, _homogeneous_comparison(spec, sim, p, se, names)),
        "warnings": [f"vlab run: {w}" for w in sim.warnings],
        "options": {"residual": spec.residual},
        "timing": {"fit_s": t_fit, "total_s": time.perf_counter() - t0},
    }
    data["trust"] = trust_of(data)
    outcome = FitOutcome(data, dataclasses.replace(spec, model=model), x, cov_x, stats["t_quantile"])
    _attach_figure(outcome, lambda path: _plot(spec, sim, J, cov, stats["t_quantile"], path))
    return outcome


def lm_fit(prob, spec):
    """(_lm's result from fe.start, (cov, s², dof, κ, undetermined, summary) at its end point); a
    test that fails at the start is a SceneError."""
    names = list(prob.names)
    try:
        p, r, J, sim, trail, converged, reason = _lm(prob, np.array([spec.fe["start"][n] for n in names]))
    except RuntimeError as exc:
        raise SceneError(f"fe.scene: {exc}") from None
    cov, s2, dof, cond = unc.covariance(J, r)
    reasons = unc.undetermined(J, names, dof)
    stats = unc.summarize(p, cov, names, dof, spec.confidence, reasons)
    return (p, r, J, sim, trail, converged, reason), (cov, s2, dof, cond, reasons, stats)


def _model_entry(spec, model: Constitutive, values: dict, names) -> dict:
    """fit.json's model entry: the law, its terms, the bulk term (fitted or the scene's K), μ0."""
    return {"name": model.law.model, "terms": model.law.terms, "bulk": "fit" if "K" in names else "fixed",
            "K": values["K"], "volumetric": spec.fe.get("volumetric") or "vlab neo-hookean",
            "mu0": model.law.mu0([values[n] for n in model.law.names])}


def _one_start() -> dict:
    """fit.json's starts entry of an FE-in-the-loop fit (one start, from fe.start)."""
    return {"count": 1, "reached_best": 1, "agree": True, "others_objective_ratio": None,
            "note": "FE-in-the-loop fits start once, from fe.start"}


def _identifiability(stats: dict, reasons, cond: float) -> dict:
    """Identifiable: no correlated pair, no undetermined constant, κ(J, unit-norm columns) ≤ unc.COND_LIMIT."""
    return {"identifiable": not stats["correlated_pairs"] and not reasons and cond <= unc.COND_LIMIT,
            "condition_number": cond, "correlated_pairs": stats["correlated_pairs"], "not_determined": reasons}


def _attach_figure(outcome, writer) -> None:
    """The specimen figure the fit report draws beside the closed-form ones."""
    outcome.extras["writers"] = [("specimen.png", writer)]
    outcome.extras["figures"] = [("specimen.png", "The specimen's readings (points) against vlab's own test at the "
                                  "fitted constants (line), each reading against its control.")]


def _fe_record(spec, prob, run, trail, homogeneous: dict) -> dict:
    """fit.json's fe entry: the scene, its solves (and how many came from the cache), the
    instruments' axes, factorization counts, where the solves ran and the homogeneous comparison."""
    return {"scene": spec.fe["scene_path"], "solves": prob.solves, "from_cache": prob.cached,
            "axes": ["xy"[a] for a in spec.fe["axes"]], "counts": prob.counts,
            "execution": {"dask": False} if run is None else run.describe(),
            "cache": spec.fe.get("cache"), "trail": trail, "homogeneous_fit": homogeneous}


def _specimen_stability(model, x, spec) -> dict:
    """Drucker stability of the FE-fitted card along the homogeneous paths, judged over the data:
    the paths and stretch ranges of each data set are its scene kind's (vlab.identify.fe_readings:
    an extension test's uniaxial stretches 1 + strain, a cruciform's also equibiaxial (its centre
    lies between those paths, not on either), torsion's surface shear as pure shear, the die's
    isochoric part, the inflated wall's equibiaxial stretch), said in ``basis``."""
    from vlab.identify.fe_readings import SPECIMEN_KINDS

    kind = SPECIMEN_KINDS[spec.fe["scene"].test.kind]
    ranges: dict = {}
    bases = []
    for d in (d for d in spec.datasets if d.kind == "specimen" and d.role == "fit"):
        paths, basis = kind.stability(d, spec.fe["scene_raw"])
        bases.append(basis)
        for path, (lo, hi) in paths.items():
            old = ranges.get(path, (lo, hi))
            ranges[path] = (min(old[0], lo), max(old[1], hi))
    kinds = {k: kind_stability(model, x, k, ranges.get(k)) for k in ("uniaxial", "equibiaxial", "planar")}
    judged = [v["stable_over_fitted_range"] for v in kinds.values() if "stable_over_fitted_range" in v]
    return {"kinds": kinds, "stable_over_all_fitted_ranges": bool(all(judged)),
            "basis": "; ".join(dict.fromkeys(bases))}


def _dataset_errors(sim, d) -> dict:
    """fit.json's row of a specimen data set: its errors at the fitted constants (both axes)."""
    _, _, Fi = residuals(sim, d, True)
    n = d.points
    rel = np.concatenate([_relative_error(Fi[:n], d.y[:n])]
                         + ([_relative_error(Fi[n:], d.y[n:])] if d.b is not None else []))
    return {"name": d.name, "file": d.file, "kind": "specimen", "role": d.role, "points": d.points,
            "rms_relative": float(np.sqrt(np.mean(rel ** 2))), "max_relative": float(np.max(np.abs(rel))),
            "rms_absolute_N": float(np.sqrt(np.mean((Fi - d.y) ** 2)))}


def _plot(spec, sim, J, cov, tq, path):
    """One panel per channel: the data's reading against its control (points) and vlab's test at
    the fitted constants (line)."""
    import matplotlib.pyplot as plt

    sets = [d for d in spec.datasets if d.kind == "specimen"]
    keys = channel_keys(sets[0])
    fig, axes = plt.subplots(1, len(keys), figsize=(6 * len(keys), 4.2), squeeze=False)
    for a, (control, reading) in enumerate(keys):
        ax = axes[0, a]
        for d in sets:
            n = d.points
            ax.plot(d.a if a == 0 else d.b, d.y[a * n:(a + 1) * n], "os"[a], ms=4, label=f"{d.name} ({d.role})")
        e0, F0 = UNSTRAINED.get(control, 0.0), UNSTRAINED.get(reading, 0.0)
        ax.plot(np.r_[e0, sim.strain[:, a]], np.r_[F0, sim.force[:, a]], "k-", lw=1.2,
                label="vlab test at the fitted constants")
        ax.set_xlabel(LABELS.get(control, control))
        ax.set_ylabel(LABELS.get(reading, reading))
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


LABELS = {"strain": "extensometer strain", "force": "force (N)", "strain2": "extensometer strain, axis y",
          "force2": "force, axis y (N)", "twist": "twist ψ (rad/mm)", "torque": "torque (N·mm)",
          "axial_force": "axial force (N)", "axial_stretch": "axial stretch", "stretch": "stretch",
          "stress": "axial nominal stress (MPa)", "volume_ratio": "volume ratio", "pole_height": "pole height (mm)",
          "pressure": "pressure (MPa)"}

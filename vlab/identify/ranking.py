"""Several models fitted to the same data, ranked on the worse of the fit and held-out errors.

The fit error of a model is the mean rms relative error over the data sets with role = "fit";
its held-out error the same over those with role = "validate" (predicted, never fitted). The
criterion is the worse of the two (the fit error alone without held-out data), so a model that
misses the data it was fitted to cannot rank first on its predictions, nor one that fits but
predicts badly; ties go to the lower BIC. A model that did not converge ranks after every one
that did, and a converged card that is not trustworthy (vlab.identify.fitting.trust_of: a constant
the data leave undetermined or on a bound, a card not Drucker-stable over the fitted ranges, or one
`vlab run` refuses) after every trustworthy one: such a card is never recommended first while a
usable one exists.
"""

from __future__ import annotations

import dataclasses
import html
from pathlib import Path

from vlab.identify.fitfile import FitSpec, parse_model_name
from vlab.identify.fitting import FitOutcome, fit_homogeneous
from vlab.identify.laws import law_for

__all__ = ["fit_models", "ranking_rows", "write_ranking"]


def spec_for(spec: FitSpec, text: str) -> FitSpec:
    """The fit spec with its model replaced by one named like "ogden-3" (bulk kept)."""
    name, terms = parse_model_name(text, "--models")
    return dataclasses.replace(spec, model=dataclasses.replace(spec.model, law=law_for(name, terms)))


def held_out_error(d: dict) -> float | None:
    errs = [x["rms_relative"] for x in d["datasets"] if x["role"] == "validate"]
    return sum(errs) / len(errs) if errs else None


def fit_error(d: dict) -> float:
    errs = [x["rms_relative"] for x in d["datasets"] if x["role"] == "fit"]
    return sum(errs) / len(errs)


def criterion(d: dict) -> float:
    """The ranking's error: the worse of the fit and the held-out error."""
    return max(fit_error(d), held_out_error(d) or 0.0)


def rank_key(d: dict) -> tuple:
    return (not d["converged"], not d["trust"]["trustworthy"], criterion(d), d["information"]["BIC"])


def fit_models(spec: FitSpec, names: list[str]) -> list[tuple[str, FitOutcome]]:
    """Each model's outcome, best first."""
    outs = [(n, fit_homogeneous(spec_for(spec, n))) for n in names]
    return sorted(outs, key=lambda no: rank_key(no[1].data))


def ranking_rows(ranked) -> list[dict]:
    rows = []
    for i, (name, o) in enumerate(ranked, 1):
        d = o.data
        rows.append({"rank": i, "model": name, "converged": d["converged"], "held_out_rms_relative":
                     held_out_error(d), "fit_rms_relative": fit_error(d), "criterion": criterion(d),
                     "trustworthy": d["trust"]["trustworthy"],
                     "fitted_rms_relative": {x["name"]: x["rms_relative"] for x in d["datasets"]},
                     "BIC": d["information"]["BIC"], "AIC": d["information"]["AIC"],
                     "parameters": d["parameters"], "identifiable": d["identifiability"]["identifiable"],
                     "stable_over_fitted_ranges": d["stability"]["stable_over_all_fitted_ranges"],
                     "starts_agree": d["starts"]["agree"], "fit_s": d["timing"]["fit_s"],
                     "evaluations": d["starts"]["evaluations"], "folder": name})
    return rows


def _page(name: str, rows: list[dict]) -> str:
    from vlab.report.html import _STYLE

    def f(v):
        return "—" if v is None else f"{100 * v:.3g} %" if isinstance(v, float) else html.escape(str(v))
    head = "".join(f"<th>{h}</th>" for h in ("rank", "model", "criterion (worse of the two)", "fit rms",
                                             "held-out rms", "rms per data set", "BIC", "identifiable",
                                             "Drucker-stable", "starts agree", "fit time"))
    body = "".join(
        f"<tr><td>{r['rank']}</td><td><a href='{r['folder']}/index.html'>{html.escape(r['model'])}</a></td>"
        f"<td>{f(r['criterion'])}</td><td>{f(r['fit_rms_relative'])}</td>"
        f"<td>{f(r['held_out_rms_relative'])}</td><td>"
        + ", ".join(f"{html.escape(k)} {f(v)}" for k, v in r["fitted_rms_relative"].items())
        + f"</td><td>{r['BIC']:.4g}</td><td>{r['identifiable']}</td><td>{r['stable_over_fitted_ranges']}</td>"
        f"<td>{r['starts_agree']}</td><td>{r['fit_s']:.3g} s</td></tr>" for r in rows)
    return (f"<!doctype html><html><head><meta charset='utf-8'><title>vlab fit — {html.escape(name)} ranking"
            f"</title><style>{_STYLE}</style></head><body><h1>{html.escape(name)}: models ranked</h1>"
            "<p>Ranked on the worse of the fit error (mean rms relative error of the data sets with role = "
            "\"fit\") and the held-out error (the same over role = \"validate\"), then BIC; a model that did "
            "not converge or whose card is not Drucker-stable over the fitted ranges ranks after every one "
            f"that is.</p><table><tr>{head}</tr>{body}</table>"
            "<figure><img src='models.png' style='max-width:100%'><figcaption>Every model against the data "
            "(filled: fitted; open orange: held out, predicted only).</figcaption></figure></body></html>")


def write_ranking(spec: FitSpec, ranked, out: Path, fit_text: str | None) -> list[dict]:
    from vlab.identify.plots import plot_models
    from vlab.identify.report import json_text, write_fit_files
    from vlab.report.folder import report_folder

    rows = ranking_rows(ranked)
    with report_folder(out, "fit-ranking") as tmp:
        for name, o in ranked:
            (tmp / name).mkdir()
            write_fit_files(o, tmp / name)
        (tmp / "ranking.json").write_text(json_text({"name": spec.name, "ranking": rows}))
        plot_models(spec, ranked, tmp / "models.png")
        (tmp / "index.html").write_text(_page(spec.name, rows), encoding="utf-8")
        if fit_text is not None:
            (tmp / "fit.toml").write_text(fit_text)
    return rows

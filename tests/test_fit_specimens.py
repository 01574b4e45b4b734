"""Several specimens of one material (data.specimen): a fit per specimen, the pooled fit, and the
statistics between specimens in fit.json → specimens; a single-specimen file fits as before."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from vlab.identify.fitfile import load_fit
from vlab.identify.fitting import fit_any
from vlab.identify.laws import law_for
from vlab.identify.specimens import between_statistics
from vlab.identify.states import Constitutive, response

ROOT = Path(__file__).resolve().parents[1]
MR = Constitutive(law_for("mooney-rivlin"))
CARDS = {"A": (0.30, 0.050), "B": (0.31, 0.055), "C": (0.29, 0.045)}  # (C10, C01) MPa: sd 0.01, 0.005
STRETCH = np.linspace(1.05, 3.0, 25)


def _write_specimens(tmp_path: Path, cards=CARDS, noise=0.005, seed=7, name_specimens=True) -> Path:
    """One uniaxial CSV per card (relative Gaussian noise) and the fit file naming each specimen;
    99.9 % intervals, so that all six (3 specimens × 2 constants) hold their card in all but about
    0.6 % of seeds (at 95 % it would be about 1 in 4 that misses one)."""
    rng = np.random.default_rng(seed)
    toml = 'name = "s"\n[model]\nname = "mooney-rivlin"\n[options]\nstarts = 6\nconfidence = 0.999\n'
    for s, card in cards.items():
        x = np.linalg.solve(MR.transform, np.asarray(card, float))
        P = np.real(response(MR, x[None], "uniaxial", STRETCH, None))[0] * (1 + noise * rng.standard_normal(len(STRETCH)))
        (tmp_path / f"{s}.csv").write_text("lambda,P\n" + "".join(f"{float(a)!r},{float(p)!r}\n" for a, p in zip(STRETCH, P)))
        toml += (f'[[data]]\nfile = "{s}.csv"\nkind = "uniaxial"\ncolumns = {{ stretch = "lambda", stress = "P" }}\n'
                 + (f'specimen = "{s}"\n' if name_specimens else ""))
    f = tmp_path / "fit.toml"
    f.write_text(toml)
    return f


def test_three_specimens_recover_their_cards_and_their_spread(tmp_path):
    """Each specimen's fit holds its generating card inside its 99.9 % interval; the mean and sample
    standard deviation of the fitted constants match the cards' (C10: 0.30, 0.01; C01: 0.050,
    0.005) to within 3 × the largest specimen standard error / √3 (mean) and 3 × it (sd), and the
    pooled constants lie between the specimens' smallest and largest."""
    d = fit_any(load_fit(_write_specimens(tmp_path))).data
    sp = d["specimens"]
    assert sp["n"] == 3 and sp["ids"] == ["A", "B", "C"]
    for k, j in (("C10", 0), ("C01", 1)):
        for s, card in CARDS.items():
            c = sp["per_specimen"][s]["constants"][k]
            assert c["interval"][0] <= card[j] <= c["interval"][1], (s, k, c)
        truth = np.array([c[j] for c in CARDS.values()])
        st = sp["statistics"][k]
        se = max(sp["per_specimen"][s]["constants"][k]["standard_error"] for s in CARDS)
        assert st["n"] == 3
        assert abs(st["mean"] - truth.mean()) <= 3 * se / np.sqrt(3), (k, st, se)
        assert abs(st["standard_deviation"] - truth.std(ddof=1)) <= 3 * se, (k, st, se)
        assert st["coefficient_of_variation"] == pytest.approx(st["standard_deviation"] / abs(st["mean"]))
        assert st["min"] < d["parameters"][k] < st["max"] and st["pooled_within_range"]
        assert st["pooled"] == d["uncertainty"][k]["value"]
    assert [r["specimen"] for r in d["datasets"]] == ["A", "B", "C"]


def test_a_file_without_specimens_or_with_one_fits_as_before(tmp_path):
    one = {"A": CARDS["A"]}
    plain = fit_any(load_fit(_write_specimens(tmp_path, one, name_specimens=False))).data
    named = fit_any(load_fit(_write_specimens(tmp_path, one))).data
    assert "specimens" not in plain
    assert named["specimens"]["n"] == 1 and named["specimens"]["statistics"] is None
    assert "between-specimen statistics" in named["specimens"]["reason"]
    assert named["parameters"] == plain["parameters"] and named["uncertainty"] == plain["uncertainty"]


def test_between_statistics_are_null_with_a_reason_where_undefined():
    one = between_statistics([0.3], 0.3)
    assert one["n"] == 1 and one["mean"] == 0.3 and one["standard_deviation"] is None
    assert one["coefficient_of_variation"] is None and "n = 1" in one["reason"]
    zero = between_statistics([-0.1, 0.1], 0.0)
    assert zero["standard_deviation"] == pytest.approx(np.sqrt(0.02)) and zero["coefficient_of_variation"] is None
    assert "mean = 0" in zero["reason"]
    none = between_statistics([], None)
    assert none["n"] == 0 and none["mean"] is None and none["reason"]
    three = between_statistics([0.30, 0.31, 0.29], 0.30)
    assert three["mean"] == pytest.approx(0.30) and three["standard_deviation"] == pytest.approx(0.01)
    assert three["coefficient_of_variation"] == pytest.approx(0.01 / 0.30) and three["reason"] is None


def _cli(*args, cwd):
    return subprocess.run([sys.executable, "-m", "vlab", "fit", *map(str, args)], capture_output=True, text=True,
                          cwd=cwd, timeout=300)


@pytest.mark.parametrize("edit,needle", [
    (lambda t: t.replace('specimen = "A"', "specimen = 3"), "data[0].specimen must be a specimen id"),
    (lambda t: t.replace('specimen = "A"', 'specimen = ""'), "data[0].specimen must be a specimen id"),
    (lambda t: t.replace('specimen = "B"', 'specimen = " B"'), "data[1].specimen must be a printable id"),
    (lambda t: t.replace('specimen = "C"\n', ""), "data[2] ('C') names no specimen"),
    (lambda t: t.replace('kind = "uniaxial"\ncolumns = { stretch = "lambda", stress = "P" }\nspecimen = "C"',
                         'kind = "uniaxial"\ncolumns = { stretch = "lambda", stress = "P" }\nspecimen = "C"\n'
                         'role = "validate"'), "specimen 'C' has no data set with role = \"fit\""),
])
def test_bad_specimens_are_refused_naming_the_field_exit_2_nothing_written(tmp_path, edit, needle):
    f = _write_specimens(tmp_path)
    f.write_text(edit(f.read_text()))
    r = _cli(f, "--out", tmp_path / "out", cwd=tmp_path)
    assert r.returncode == 2, r.stdout + r.stderr
    assert needle in " ".join(r.stderr.split()) and "Traceback" not in r.stdout + r.stderr
    assert not (tmp_path / "out").exists()


def test_models_ranking_of_several_specimens_is_refused(tmp_path):
    r = _cli(_write_specimens(tmp_path), "--models", "neo-hookean,mooney-rivlin", "--out", tmp_path / "o", cwd=tmp_path)
    assert r.returncode == 2 and "several specimens" in " ".join(r.stderr.split())
    assert not (tmp_path / "o").exists()


def test_shipped_example_console_page_and_strict_json_say_the_same(tmp_path):
    out = tmp_path / "out"
    r = _cli(ROOT / "specimens/records/specimens.fit.toml", "--out", out, cwd=tmp_path)
    assert r.returncode == 0, r.stdout + r.stderr
    d = json.loads((out / "fit.json").read_text(), parse_constant=lambda c: pytest.fail(f"non-strict JSON {c}"))
    sp = d["specimens"]
    assert sp["n"] == 3 and sp["figure"] == "specimens.png" and (out / "specimens.png").exists()
    shipped = {"A": (0.30, 0.050), "B": (0.31, 0.055), "C": (0.29, 0.045)}  # make_records.SPECIMENS
    for s, card in shipped.items():
        for k, v in zip(("C10", "C01"), card):
            lo, hi = sp["per_specimen"][s]["constants"][k]["interval"]
            assert lo <= v <= hi, (s, k, lo, hi)
    page = (out / "index.html").read_text()
    text = " ".join(r.stdout.split())  # the fit's summary is a result: stdout
    assert "<h2>Specimens</h2>" in page and "specimens.png" in page
    for k, st in sp["statistics"].items():
        cv = f"{100 * st['coefficient_of_variation']:.3g} %"
        assert f"{k}: mean {st['mean']:.4g}, sd {st['standard_deviation']:.3g}, cv {cv}, n 3" in text
        assert f"<td>{k}</td><td>{st['mean']:.5g}</td><td>{st['standard_deviation']:.3g}</td><td>{cv}</td>" in page


# --- records: the band of the specimens' fits run over a reference history ------------------------
def test_the_records_band_is_each_specimens_model_over_the_first_record():
    import dataclasses
    from types import SimpleNamespace

    from vlab.identify.datasets import Dataset
    from vlab.identify.fitfile import FitSpec
    from vlab.identify.records.prony import PronySpec, history_stress
    from vlab.identify.specimens import record_band_panels

    nh, prony = Constitutive(law_for("neo-hookean")), PronySpec(1)
    t = np.r_[np.arange(1, 11) / 10, 1.0 + np.geomspace(0.1, 30.0, 12)]
    lam = 1.0 + 0.5 * np.minimum(t, 1.0)
    xs = {"A": np.r_[0.55, 0.4, 2.0], "B": np.r_[0.60, 0.5, 3.0], "C": np.r_[0.65, 0.3, 1.0]}
    truth = {s: np.real(history_stress(nh, prony, x[None], "uniaxial", t, lam)[0]) for s, x in xs.items()}
    sets = tuple(dataclasses.replace(Dataset(s, f"{s}.csv", "relaxation", "fit", 1.0, "nominal", t * (1 + i), lam,
                                             truth[s], extra={"test": "uniaxial"}), specimen=s)
                 for i, s in enumerate(xs))
    spec = FitSpec("r", nh, sets, effects={"viscoelastic": prony})
    fit = lambda x: SimpleNamespace(spec=spec, x=x, converged=True)  # noqa: E731
    panels = record_band_panels(fit(np.r_[0.6, 0.4, 2.0]), spec, {s: fit(x) for s, x in xs.items()})
    (p,) = panels
    assert p["kind"] == "relaxation" and p["xlabel"] == "time (s)" and np.array_equal(p["a"], t)
    on_ref = {s: np.real(history_stress(nh, prony, x[None], "uniaxial", t, lam)[0]) for s, x in xs.items()}
    assert np.allclose(p["lo"], np.min(list(on_ref.values()), axis=0), rtol=1e-14)
    assert np.allclose(p["hi"], np.max(list(on_ref.values()), axis=0), rtol=1e-14)
    assert [s for s, _, _ in p["data"]] == ["A", "B", "C"]
    assert np.array_equal(p["data"][1][1], 2 * t)  # each record against its own time


def test_the_shipped_relaxation_specimens_draw_their_band(tmp_path):
    out = tmp_path / "o"
    fit = ROOT / "specimens" / "records" / "specimens-relaxation.fit.toml"
    res = subprocess.run([sys.executable, "-m", "vlab", "fit", str(fit), "--out", str(out)], capture_output=True,
                         text=True)
    assert res.returncode == 0, res.stderr
    sp = json.loads((out / "fit.json").read_text())["specimens"]
    assert sp["figure"] == "specimens.png" and sp["figure_reason"] is None and (out / "specimens.png").exists()
    assert "specimens.png" in (out / "index.html").read_text()


def test_the_records_band_of_cycles_without_time_and_of_dma_sweeps():
    import dataclasses
    from types import SimpleNamespace

    from vlab.identify.datasets import Dataset
    from vlab.identify.fitfile import FitSpec
    from vlab.identify.records.cyclic import stress_along
    from vlab.identify.records.prony import PronySpec, dynamic_moduli
    from vlab.identify.records.softening import MullinsSpec
    from vlab.identify.specimens import record_band_panels

    nh = Constitutive(law_for("neo-hookean"))
    lam = np.r_[np.linspace(1.1, 2.0, 10), np.linspace(1.9, 1.0, 10)]
    xs = {"A": np.r_[0.55, 2.0, 0.3, 0.1], "B": np.r_[0.65, 1.5, 0.2, 0.0]}
    mullins = {"mullins": MullinsSpec()}
    cyc = lambda x: np.real(stress_along(nh, mullins, x[None], "uniaxial", lam)[0])  # noqa: E731
    extra = {"test": "uniaxial", "stretch": lam, "time": None, "mask": np.ones(len(lam), bool), "branch": "all"}
    sets = tuple(dataclasses.replace(Dataset(s, f"{s}.csv", "cyclic", "fit", 1.0, "nominal", lam, None, cyc(x),
                                             extra=extra), specimen=s) for s, x in xs.items())
    spec = FitSpec("c", nh, sets, effects=mullins)
    fit = lambda x: SimpleNamespace(spec=spec, x=x, converged=True)  # noqa: E731
    (p,) = record_band_panels(fit(xs["A"]), spec, {s: fit(x) for s, x in xs.items()})
    assert p["xlabel"] == "row of the history" and np.array_equal(p["a"], np.arange(1, 21))
    assert np.allclose(p["lo"], np.minimum(cyc(xs["A"]), cyc(xs["B"])), rtol=1e-14)

    prony = {"viscoelastic": PronySpec(1)}
    f = np.geomspace(0.1, 10.0, 7)
    xd = {"A": np.r_[0.5, 0.4, 0.3], "B": np.r_[0.6, 0.2, 1.0]}
    sl = {s: dynamic_moduli(nh, PronySpec(1), x[None], f, "tensile") for s, x in xd.items()}
    sets = tuple(dataclasses.replace(Dataset(s, f"{s}.csv", "dma", "fit", 1.0, "nominal", f, None,
                                             np.r_[sl[s][0][0], sl[s][1][0]], extra={"modulus": "tensile"}),
                                     specimen=s) for s in xd)
    spec = FitSpec("d", nh, sets, effects=prony)
    fit = lambda x: SimpleNamespace(spec=spec, x=x, converged=True)  # noqa: E731
    storage, loss = record_band_panels(fit(xd["A"]), spec, {s: fit(x) for s, x in xd.items()})
    assert storage["log_x"] and storage["ylabel"] == "storage modulus (MPa)" and loss["ylabel"] == "loss modulus (MPa)"
    assert np.allclose(storage["hi"], np.maximum(sl["A"][0][0], sl["B"][0][0]), rtol=1e-14)
    assert np.allclose(loss["lo"], np.minimum(sl["A"][1][0], sl["B"][1][0]), rtol=1e-14)
    assert np.allclose(loss["data"][1][2], sl["B"][1][0], rtol=1e-14)

"""The viscoelastic (Prony) and Mullins (Ogden–Roxburgh) parts of exported cards.

Oracles: the test reads each written file with its own parser and codes the target's relaxation
and damage functions as its manual writes them (not vlab's classes):

- Abaqus *VISCOELASTIC, TIME=PRONY with MODULI=LONG TERM: g_R(t) = 1 − Σ gᵢ (1 − e^(−t/τᵢ)),
  the long-term constants are the hyperelastic ones, so μ(t) = 2 C10 g_R(t)/g_R(∞);
- ANSYS TB,PRONY SHEAR over TB,HYPER (instantaneous constants): μ(t) = 2 c10 (α∞ + Σ αᵢ e^(−t/τᵢ));
- FEBio uncoupled viscoelastic: μ(t) = 2 c1 (g0 + Σ gᵢ e^(−t/tᵢ));
- Abaqus *MULLINS EFFECT and ANSYS TB,CDM PSE2: η = 1 − erf((U_m − U)/(m + β U_m))/r with U
  the deviatoric energy C10 (I1 − 3) of the file's constants.

and compares, for a held uniaxial stretch λ (J = 1), σ11 − σ22 = μ(t)(λ² − 1/λ) (Neo-Hookean
ground, step at t = 0) and, after loading to λ_max, η × the file's ground stress on unloading,
with vlab's own history materials (vlab.materials.viscoelastic, vlab.materials.mullins) run on
vlab's card: 1e-9 relative. Round trips return every constant to 1e-12.
"""

from __future__ import annotations

import json
import math
import re
import xml.etree.ElementTree as ET
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from vlab.cli import app
from vlab.export import EXPORTERS
from vlab.export.card import card_from_table, with_parts
from vlab.export.command import card_text
from vlab.export.header import UNITS
from vlab.export.registry import refusal
from vlab.materials.card import build_material, parse_material
from vlab.materials.mullins import OgdenRoxburgh
from vlab.materials.viscoelastic import PronyViscoelastic

runner = CliRunner()
ROOT = Path(__file__).resolve().parents[1]
PRONY = {"tau": [0.37, 4.1, 55.0], "beta": [0.61, 0.25, 0.093]}
MULLINS = {"r": 1.83, "m": 0.217, "beta": 0.14}
TIMES = (0.0, 0.05, 0.4, 3.0, 20.0, 200.0)
STRETCHES = (0.6, 1.3, 2.0, 3.5)
GROUNDS = {"nh-fit": {"model": "neo-hookean", "mu": 0.58, "K": 580.0},  # an incompressible fit's card
           "mr-fit": {"model": "mooney-rivlin", "C10": 0.29, "C01": 0.0, "K": 580.0}}


def _card(ground: str, parts: dict, stand_in: bool = True):
    return with_parts(card_from_table(dict(GROUNDS[ground]), ground, stand_in=stand_in), parts, ground)


# --- each target's file, read by the test --------------------------------------------------
def _abaqus(text: str) -> dict:
    blocks, cur = {}, None
    for line in text.splitlines():
        if not line.strip() or line.startswith("**"):
            continue
        if line.startswith("*"):
            cur = line[1:].split(",")[0].strip().upper()
            blocks[cur] = {"head": line.upper(), "rows": []}
        else:
            blocks[cur]["rows"].append([float(x) for x in line.split(",")])
    assert "MODULI=LONG TERM" in blocks["HYPERELASTIC"]["head"] or "VISCOELASTIC" not in blocks
    out = {"C10": blocks["HYPERELASTIC"]["rows"][0][0]}
    if "VISCOELASTIC" in blocks:
        g = [r[0] for r in blocks["VISCOELASTIC"]["rows"]]
        tau = [r[2] for r in blocks["VISCOELASTIC"]["rows"]]
        assert all(r[1] == 0.0 for r in blocks["VISCOELASTIC"]["rows"])
        g_R = lambda t: 1 - sum(gi * (1 - math.exp(-t / ti)) for gi, ti in zip(g, tau))  # noqa: E731
        out["mu_t"] = lambda t: 2 * out["C10"] * g_R(t) / (1 - sum(g))
    if "MULLINS EFFECT" in blocks:
        out["mullins"] = blocks["MULLINS EFFECT"]["rows"][0]
    return out


def _ansys(text: str) -> dict:
    tables, cur = {}, None
    for line in text.splitlines():
        if line.startswith("TB,"):
            f = line.split(",")
            cur = f[1]
            tables[cur] = {"opt": f[5], "data": {}}
        elif line.startswith("TBDATA,"):
            f = line.split(",")
            for k, x in enumerate(f[2:]):
                tables[cur]["data"][int(f[1]) + k] = float(x)
    out = {"C10": tables["HYPER"]["data"][1]}
    if "PRONY" in tables:
        assert tables["PRONY"]["opt"] == "SHEAR"
        d = tables["PRONY"]["data"]
        a, tau = [d[i] for i in range(1, len(d) + 1, 2)], [d[i] for i in range(2, len(d) + 1, 2)]
        out["mu_t"] = lambda t: 2 * out["C10"] * (1 - sum(a) + sum(ai * math.exp(-t / ti) for ai, ti in zip(a, tau)))
    if "CDM" in tables:
        assert tables["CDM"]["opt"] == "PSE2"
        out["mullins"] = [tables["CDM"]["data"][i] for i in (1, 2, 3)]
    return out


def _febio(text: str) -> dict:
    el = ET.fromstring(text).find(".//material")
    base = el.find("elastic")
    out = {"C10": float(base.find("c1").text)}
    assert float(base.find("c2").text) == 0.0
    g0 = float(el.find("g0").text)
    terms = [(float(el.find(f"g{i}").text), float(el.find(f"t{i}").text)) for i in range(1, 7)
             if el.find(f"g{i}") is not None]
    out["mu_t"] = lambda t: 2 * out["C10"] * (g0 + sum(g * math.exp(-t / tt) for g, tt in terms))
    return out


READ = {"abaqus": _abaqus, "ansys": _ansys, "febio": _febio}


def _eta(row, U, Um):
    r, m, beta = row
    return 1 - math.erf((Um - U) / (m + beta * Um)) / r


def _uniaxial(lam):
    return np.diag([lam, lam ** -0.5, lam ** -0.5])[:, :, None]


def _difference(P, F):
    sigma = np.einsum("ijk,ljk->il", P, F)  # σ = P Fᵀ (J = 1)
    return sigma[0, 0] - sigma[1, 1]


def _ground(card):
    from vlab.export.card import material_table

    return build_material(parse_material(material_table(card)))


# --- oracles ------------------------------------------------------------------------------
@pytest.mark.parametrize("ground", tuple(GROUNDS))
@pytest.mark.parametrize("target", ("abaqus", "ansys", "febio"))
def test_the_targets_relaxation_function_is_vlabs_under_a_held_stretch(ground, target):
    card = _card(ground, {"viscoelastic": PRONY})
    got = READ[target](card_text(card, target, UNITS["mm"]))
    law = PronyViscoelastic(_ground(card), tau=tuple(PRONY["tau"]), beta=tuple(PRONY["beta"]))
    mu0 = card.mu0
    dt0 = 1e-13  # the step from rest: the midpoint rule dates it at dt0/2
    for lam in STRETCHES:
        F = _uniaxial(lam)
        state = law.update(F, law.initial_state((1,)), dt0)
        t_prev = dt0 / 2
        for t in TIMES[1:]:
            P = law.respond(F, state, t - t_prev, with_tangent=False).stress
            state = law.update(F, state, t - t_prev)
            t_prev = t
            vlab_diff = _difference(P, F)
            target_diff = got["mu_t"](t) * (lam ** 2 - 1 / lam)
            assert abs(vlab_diff / target_diff - 1) < 1e-9, (lam, t, vlab_diff, target_diff)
            closed = mu0 * (1 + sum(b * math.exp(-t / tt) for b, tt in zip(PRONY["beta"], PRONY["tau"])))
            assert abs(got["mu_t"](t) / closed - 1) < 1e-12


@pytest.mark.parametrize("ground", tuple(GROUNDS))
@pytest.mark.parametrize("target", ("abaqus", "ansys"))
def test_the_targets_damage_function_is_vlabs_on_unloading(ground, target):
    card = _card(ground, {"mullins": MULLINS})
    got = READ[target](card_text(card, target, UNITS["mm"]))
    law = OgdenRoxburgh(_ground(card), **MULLINS)
    C10 = got["C10"]
    U = lambda lam: C10 * (lam ** 2 + 2 / lam - 3)  # noqa: E731  deviatoric energy at J = 1
    for lam_max in (1.5, 2.5, 4.0):
        state = law.update(_uniaxial(lam_max), law.initial_state((1,)), 0.0)
        for lam in np.linspace(0.7, lam_max, 7):
            F = _uniaxial(lam)
            vlab_diff = _difference(law.respond(F, state, 0.0, with_tangent=False).stress, F)
            target_diff = _eta(got["mullins"], U(lam), U(lam_max)) * 2 * C10 * (lam ** 2 - 1 / lam)
            assert abs(vlab_diff - target_diff) <= 1e-9 * abs(target_diff) + 1e-15, (lam_max, lam)
            assert abs(law.softening(U(lam), U(lam_max))[()] - _eta(got["mullins"], U(lam), U(lam_max))) < 1e-12


# --- round trips ---------------------------------------------------------------------------
ROUND = [("abaqus", {"viscoelastic": PRONY}), ("abaqus", {"mullins": MULLINS}), ("ansys", {"viscoelastic": PRONY}),
         ("ansys", {"mullins": MULLINS}), ("febio", {"viscoelastic": PRONY})]


@pytest.mark.parametrize("target,parts", ROUND)
@pytest.mark.parametrize("units", ("mm", "SI"))
def test_export_then_import_returns_the_parts_to_1e_12(target, parts, units):
    card = _card("mr-fit", parts)
    back = EXPORTERS[target].read(card_text(card, target, UNITS[units]), "card", UNITS[units])
    assert back.model == "mooney-rivlin" and back.parts == card.parts
    assert abs(back.params["C10"] / card.params["C10"] - 1) < 1e-12 and back.params["C01"] == 0.0
    assert abs(back.K / card.K - 1) < 1e-12
    for part, table in parts.items():
        for key, want in table.items():
            for a, b in zip(np.atleast_1d(back.effects[part][key]), np.atleast_1d(want)):
                assert abs(a - b) <= 1e-12 * abs(b), (part, key, a, b)


def test_an_incompressible_neo_hookean_fit_is_written_as_the_split_neo_hooke():
    card = _card("nh-fit", {"viscoelastic": PRONY})
    text = card_text(card, "abaqus", UNITS["mm"])
    assert "*HYPERELASTIC, MOONEY-RIVLIN, MODULI=LONG TERM" in text and "form: vlab's incompressible" in text
    assert abs(_abaqus(text)["C10"] - 0.29) < 1e-15
    # the same card with a K of its own (not a stand-in) is vlab's coupled law: Abaqus has no such card
    assert refusal("abaqus", replace(card, stand_in=False)) is not None


# --- refusals --------------------------------------------------------------------------------
def test_targets_without_the_part_refuse_and_name_those_that_have_it():
    ve, mu = _card("mr-fit", {"viscoelastic": PRONY}), _card("mr-fit", {"mullins": MULLINS})
    for target in ("calculix", "lsdyna", "felupe"):
        assert "targets that write it exactly: abaqus, ansys, febio" in refusal(target, ve)
        assert "targets that write it exactly: abaqus, ansys" in refusal(target, mu)
    assert "febio has no mullins part" in refusal("febio", mu)


@pytest.mark.parametrize("table,parts,why", [
    ({"model": "mooney-rivlin", "C10": 0.29, "C01": 0.04, "K": 580.0}, {"viscoelastic": PRONY}, "Neo-Hookean ground"),
    ({"model": "yeoh", "C10": 0.29, "C20": -0.01, "C30": 0.001, "K": 580.0}, {"viscoelastic": PRONY}, "Neo-Hookean"),
    ({"model": "ogden", "mu": [0.29], "alpha": [2.5], "K": 580.0}, {"viscoelastic": PRONY}, "Neo-Hookean"),
    (GROUNDS["mr-fit"], {"viscoelastic": PRONY, "mullins": MULLINS}, "both"),
])
def test_a_part_that_is_not_the_targets_model_is_refused_everywhere(table, parts, why):
    card = with_parts(card_from_table(dict(table), "t", stand_in=True), parts, "t")
    for target in EXPORTERS:
        msg = refusal(target, card)
        assert msg is not None and "no target writes this card exactly" in msg
    assert why in refusal("abaqus", card)


def test_deviatoric_only_parts_need_j_1_and_febio_is_vlabs_at_any_j():
    mr = {"model": "mooney-rivlin", "C10": 0.29, "C01": 0.0, "K": 80.0}
    ve = with_parts(card_from_table(dict(mr), "t"), {"viscoelastic": PRONY}, "t")
    mu = with_parts(card_from_table(dict(mr), "t"), {"mullins": MULLINS}, "t")
    for target in ("abaqus", "ansys"):
        assert "J = 1" in refusal(target, ve) and "J = 1" in refusal(target, mu)
    log_ve = with_parts(card_from_table(dict(mr, volumetric="log"), "t"), {"viscoelastic": PRONY}, "t")
    assert refusal("febio", log_ve) is None
    many = with_parts(card_from_table(dict(mr, volumetric="log"), "t"),
                      {"viscoelastic": {"tau": [1.0 * i for i in range(1, 8)], "beta": [0.1] * 7}}, "t")
    assert "at most 6 Prony terms" in refusal("febio", many)


def test_export_command_refuses_without_writing(tmp_path):
    scene = tmp_path / "card.toml"
    scene.write_text('# incompressible fit\n[material]\nmodel = "mooney-rivlin"\nC10 = 0.3\nC01 = 0.0\nK = 300.0\n'
                     "[effects.mullins]\nr = 2.0\nm = 0.3\n")
    out = tmp_path / "x.feb"
    res = runner.invoke(app, ["export", str(scene), "--to", "febio", "--out", str(out)])
    assert res.exit_code == 2 and "abaqus, ansys" in res.output and not out.exists()
    res = runner.invoke(app, ["export", str(scene), "--to", "abaqus", "--out", str(tmp_path / "a.inp")])
    assert res.exit_code == 0, res.output
    assert "*MULLINS EFFECT\n2.0000000000000000e+00, 2.9999999999999999e-01, 0.0000000000000000e+00" in (
        tmp_path / "a.inp").read_text()


# --- malformed parts name their line ----------------------------------------------------------
MALFORMED = [
    ("a.inp", "*HYPERELASTIC, MOONEY-RIVLIN, MODULI=INSTANTANEOUS\n0.3, 0.0, 0.01\n", "line 1", "MODULI=INSTANTANEOUS"),
    ("a.inp", "*HYPERELASTIC, MOONEY-RIVLIN\n0.3, 0.0, 0.01\n*VISCOELASTIC, TIME=PRONY\n0.2, 0.1, 1.0\n", "line 4",
     "k = 0.1"),
    ("a.inp", "*HYPERELASTIC, MOONEY-RIVLIN\n0.3, 0.0, 0.01\n*VISCOELASTIC, FREQUENCY=PRONY\n0.2, 0.0, 1.0\n",
     "line 3", "TIME=PRONY only"),
    ("a.inp", "*HYPERELASTIC, MOONEY-RIVLIN\n0.3, 0.0, 0.01\n*MULLINS EFFECT\n0.5, 0.3\n", "", "effects.mullins.r"),
    ("a.mac", "TB,HYPER,1,1,2,MOONEY\nTBDATA,1,0.3,0,0.01\nTB,PRONY,1,1,1,BULK\nTBDATA,1,0.2,1.0\n", "line 3", "SHEAR"),
    ("a.inp", "*HYPERELASTIC, OGDEN, N=1\n0.3, 2.5, 0.01\n*VISCOELASTIC, TIME=PRONY\n0.2, 0.0, 1.0\n", "a.inp",
     "Neo-Hookean ground"),
    ("a.mac", "TB,HYPER,1,1,2,MOONEY\nTBDATA,1,0.3,0,0.01\nTB,CDM,1,1,3,PSE1\nTBDATA,1,2,0.3,0\n", "line 3", "PSE2"),
]


@pytest.mark.parametrize("name,text,line,what", MALFORMED)
def test_a_malformed_part_is_named_and_exits_2(tmp_path, name, text, line, what):
    src = tmp_path / name
    src.write_text(text)
    res = runner.invoke(app, ["import-card", str(src), "--out", str(tmp_path / "c.toml")])
    assert res.exit_code == 2 and line in res.output and what in res.output, res.output
    assert not (tmp_path / "c.toml").exists()


def test_an_imported_deviatoric_only_part_says_it_is_vlabs_at_j_1(tmp_path):
    src = tmp_path / "a.inp"
    src.write_text(card_text(_card("mr-fit", {"mullins": MULLINS}), "abaqus", UNITS["mm"]))
    out = tmp_path / "c.toml"
    res = runner.invoke(app, ["import-card", str(src), "--out", str(out)])
    assert res.exit_code == 0, res.output
    text = out.read_text()
    assert "the same model at J = 1" in text.splitlines()[1] and "[effects.mullins]" in text


# --- vlab fit --export writes the parts -------------------------------------------------------
@pytest.mark.parametrize("fitfile,part,targets", [("relaxation.fit.toml", "viscoelastic", ("abaqus", "ansys", "febio")),
                                                   ("cycles.fit.toml", "mullins", ("abaqus", "ansys"))])
def test_a_fit_of_records_exports_its_parts_to_abaqus(tmp_path, fitfile, part, targets):
    out = tmp_path / "fit"
    res = runner.invoke(app, ["fit", str(ROOT / "specimens" / "records" / fitfile), "--out", str(out),
                              "--export", ",".join(targets)])
    assert res.exit_code == 0, res.output
    fitted = json.loads((out / "fit.json").read_text())["card"]["effects"][part]
    for target in targets:
        back = EXPORTERS[target].read((out / "cards" / EXPORTERS[target].default_file).read_text(), "c", UNITS["mm"])
        for key, want in fitted.items():
            for a, b in zip(np.atleast_1d(back.effects[part][key]), np.atleast_1d(want)):
                assert abs(a - b) <= 1e-12 * abs(b)
    text = (out / "cards" / "abaqus.inp").read_text()
    assert ("*VISCOELASTIC, TIME=PRONY" if part == "viscoelastic" else "*MULLINS EFFECT") in text
    assert re.search(r"\*HYPERELASTIC, MOONEY-RIVLIN", text)

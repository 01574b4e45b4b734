"""vlab export / import-card: round trips, refusals, malformed cards, files, fit --export."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from export_cases import LABELS, PAIRS, REFUSED, TABLES, TARGETS, base_card, card_for
from vlab.cli import app
from vlab.export import EXPORTERS
from vlab.export.header import UNITS
from vlab.identify.card import card_toml

runner = CliRunner()
ROOT = Path(__file__).resolve().parents[1]


def _flat(card) -> dict:
    out = {}
    for k, v in card.params.items():
        for i, x in enumerate(v if isinstance(v, tuple) else (v,)):
            out[f"{k}[{i}]"] = float(x)
    if card.K is not None:
        out["K"] = card.K
    if card.density is not None:
        out["density"] = card.density
    return out


def _close(a: dict, b: dict, rtol: float = 1e-12) -> None:
    assert a.keys() == b.keys()
    for k in a:
        assert abs(a[k] - b[k]) <= rtol * max(abs(a[k]), abs(b[k])) + 1e-300, (k, a[k], b[k])


@pytest.mark.parametrize("label,target", PAIRS)
@pytest.mark.parametrize("units", ["mm", "SI"])
def test_export_then_import_returns_the_constants_to_1e_12(label, target, units):
    card = card_for(label, target)
    text = EXPORTERS[target].write(card, UNITS[units])
    back = EXPORTERS[target].read(text, f"{target}-card", UNITS[units])
    assert back.model == card.model
    _close(_flat(card), _flat(back))
    if not card.stand_in:
        assert back.volumetric == card.volumetric


@pytest.mark.parametrize("label,target", PAIRS)
def test_a_card_carries_its_header_and_at_least_12_significant_digits(label, target):
    card = card_for(label, target)
    text = EXPORTERS[target].write(card, UNITS["mm"])
    assert "vlab material card" in text and "convention: " in text and "follows: " in text
    assert "units: N, mm, MPa, s, t/mm³" in text and "source: " in text
    mantissas = re.findall(r"-?\d\.(\d+)[eE][-+]\d+", text)
    assert mantissas and min(len(m) for m in mantissas) >= 11  # d.ddddddddddd: ≥ 12 significant digits


def _export(tmp_path, source, target, *extra):
    out = tmp_path / f"card.{target}"
    res = runner.invoke(app, ["export", str(source), "--to", target, "--out", str(out), *extra])
    return res, out


def _card_file(tmp_path, table, name="card.toml", comment=""):
    path = tmp_path / name
    path.write_text(comment + card_toml(table))
    return path


@pytest.mark.parametrize("label,target", REFUSED)
def test_an_unsupported_pair_exits_2_naming_where_it_is_supported_and_writes_nothing(tmp_path, label, target):
    table = dict(TABLES[label])
    res, out = _export(tmp_path, _card_file(tmp_path, table), target)
    assert res.exit_code == 2, res.output
    assert not out.exists()
    assert "cannot export" in res.output
    card = base_card(label, density=None)
    from vlab.export.registry import supporting

    where = supporting(card)
    assert ("targets that write it exactly: " + ", ".join(where)) in res.output if where else \
        "no target writes" in res.output


def test_a_volumetric_form_a_target_lacks_is_refused_naming_the_targets_that_have_it(tmp_path):
    table = TABLES["mooney-rivlin"] | {"volumetric": "log"}  # FEBio's U, not Abaqus'
    res, out = _export(tmp_path, _card_file(tmp_path, table), "abaqus")
    assert res.exit_code == 2 and not out.exists()
    assert "(J − 1)²/D1" not in res.output or "volumetric" in res.output
    assert "targets that write it exactly: febio, felupe" in res.output


def test_an_incompressible_fits_stand_in_k_is_written_with_the_targets_u_and_said_so(tmp_path):
    src = _card_file(tmp_path, TABLES["ogden-3"], comment="# incompressible fit: K = 1000 mu0 stands in\n")
    for target in ("abaqus", "febio", "lsdyna"):
        res, out = _export(tmp_path, src, target)
        assert res.exit_code == 0, res.output
        assert "incompressible fit's stand-in" in out.read_text()


def test_export_refuses_to_replace_a_file_vlab_did_not_write(tmp_path):
    src = _card_file(tmp_path, TABLES["yeoh"])
    out = tmp_path / "card.abaqus"
    out.write_text("my own deck\n")
    res = runner.invoke(app, ["export", str(src), "--to", "abaqus", "--out", str(out)])
    assert res.exit_code == 2 and out.read_text() == "my own deck\n"
    assert runner.invoke(app, ["export", str(src), "--to", "abaqus", "--out", str(out), "--force"]).exit_code == 0
    assert runner.invoke(app, ["export", str(src), "--to", "abaqus", "--out", str(out)]).exit_code == 0  # ours now


def test_export_of_several_targets_writes_the_default_files(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    src = _card_file(tmp_path, TABLES["mooney-rivlin"])
    res = runner.invoke(app, ["export", str(src), "--to", "abaqus,ansys,lsdyna,felupe,calculix"])
    assert res.exit_code == 0, res.output
    for name in ("abaqus.inp", "ansys.mac", "lsdyna.k", "felupe.py", "calculix.inp"):
        assert (tmp_path / name).is_file()


def test_one_refused_target_of_several_writes_no_file(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    src = _card_file(tmp_path, TABLES["gent"])
    res = runner.invoke(app, ["export", str(src), "--to", "ansys,abaqus"])
    assert res.exit_code == 2 and not (tmp_path / "ansys.mac").exists()


def test_a_scene_with_a_viscoelastic_part_is_refused_unless_elastic_only(tmp_path):
    scene = tmp_path / "scene.toml"  # C01 ≠ 0: the ground law is not Neo-Hookean, no target has vlab's branches
    scene.write_text(card_toml(TABLES["mooney-rivlin"]) + "[effects.viscoelastic]\nbeta = [0.2]\ntau = [1.0]\n")
    res, out = _export(tmp_path, scene, "abaqus")
    assert res.exit_code == 2 and "viscoelastic" in res.output and not out.exists()
    res, out = _export(tmp_path, scene, "abaqus", "--elastic-only")
    assert res.exit_code == 0, res.output


def test_a_malformed_effects_table_is_named(tmp_path):
    scene = tmp_path / "scene.toml"
    scene.write_text(card_toml(TABLES["mooney-rivlin"]) + "[effects.viscoelastic]\ng = [0.2]\ntau = [1.0]\n")
    res, out = _export(tmp_path, scene, "abaqus", "--elastic-only")
    assert res.exit_code == 2 and "unknown key 'g' in [effects.viscoelastic]" in res.output and not out.exists()


def test_an_unknown_solver_and_bad_units_exit_2(tmp_path):
    src = _card_file(tmp_path, TABLES["yeoh"])
    assert _export(tmp_path, src, "nastran")[0].exit_code == 2
    assert _export(tmp_path, src, "abaqus", "--units", "inch")[0].exit_code == 2


@pytest.mark.parametrize("target", TARGETS)
def test_import_card_writes_a_card_vlab_runs(tmp_path, target):
    label = "mooney-rivlin" if target != "febio" else "gent"
    card = card_for(label, target)
    src = tmp_path / EXPORTERS[target].default_file
    src.write_text(EXPORTERS[target].write(card, UNITS["SI"]))
    out = tmp_path / "back.toml"
    res = runner.invoke(app, ["import-card", str(src), "--out", str(out)])  # units from the header
    assert res.exit_code == 0, res.output
    import tomllib

    from vlab.materials.card import parse_material

    spec = parse_material(tomllib.loads(out.read_text())["material"])
    assert spec.model == card.model and abs(spec.moduli.K / card.K - 1) < 1e-12


# --- malformed cards: a clear error naming the line, exit 2 ------------------------------------
MALFORMED = [
    ("abaqus.inp", "*MATERIAL, NAME=R\n*HYPERELASTIC, MOONEY-RIVLIN\n*DENSITY\n1e-9\n", "line 2", "needs 3 constants"),
    ("abaqus.inp", "*HYPERELASTIC, OGDEN, N=2\n0.5, 2.0, 0.01, -2.0\n0.01\n", "line 1", "needs 6 constants"),
    ("abaqus.inp", "*HYPERELASTIC, MOONEY-RIVLIN\n0.5, abc, 0.01\n", "line 2", "'abc' is not a number"),
    ("abaqus.inp", "*HYPERELASTIC, MOONEY-RIVLIN, TEST DATA INPUT\n", "line 1", "TEST DATA INPUT"),
    ("abaqus.inp", "*HYPERELASTIC, MARLOW\n", "line 1", "'MARLOW' is not read by vlab"),
    ("abaqus.inp", "*HYPERELASTIC, N=1\n0.3, 0.0, 0.01\n", "line 1", "names no model"),
    ("ansys.mac", "TB,HYPER,1,1,2,MOONEY\nTBDATA,1,0.3,0.05\n", "line 1", "needs constants 1 … 3"),
    ("ansys.mac", "TB,HYPER,1,1,2,MOONEY\nTBDATA,1,0.3,x,0.01\n", "line 2", "'x' is not a number"),
    ("ansys.mac", "TB,HYPER,1,1,,ETUBE\nTBDATA,1,1,2,3\n", "line 1", "ETUBE"),
    ("lsdyna.k", "*MAT_OGDEN_RUBBER\n1,1e-9,0.49,0\n", "line 1", "needs 3 data cards"),
    ("lsdyna.k", "*MAT_HYPERELASTIC_RUBBER\n1,1e-9,0.49,0\n0.3,zz,0,0,0,0\n", "line 3", "'zz' is not a number"),
    ("lsdyna.k", "*MAT_HYPERELASTIC_RUBBER\n1,1e-9,0.49,1\n0.3,0.1\n", "line 2", "N = 1"),
    ("febio.feb", "<Material>\n<material id='1' type='Ogden'><c1>1</c1><k>10</k></material></Material>", "line 2",
     "nonzero m_i"),
    ("febio.feb", "<Material><material id='1' type='Mooney-Rivlin'><c1>1</c1><c2>q</c2><k>1</k></material>"
     "</Material>", "line 1", "'q', not a number"),
    ("febio.feb", "<Material><material type='Mooney-Rivlin'>\n<c1>1</c1>\n</Material>", "line 3", "not well-formed"),
    ("felupe.py", "import felupe as fem\numat = fem.Hyperelastic(fem.ogden, mu=[1.0], alpha=[2.0, 1.0]) & "
     "fem.Volumetric(bulk=5.0)\n", "felupe.py", "same length"),
    ("felupe.py", "import felupe as fem\numat = fem.Hyperelastic(fem.yeoh, C10='a', C20=0, C30=0) & "
     "fem.Volumetric(bulk=5.0)\n", "line 2", "is not a number"),
]


@pytest.mark.parametrize("name,text,where,words", MALFORMED)
def test_import_card_on_a_malformed_card_names_the_line_and_exits_2(tmp_path, name, text, where, words):
    src = tmp_path / name
    src.write_text(text)
    res = runner.invoke(app, ["import-card", str(src), "--out", str(tmp_path / "back.toml")])
    assert res.exit_code == 2, res.output
    flat = " ".join(res.output.split())
    assert where in flat and words in flat, flat
    assert not (tmp_path / "back.toml").exists()


# --- vlab fit --export ---------------------------------------------------------------------------
def test_fit_export_writes_the_cards_and_lists_them_on_the_fit_page(tmp_path):
    # all three modes: Ogden-3 on uniaxial data alone leaves constants undetermined (exit 3)
    fit = ROOT / "specimens" / "treloar1944" / "treloar-all.toml"
    out = tmp_path / "fit"
    res = runner.invoke(app, ["fit", str(fit), "--out", str(out), "--export", "abaqus,ansys,felupe"])
    assert res.exit_code == 0, res.output
    for name in ("abaqus.inp", "ansys.mac", "felupe.py"):
        assert (out / "cards" / name).is_file()
        assert f"cards/{name}" in (out / "index.html").read_text()
    text = (out / "cards" / "abaqus.inp").read_text()
    assert "Drucker-stable" in text and "data uniaxial" in text


def test_fit_export_refuses_a_target_without_the_model_before_fitting(tmp_path):
    fit = tmp_path / "gent.toml"
    src = (ROOT / "specimens" / "treloar1944" / "treloar-uniaxial.toml").read_text()
    fit.write_text(re.sub(r'name = "ogden"\nterms = 3', 'name = "gent"', src).replace(
        'file = "', f'file = "{ROOT / "specimens" / "treloar1944"}/'))
    out = tmp_path / "fit"
    res = runner.invoke(app, ["fit", str(fit), "--out", str(out), "--export", "abaqus"])
    assert res.exit_code == 2 and "ansys" in res.output and not out.exists()


def test_the_shipped_treloar_cards_read_back_to_the_fit(tmp_path):
    folder = ROOT / "specimens" / "treloar1944" / "cards"
    import tomllib

    ref = tomllib.loads((folder / "card.toml").read_text())["material"]
    for target, e in EXPORTERS.items():
        back = e.read((folder / e.default_file).read_text(), target, UNITS["mm"])
        assert np.allclose(back.params["mu"], ref["mu"], rtol=1e-12, atol=0)
        assert np.allclose(back.params["alpha"], ref["alpha"], rtol=1e-12, atol=0)
        assert abs(back.K / ref["K"] - 1) < 1e-12


def test_fe_in_the_loop_export_refuses_a_target_without_the_scene_s_energy_before_fitting(tmp_path):
    """An FE fit's card is the scene's coupled Neo-Hookean (not an incompressible stand-in): a
    target without that energy is refused before any solve (it was a traceback after the fit)."""
    folder = ROOT / "specimens" / "dic-field-fit"
    fit = tmp_path / "field-fit.toml"
    fit.write_text((folder / "field-fit.toml").read_text().replace('fields = "field"', f'fields = "{folder / "field"}"')
                   .replace('scene = "block-clamped.toml"', f'scene = "{folder / "block-clamped.toml"}"'))
    out = tmp_path / "fit"
    res = runner.invoke(app, ["fit", str(fit), "--out", str(out), "--export", "abaqus"])
    assert res.exit_code == 2 and "febio, felupe" in res.output and not out.exists()
    assert res.exception is None or isinstance(res.exception, SystemExit)

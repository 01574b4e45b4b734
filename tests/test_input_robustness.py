"""No traceback, whatever the input (#30): each input below once raised a traceback or was silently
ignored; through the CLI it is now exit 2 with a message naming the file or the field (and the
allowed range), and nothing is written in --out.

- a data CSV or a fit file that is not UTF-8 (binary bytes), a CSV cell too long for a CSV
  (UnicodeDecodeError, csv.Error): read through vlab.scene.file as a scene is;
- a TOML nested ~100 000 levels deep (200 kB, under the size limit) in vlab run and vlab fit
  (RecursionError in tomllib), and one nested 40 levels (parsed, then refused by depth);
- material constants whose terms overflow or underflow double precision while the scene is read
  (Arruda–Boyce lambda_m = 1e200: OverflowError; Ogden alpha = 1e300 (a tiny alpha is evaluated
  stably instead: tests/test_input_robustness_b.py); C10 = 1e308:
  LinAlgError; K = 1e308) and the fitter's box that keeps lambda_m inside the scene's range;
- simple shear with protocol = "creep" (solved, then KeyError 'strain' in the report), and a
  viscoelastic biaxial test with a time (TypeError in the report's by-design note);
- [fe] cache = FILE (silently ignored) and --models yeoh,yeoh (failed late with "File exists").
"""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from vlab.cli import app
from helpers_scenes import block_toml

runner = CliRunner()
FAST = ["--no-render", "--no-estimate", "-q"]
CSV = "lambda,P\n1.0,0\n1.5,0.3\n2.0,0.5\n2.5,0.7\n3.0,0.9\n"
FIT = '''name = "t"
[model]
name = "mooney-rivlin"
[[data]]
file = "u.csv"
kind = "uniaxial"
columns = { stretch = "lambda", stress = "P" }
'''
BLOCK = block_toml("b", material='model = "neo-hookean"\nE = 3.0\nnu = 0.45', stretch=1.1, steps=2)


def _refused(result, *needles: str) -> None:
    """Exit 2, every needle in the message, no traceback."""
    assert result.exit_code == 2, result.output
    assert not isinstance(result.exception, Exception) or isinstance(result.exception, SystemExit), result.exception
    assert "Traceback" not in result.output and "Error:" not in result.output, result.output
    text = " ".join(result.output.split())  # the console wraps long messages
    for needle in needles:
        assert needle in text, (needle, result.output)


def _fit(tmp_path: Path, *extra: str):
    return runner.invoke(app, ["fit", str(tmp_path / "fit.toml"), "--out", str(tmp_path / "out"), *extra])


def _run(tmp_path: Path, scene: str):
    (tmp_path / "s.toml").write_text(scene)
    return runner.invoke(app, ["run", str(tmp_path / "s.toml"), "--out", str(tmp_path / "out"), *FAST])


# --- files that are not UTF-8 text -------------------------------------------------------------

@pytest.mark.parametrize("which", ["csv", "fit"])
def test_a_binary_data_csv_or_fit_file_is_exit_2_naming_it(tmp_path, which):
    (tmp_path / "u.csv").write_text(CSV)
    (tmp_path / "fit.toml").write_text(FIT)
    target = tmp_path / ("u.csv" if which == "csv" else "fit.toml")
    target.write_bytes(target.read_bytes()[:40] + b"\xff\xfe\x00\x89PNG\r\n\x1a\n")
    _refused(_fit(tmp_path), target.name, "is not UTF-8")
    assert not (tmp_path / "out").exists()


def test_a_data_csv_with_a_field_longer_than_a_csv_allows_is_exit_2(tmp_path):
    (tmp_path / "u.csv").write_text("lambda,P\n" + "1" * 200_000 + ",0\n")
    (tmp_path / "fit.toml").write_text(FIT)
    _refused(_fit(tmp_path), "u.csv row", "not a CSV table")
    assert not (tmp_path / "out").exists()


def test_a_utf8_csv_with_a_byte_order_mark_still_reads(tmp_path):
    (tmp_path / "u.csv").write_bytes(b"\xef\xbb\xbf" + CSV.encode())
    (tmp_path / "fit.toml").write_text(FIT)
    from vlab.identify.fitfile import load_fit

    assert list(load_fit(tmp_path / "fit.toml").datasets[0].a) == [1.0, 1.5, 2.0, 2.5, 3.0]


# --- pathological TOML ---------------------------------------------------------------------------

DEEP = "a = " + "[" * 100_000 + "]" * 100_000 + "\n"  # 200 kB: under the 1 MiB limit


@pytest.mark.parametrize("text", [DEEP, "a = " + "{b = " * 20_000 + "1" + "}" * 20_000 + "\n",
                                  "a = " + "[" * 40 + "]" * 40 + "\n"], ids=["arrays", "tables", "forty"])
@pytest.mark.parametrize("command", ["run", "fit"])
def test_a_deeply_nested_toml_is_exit_2_naming_the_file(tmp_path, text, command):
    (tmp_path / "u.csv").write_text(CSV)
    if command == "fit":
        (tmp_path / "fit.toml").write_text(FIT + text)
        result = _fit(tmp_path)
    else:
        result = _run(tmp_path, BLOCK + text)
    _refused(result, "fit.toml" if command == "fit" else "s.toml", "more than 32 levels deep")
    assert not (tmp_path / "out").exists()


# --- material constants at the ends of double precision ----------------------------------------

@pytest.mark.parametrize("card,needles", [
    ('model = "arruda-boyce"\nmu = 1.0\nlambda_m = 1e200\nK = 1000.0',
     ("material.lambda_m must be > 1 and <= 1e+06", "got 1e+200")),
    ('model = "arruda-boyce"\nmu = 1.0\nlambda_m = 1e30\nK = 1000.0', ("material.lambda_m", "<= 1e+06")),
    ('model = "ogden"\nmu = [1.0]\nalpha = [1e300]\nK = 1000.0',
     ("material.alpha[0] = 1e+300", "|material.alpha[0]| <= 100")),
    ('model = "ogden"\nmu = [1e308, 1.0]\nalpha = [2.0, 3.0]\nK = 1000.0', ("|material.mu[0]| <= 1e+100",)),
    ('model = "mooney-rivlin"\nC10 = 1e308\nC01 = 1e308\nK = 1000.0', ("material.C10 = 1e+308", "1e+100")),
    ('model = "yeoh"\nC10 = 1.0\nC20 = 1e300\nK = 1000.0', ("material.C20 = 1e+300",)),
    ('model = "gent"\nmu = 1e300\nJm = 10.0\nK = 1000.0', ("material.mu = 1e+300", "1e+100")),
    ('model = "mooney-rivlin"\nC10 = 1e100\nC01 = 1e100\nK = 1000.0', ("mu0 = 4e+100 MPa", "material.C10")),
    ('model = "arruda-boyce"\nmu = 1.0\nlambda_m = 2.0\nK = 1e308', ("K = 1e+308 MPa (from material.K)",)),
    ('model = "arruda-boyce"\nmu = 1.0\nlambda_m = 2.0\nD1 = 1e308', ("K = 2e-308 MPa (from material.D1)",)),
], ids=["ab-1e200", "ab-1e30", "ogden-alpha-big", "ogden-mu", "mr-1e308", "yeoh-C20",
        "gent-mu", "mr-mu0", "K", "D1"])
def test_a_constant_beyond_double_precision_is_exit_2_naming_the_field_and_range(tmp_path, card, needles):
    scene = BLOCK.replace('model = "neo-hookean"\nE = 3.0\nnu = 0.45', card)
    _refused(_run(tmp_path, scene), "s.toml", *needles)
    assert not (tmp_path / "out").exists()


def test_the_largest_lambda_m_is_read_and_the_fitter_keeps_lambda_m_below_it():
    import numpy as np

    from vlab.identify.laws import law_for
    from vlab.materials.arruda_boyce import LAMBDA_M_MAX
    from vlab.scene import parse_scene
    import tomllib

    raw = tomllib.loads(BLOCK.replace('model = "neo-hookean"\nE = 3.0\nnu = 0.45',
                                      f'model = "arruda-boyce"\nmu = 1.0\nlambda_m = {LAMBDA_M_MAX!r}\nK = 1000.0'))
    spec = parse_scene(raw, origin="s.toml")
    assert spec.material.moduli.mu == pytest.approx(1.0, rel=1e-11)  # Neo-Hookean with mu there
    _, lower, upper = law_for("arruda-boyce").start(np.random.default_rng(0), 1.0, 4.0)
    assert lower[1] > 1.0 and upper[1] == LAMBDA_M_MAX


# --- protocols a kind cannot report ---------------------------------------------------------------

SHEAR = '''name = "shear-creep"
[specimen]
shape = "shear"
length = 20.0
gap = 4.0
depth = 10.0
[mesh]
size = 4.0
cell = "hex"
[material]
model = "neo-hookean"
E = 3.0
nu = 0.45
[test]
kind = "simple-shear"
grips = "plates"
protocol = "creep"
shear = 0.2
ramp_time = 1.0
hold_time = 5.0
hold_steps = 3
steps = 3
'''
VISCO = "[effects.viscoelastic]\ntau = [1.0]\nbeta = [0.5]\n"


@pytest.mark.parametrize("extra", [VISCO, ""], ids=["viscoelastic", "elastic"])
def test_simple_shear_creep_is_refused_before_solving(tmp_path, extra):
    _refused(_run(tmp_path, SHEAR + extra), "test.protocol = 'creep'", "test.kind = 'simple-shear'",
             "'relaxation'")
    assert not (tmp_path / "out").exists()


def test_a_viscoelastic_biaxial_relaxation_writes_its_report(tmp_path):
    scene = BLOCK.replace('kind = "uniaxial"', 'kind = "biaxial"').replace("stretch = 1.1", "stretch = [1.1, 1.1]")
    scene = scene.replace("steps = 2", 'steps = 3\nprotocol = "relaxation"\nramp_time = 1.0\nhold_time = 5.0\n'
                          "hold_steps = 3") + VISCO
    result = _run(tmp_path, scene)
    assert result.exit_code == 0, result.output
    assert (tmp_path / "out" / "results.json").is_file()


# --- options and keys that were ignored or failed late --------------------------------------------

def test_fe_cache_that_is_a_file_is_exit_2_as_sweep_cache_is(tmp_path):
    (tmp_path / "block.toml").write_text(BLOCK.replace("E = 3.0\nnu = 0.45", "mu = 0.4\nK = 2.0"))
    (tmp_path / "r.csv").write_text("strain,force\n0.02,1\n0.05,2\n0.1,3\n")
    (tmp_path / "taken").write_text("a file")
    (tmp_path / "fit.toml").write_text('[model]\nname = "neo-hookean"\n[[data]]\nfile = "r.csv"\nkind = "specimen"\n'
                                       '[fe]\nscene = "block.toml"\ncache = "taken"\n')
    _refused(_fit(tmp_path), "fe.cache", "taken", "is a file, not a folder")
    assert not (tmp_path / "out").exists() and (tmp_path / "taken").read_text() == "a file"


@pytest.mark.parametrize("models,needles", [
    ("yeoh,yeoh", ("--models lists 'yeoh' more than once",)),
    ("ogden,mooney-rivlin,ogden-1", ("'ogden-1' more than once", "the same model as 'ogden'")),
])
def test_a_repeated_model_is_refused_at_once(tmp_path, models, needles):
    (tmp_path / "u.csv").write_text(CSV)
    (tmp_path / "fit.toml").write_text(FIT)
    _refused(_fit(tmp_path, "--models", models), *needles)
    assert not (tmp_path / "out").exists()

"""Fuzz of `vlab fit` (#30): random fit files and CSVs (tests/fuzz_fit_cases.py, fixed seed) and the
invariants of docs/fit-exit-codes.md on every one of them:
- no traceback: the exit code is one of 0, 1, 2, 3 and nothing but typer's exit escapes;
- exit 2 writes nothing; any other code writes fit.json, strict JSON (a parser that refuses NaN and
  Infinity reads it);
- every reported interval is finite with positive width around a finite standard error, or null
  with a reason;
- exit 0 only when the card is usable: converged, trustworthy, and `vlab run` accepts the card's
  [material] (the scene parser's bounds)."""

from __future__ import annotations

import json
import math
import os
import time

import numpy as np
import pytest
from typer.testing import CliRunner

from fuzz_fit_cases import fit_case
from vlab.cli import app

runner = CliRunner()
CASES = int(os.environ.get("VLAB_FIT_FUZZ_CASES", "100"))
DRAWN = 3  # fits whose figures are drawn (the others get empty files: the figures are not the contract)
SEED = int(os.environ.get("VLAB_FIT_FUZZ_SEED", "20261204"))


def _refuse(token):
    raise ValueError(f"not strict JSON: {token}")


def check_intervals(d: dict) -> None:
    for name, u in d["uncertainty"].items():
        if u["interval"] is None:
            assert isinstance(u["reason"], str) and u["reason"], (name, u)
            continue
        lo, hi = u["interval"]
        assert all(isinstance(v, float) and math.isfinite(v) for v in (lo, hi)) and hi > lo, (name, u)
        se = u["standard_error"]
        assert isinstance(se, float) and math.isfinite(se) and se > 0, (name, u)


def check_card_runs(card: dict) -> None:
    from vlab.scene import parse_scene

    parse_scene({"name": "card", "specimen": {"shape": "block", "size": [4.0, 4.0, 4.0]},
                 "mesh": {"size": 4.0, "order": 1, "cell": "hex"}, "material": card,
                 "test": {"kind": "uniaxial", "grips": "roller", "stretch": 1.5, "steps": 2}})


def check_fit_json(path, code: int, where: str) -> None:
    d = json.loads(path.read_text(), parse_constant=_refuse)
    check_intervals(d)
    if code == 0:
        assert d["converged"] and d["trust"]["trustworthy"], where
        check_card_runs(d["card"]["material"])


def check_ranking(out, code: int, where: str) -> None:
    """--models: ranking.json strict; every model's fit.json as above; 0 only for a usable first."""
    rows = json.loads((out / "ranking.json").read_text(), parse_constant=_refuse)["ranking"]
    for i, row in enumerate(rows):
        check_fit_json(out / row["model"] / "fit.json", code if i == 0 else -1, where)


def check_case(folder, text: str, files: dict[str, bytes], models: str | None = None) -> int:
    """Write the case into ``folder``, fit it, assert the invariants; returns the exit code."""
    (folder / "fit.toml").write_text(text)
    for name, data in files.items():
        (folder / name).write_bytes(data)
    extra = ["--models", models] if models else []
    result = runner.invoke(app, ["fit", str(folder / "fit.toml"), "--out", str(folder / "out"), *extra])
    where = f"\n--- fit.toml\n{text}\n--- output\n{result.output}"
    assert result.exception is None or isinstance(result.exception, SystemExit), \
        f"{type(result.exception).__name__}: {result.exception}{where}"
    assert result.exit_code in (0, 1, 2, 3) and "Traceback" not in result.output, where
    if result.exit_code == 2:
        assert not (folder / "out").exists(), where
        return 2
    if models:
        check_ranking(folder / "out", result.exit_code, where)
    else:
        check_fit_json(folder / "out" / "fit.json", result.exit_code, where)
    return result.exit_code


def _blank(*args):
    """A figure not drawn (2-4 s each; the first DRAWN fits draw them): an empty file in its place."""
    open(args[-1], "wb").close()


def test_random_fit_files_keep_the_exit_code_contract(tmp_path, monkeypatch):
    import vlab.identify.plots as plots

    real = {name: getattr(plots, name) for name in ("plot_curves", "plot_stability_map", "plot_models")}
    rng = np.random.default_rng(SEED)
    codes, start = [], time.perf_counter()
    for i in range(CASES):
        for name, draw in real.items():
            monkeypatch.setattr(plots, name, draw if sum(c != 2 for c in codes) < DRAWN else _blank)
        folder = tmp_path / f"case{i:03d}"
        folder.mkdir()
        text, files = fit_case(rng)
        models = "neo-hookean,yeoh,ogden-2" if i % 10 == 5 else None  # the ranking of several models
        codes.append(check_case(folder, text, files, models))
    seconds = time.perf_counter() - start
    counts = {c: codes.count(c) for c in sorted(set(codes))}
    print(f"{CASES} cases in {seconds:.1f} s; exit codes {counts}")
    assert set(codes) - {2}, counts  # some cases reach the fit, not only the input checks


# --- what the fuzz found (each fails on the code before its fix) -----------------------------

GOOD = "lambda,P\n1.0,0\n1.5,0.3\n2.0,0.5\n2.5,0.7\n3.0,0.9\n"
BASE = '''name = "t"
[model]
name = "neo-hookean"
[[data]]
file = "u.csv"
kind = "uniaxial"
columns = { stretch = "lambda", stress = "P" }
[options]
starts = 1
'''


def _fit_file(tmp_path, text):
    (tmp_path / "u.csv").write_text(GOOD)
    (tmp_path / "fit.toml").write_text(text)
    return tmp_path / "fit.toml"


@pytest.mark.parametrize("edit, needle", [
    (('name = "neo-hookean"', 'name = "neo-hookean"\nincompressible = false\nK = 1e300'), "model.K must be"),
    (('kind = "uniaxial"', 'kind = "uniaxial"\nweight = 1e300'), "data[0].weight must be"),
])
def test_a_key_whose_size_overflowed_the_fit_is_refused_naming_its_range(tmp_path, edit, needle):
    """K = 1e300 made every residual inf (a TypeError in the page); weight = 1e300 an SVD failure."""
    from vlab.fields import SceneError
    from vlab.identify.fitfile import load_fit

    with pytest.raises(SceneError) as exc:
        load_fit(_fit_file(tmp_path, BASE.replace(*edit)))
    assert needle in str(exc.value) and ("1e+09" in str(exc.value) or "1e+06" in str(exc.value)), str(exc.value)


def test_a_fit_error_fit_json_does_not_have_is_shown_as_a_dash_not_a_traceback(tmp_path):
    from rich.console import Console

    from vlab.identify.command import _print_fit
    from vlab.identify.fitfile import load_fit
    from vlab.identify.fitting import fit_any
    from vlab.identify.report import page, strict

    d = strict(fit_any(load_fit(_fit_file(tmp_path, BASE))).data)
    d["datasets"][0]["rms_relative"] = d["datasets"][0]["max_relative"] = None  # not finite: null
    console = Console(record=True, width=200)
    _print_fit(console, d)
    assert "rms —, max —" in console.export_text()
    assert "<td>—</td><td>—</td>" in page(d, []).replace(" ", "")


def test_a_binary_data_file_is_refused_naming_it(tmp_path):
    from vlab.fields import SceneError
    from vlab.identify.fitfile import load_fit

    f = _fit_file(tmp_path, BASE)
    (tmp_path / "u.csv").write_bytes(b"\xff\xfe\x00garbage\x80\x81")
    with pytest.raises(SceneError) as exc:
        load_fit(f)
    assert "u.csv: data file is not UTF-8" in str(exc.value), str(exc.value)


def test_a_fit_file_that_is_not_utf8_is_refused_naming_it(tmp_path):
    from vlab.fields import SceneError
    from vlab.identify.fitfile import load_fit

    f = _fit_file(tmp_path, BASE)
    f.write_bytes(b"name = \"\xff\"\n")
    with pytest.raises(SceneError, match="fit.toml: fit file is not UTF-8"):
        load_fit(f)

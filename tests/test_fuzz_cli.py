"""A hypothesis fuzz of the command line (#16): random scene text (mutated valid scenes, random
bytes), random --out paths (existing user folders, the scene file, the current folder, markup, a
300-character name), random specimen.file paths, random cache corruption. Every outcome: exit 0, 1
or 2 only; no traceback; exit 2 names a field or file; nothing outside the report folder changed
or removed; a results.json that says converged has finite numbers and a complete curve.

The fast profile (normal suite, in-process through typer's CliRunner, coarse meshes) draws a few
dozen cases; the slow one (``-m slow -s``) draws more, with renders and a Dask sweep with a
corrupted cache, and prints the count of each outcome."""

from __future__ import annotations

import collections
import json
import os
import random
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from fuzz_cli_cases import FIELD, cases, check_converged_report, inside, make_lab, report_folder, snapshot
from vlab.cli import app

runner = CliRunner()
OUTCOMES: collections.Counter = collections.Counter()


def run_case(case) -> str:
    """Run one case in a fresh lab; assert the invariants; return the outcome's name."""
    with tempfile.TemporaryDirectory(prefix="vlab-fuzz-") as top:
        lab = Path(top) / "lab"
        lab.mkdir()
        make_lab(lab)
        (lab / "scene.toml").write_bytes(case.text)
        before = snapshot(Path(top))
        cwd = os.getcwd()
        os.chdir(lab)
        try:
            args = ["run", "scene.toml", "-q", *case.extra] + (["--out", case.out] if case.out else [])
            result = runner.invoke(app, args)
        finally:
            os.chdir(cwd)
        after = snapshot(Path(top))
        return check(result, before, after, lab, case)


def check(result, before, after, lab: Path, case) -> str:
    output = result.output
    assert result.exit_code in (0, 1, 2), (result.exit_code, output, result.exception)
    assert result.exception is None or isinstance(result.exception, SystemExit), repr(result.exception)
    assert "Traceback" not in output, output
    if result.exit_code == 2:
        assert FIELD.search(output), f"exit 2 without a field or file named: {output!r}"
    folder = report_folder(output) if result.exit_code in (0, 1) else None
    written = None
    if folder is not None:
        written = os.path.relpath(os.path.normpath(os.path.join(lab, folder)), lab.parent)
        check_converged_report(lab.parent / written)
    for path, digest in before.items():
        if not inside(path, written):
            assert after.get(path) == digest, f"{path} changed or removed outside the report folder {written}"
    new = [p for p in after if p not in before and not inside(p, written)
           and not (written and inside(written, p))]  # the report folder's new parents
    assert new == [], f"created outside the report folder {written}: {new}"
    return f"exit {result.exit_code}" + (" (report)" if written else "")


@settings(max_examples=30, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(cases())
def test_random_command_lines_keep_the_error_contract(case):
    OUTCOMES[run_case(case)] += 1


def _corrupt(entry: Path, how: str, rng: random.Random) -> None:
    data = json.loads(entry.read_text())
    if how == "edit":
        data["measured"]["E"] = rng.choice([12345.0, -1.0, 0.0])
        entry.write_text(json.dumps(data))
    elif how == "nan":
        data["measured"]["nu"] = float("nan")
        entry.write_text(json.dumps(data))
    elif how == "bytes":
        entry.write_bytes(bytes(rng.randrange(256) for _ in range(rng.randrange(0, 200))))
    elif how == "folder":
        entry.unlink()
        entry.mkdir()
    elif how == "key":
        data["cache_key"] = "0" * 64
        entry.write_text(json.dumps(data))
    else:
        entry.write_text(how)


@settings(max_examples=20, deadline=None, derandomize=True)
@given(st.sampled_from(["edit", "nan", "bytes", "folder", "key", "[]", "{}", "null", "1"]), st.integers(0, 99))
def test_a_corrupted_cache_entry_is_never_served(how, seed):
    from vlab.study.cache import SummaryCache

    with tempfile.TemporaryDirectory() as top:
        cache = SummaryCache(Path(top) / "cache")
        key = "ab" * 32
        good = {"status": "ok", "label": {}, "vlab_version": __import__("vlab").__version__,
                "measured": {"E": 10.0, "nu": 0.3}}
        cache.put(key, good)
        assert cache.get(key) == good
        _corrupt(cache.path(key), how, random.Random(seed))
        assert cache.get(key) is None
        cache.put(key, good)  # recomputed: stored again (a folder in the way is left and not cached)
        assert cache.get(key) in (good, None)


@pytest.mark.slow
@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(cases(render=True))
def test_many_random_command_lines_keep_the_error_contract(case):
    OUTCOMES[run_case(case)] += 1


@pytest.fixture(scope="module")
def scheduler():
    from distributed import LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=":0",
                      scheduler_port=0) as local:
        yield local.scheduler_address


@pytest.fixture(scope="module")
def clean_sweep(tmp_path_factory, scheduler):
    """A two-point sweep of the fuzz block and its cache, computed once."""
    from fuzz_cli_cases import BLOCK

    root = tmp_path_factory.mktemp("sweep")
    (root / "scene.toml").write_text(BLOCK)
    result = runner.invoke(app, ["sweep", str(root / "scene.toml"), "--set", "material.nu=0.3,0.4", "--scheduler",
                                 scheduler, "--cache", str(root / "cache"), "--out", str(root / "out"), "-q"])
    assert result.exit_code == 0, result.output
    runs = json.loads((root / "out" / "sweep.json").read_text())["runs"]
    return root, [r["measured"] for r in runs]


@pytest.mark.slow
@settings(max_examples=25, deadline=None, suppress_health_check=list(HealthCheck))
@given(st.sampled_from(["edit", "nan", "bytes", "folder", "key", "[]", "{}", "null"]), st.integers(0, 10**6))
def test_a_sweep_over_a_randomly_corrupted_cache_recomputes_what_is_not_valid(clean_sweep, scheduler, how, seed):
    import shutil

    root, measured = clean_sweep
    with tempfile.TemporaryDirectory() as top:
        cache = Path(top) / "cache"
        shutil.copytree(root / "cache", cache)
        rng = random.Random(seed)
        _corrupt(rng.choice(sorted(cache.glob("*/*.json"))), how, rng)
        result = runner.invoke(app, ["sweep", str(root / "scene.toml"), "--set", "material.nu=0.3,0.4",
                                     "--scheduler", scheduler, "--cache", str(cache), "--out", f"{top}/out", "-q"])
        assert result.exit_code == 0 and "Traceback" not in result.output, (result.output, result.exception)
        data = json.loads(Path(f"{top}/out/sweep.json").read_text())
        assert [r["measured"] for r in data["runs"]] == measured
        assert data["meta"]["computed"] == 1 and data["meta"]["cache_hits"] == 1
        OUTCOMES[f"sweep, cache entry corrupted ({how}): recomputed"] += 1


@pytest.mark.slow
def test_zz_print_the_outcome_counts():
    print("\nCLI fuzz outcomes:", dict(sorted(OUTCOMES.items())))
    assert sum(OUTCOMES.values()) > 0

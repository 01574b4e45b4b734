"""Writes a run's output folder atomically: everything goes to a temporary sibling folder that
replaces the target only when complete, so a crash or bad input never leaves half a report."""

from __future__ import annotations

import csv
import json
import shutil
import tempfile
from contextlib import contextmanager
from pathlib import Path

from vlab.report.results import curve_columns, result_to_dict
from vlab.run import RunResult


@contextmanager
def atomic_folder(target: Path):
    target = Path(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{target.name}.", dir=target.parent))
    try:
        yield tmp
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    if target.exists():
        shutil.rmtree(target)
    tmp.rename(target)


def write_curve_csv(result: RunResult, path: Path) -> None:
    cols = curve_columns(result)
    with open(path, "w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(cols)
        writer.writerows(zip(*cols.values()))


def write_run(result: RunResult, out: Path, scene_text: str | None = None) -> dict:
    """results.json, curve.csv, stress_strain.png and index.html in ``out``; returns the dict."""
    from vlab.report.html import write_index
    from vlab.report.plots import plot_stress_strain

    data = result_to_dict(result)
    with atomic_folder(out) as tmp:
        (tmp / "results.json").write_text(json.dumps(data, indent=2))
        write_curve_csv(result, tmp / "curve.csv")
        plot_stress_strain(data, tmp / "stress_strain.png")
        if scene_text is not None:
            (tmp / "scene.toml").write_text(scene_text)
        write_index(data, tmp / "index.html", images=["stress_strain.png"])
    return data

"""The sweep page's chart: the first swept key against each measured quantity, a panel per
quantity, a line per value of the other keys (read back with vlab.report.figures.describe)."""

from __future__ import annotations

import pytest

from vlab.study.sweep_plots import CHART_COLUMNS, plot_sweep
from vlab.study.table import write_sweep_report


def _summary(size, order, E, status="ok"):
    return {"label": {"mesh.size": size, "mesh.order": order}, "status": status, "diagnosis": None,
            "measured": {"E": E, "nu": 0.3 + 0.01 * order, "final_force": 100.0 + size, "final_stress": 1.0 + size},
            "solver": {"newton_iterations": 10 + order}, "timing": {"wall_s": 1.0 / size}, "mesh": {"dofs": 81}}


GRID = [_summary(h, p, 10.0 - 0.01 * h / p) for p in (1, 2) for h in (10.0, 5.0, 2.5)]


def test_one_panel_per_quantity_one_line_per_other_key(tmp_path):
    panels = plot_sweep(GRID, tmp_path / "s.png")
    assert [p["title"] for p in panels] == ["E [MPa]", "ν", "final stress [MPa]", "final force [N]",
                                            "Newton iterations", "wall [s]"]
    assert len(panels) == len(CHART_COLUMNS)
    assert all(p["xlabel"] == "mesh.size" and p["lines"] == 2 for p in panels)
    assert panels[0]["legend"] == ["mesh.order = 1", "mesh.order = 2"]
    assert panels[1]["colours"] == panels[0]["colours"]  # a line keeps its colour across panels
    assert (tmp_path / "s.png").stat().st_size > 20_000


def test_failed_runs_have_no_point_and_no_completed_run_no_chart(tmp_path):
    runs = [dict(s) for s in GRID]
    for s in runs[:3]:  # every mesh.order = 1 run failed: that line is gone
        s["status"], s["measured"] = "failed", {"E": None}
    panels = plot_sweep(runs, tmp_path / "s.png")
    assert all(p["lines"] == 1 for p in panels) and panels[0]["legend"] == ["mesh.order = 2"]
    assert plot_sweep([dict(s, status="invalid") for s in GRID], tmp_path / "n.png") is None
    assert not (tmp_path / "n.png").exists()
    assert plot_sweep([dict(GRID[0], label={})], tmp_path / "k.png") is None  # nothing was swept


def test_one_key_one_line_and_a_model_axis_by_name(tmp_path):
    runs = [dict(_summary(5.0, 1, E), label={"material.model": m}) for m, E in (("neo-hookean", 9.98), ("yeoh", 9.9))]
    panels = plot_sweep(runs, tmp_path / "m.png")
    assert panels[0]["xlabel"] == "material.model" and panels[0]["lines"] == 1 and panels[0]["legend"] == []


def test_the_page_shows_the_chart_above_the_table(tmp_path):
    index = write_sweep_report(tmp_path / "sw", "t: sweep", GRID, {})
    page = index.read_text(encoding="utf-8")
    assert (tmp_path / "sw" / "sweep.png").is_file()
    assert page.index("<img src='sweep.png'") < page.index("<table>")
    assert "mesh.size against each quantity" in page and "a line per value of mesh.order" in page


@pytest.mark.parametrize("sizes,log", [((10.0, 5.0, 2.5), False), ((100.0, 10.0, 1.0), True)])
def test_a_key_spanning_a_factor_of_20_is_on_a_log_axis(tmp_path, sizes, log):
    panels = plot_sweep([_summary(h, 1, 10.0) for h in sizes], tmp_path / "l.png")
    assert {p["xscale"] for p in panels} == {"log" if log else "linear"}

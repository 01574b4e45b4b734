"""A real browser opens the report: headless Chromium (Debian's ``chromium`` package) screenshots
it, and the screenshot must show the figures, not broken-image placeholders."""

import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

BROWSER = next((p for p in map(shutil.which, ("chromium", "chromium-browser", "google-chrome")) if p), None)
pytestmark = pytest.mark.skipif(BROWSER is None, reason="no chromium on PATH (Debian package 'chromium'; "
                                "'.ci/run' installs it with apt-get where apt is available)")
ARTEFACTS = Path(__file__).resolve().parent.parent / "reports" / "test-artefacts"
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--hide-scrollbars", "--window-size=1300,3200", "--virtual-time-budget=5000"]


def screenshot(page: Path, png: Path, profile: Path) -> np.ndarray:
    proc = subprocess.run([BROWSER, *FLAGS, f"--user-data-dir={profile}", f"--screenshot={png}",
                           page.resolve().as_uri()], capture_output=True, text=True, timeout=120)
    assert png.is_file(), proc.stderr[-2000:]
    return np.asarray(Image.open(png).convert("HSV"), dtype=float)


def colourful_fraction(hsv: np.ndarray) -> float:
    """Share of pixels with clear colour (saturation and brightness): curves, colour maps, renders.
    Text, table borders and broken-image placeholders are grey or thin."""
    return float(np.mean((hsv[..., 1] > 90) & (hsv[..., 2] > 60)))


def test_report_screenshot_shows_the_images(comparison, tmp_path):
    shot = screenshot(comparison.folder / "index.html", tmp_path / "report.png", tmp_path / "profile")
    ARTEFACTS.mkdir(parents=True, exist_ok=True)
    shutil.copy(tmp_path / "report.png", ARTEFACTS / "report-screenshot.png")

    broken = tmp_path / "broken"  # the same page with its pictures missing: the control
    shutil.copytree(comparison.folder, broken)
    for picture in list(broken.glob("*.png")) + list(broken.glob("*.gif")) + list(broken.glob("view3d.*")):
        picture.unlink()
    control = screenshot(broken / "index.html", tmp_path / "broken.png", tmp_path / "profile2")

    loaded, missing = colourful_fraction(shot), colourful_fraction(control)
    assert missing < 0.01, missing
    assert loaded > 0.015 and loaded > 5 * missing, (loaded, missing)

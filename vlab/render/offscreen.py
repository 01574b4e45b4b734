"""Off-screen rendering set-up, done once before the first render window is made.

VTK's PyPI wheels (9.4 and later) choose their OpenGL window at run time: X, then EGL, then OSMesa.
Without a display the X attempt fails with a "bad X server connection" warning on the console
before EGL takes over, so with no DISPLAY we ask for EGL (Mesa's software EGL, Debian package
libegl-mesa0, is enough) or OSMesa directly. No Xvfb is needed. If neither library is present,
renders are skipped with a reason that names what to install; the rest of the report is written.
"""

from __future__ import annotations

import ctypes.util
import logging
import os
from functools import lru_cache

log = logging.getLogger(__name__)

_WINDOW_VARIABLE = "VTK_DEFAULT_OPENGL_WINDOW"


class RenderUnavailable(RuntimeError):
    """No way to render off-screen on this machine; the message says what is missing."""


def _choose_window() -> str | None:
    """The VTK render window class to request, or None to let VTK pick (a display exists)."""
    if os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"):
        return None
    if ctypes.util.find_library("EGL"):
        return "vtkEGLRenderWindow"
    if ctypes.util.find_library("OSMesa"):
        return "vtkOSOpenGLRenderWindow"
    raise RenderUnavailable("no display and neither libEGL nor libOSMesa found; install Mesa's EGL "
                            "(Debian: libegl1 libegl-mesa0) or OSMesa (libosmesa6) to get renders")


@lru_cache(maxsize=1)
def setup() -> str:
    """Configure pyvista/VTK for off-screen rendering once; returns the window class in use."""
    window = os.environ.get(_WINDOW_VARIABLE) or _choose_window()
    if window is not None:
        os.environ[_WINDOW_VARIABLE] = window
    import pyvista
    import vtkmodules.vtkCommonCore as vtk_core

    pyvista.OFF_SCREEN = True
    # VTK's own logger and output window would print to the console; route them to logging.
    vtk_core.vtkLogger.SetStderrVerbosity(vtk_core.vtkLogger.VERBOSITY_OFF)
    vtk_core.vtkObject.GlobalWarningDisplayOff()
    log.debug("off-screen rendering with %s", window or "VTK's default window")
    return window or "default"

"""Specimens drawn in CAD: a Gmsh .geo script or a STEP/BREP file, meshed by Gmsh (the ``cad``
extra: ``pip install "vlab[cad]"``) into linear tetrahedra of edge ``mesh.size`` (Gmsh's
Mesh.MeshSizeMax, Delaunay 3D, Gmsh's and Netgen's optimisers), then read like an imported mesh:
grips are Gmsh physical groups (a .geo's ``Physical Surface("grip_left")``) or boxes in the file's
coordinates (``{min = [x, y, z], max = [x, y, z]}``: every mesh vertex inside), checked by vlab's
mesh checks; ``mesh.order = 2`` puts P2 elements on the straight-sided tetrahedra.
"""

from __future__ import annotations

import contextlib
import functools
import tempfile
from pathlib import Path

import numpy as np

from vlab.geometry.imported import ImportedMesh, MeshImportError, read_mesh

CAD_SUFFIXES = (".geo", ".step", ".stp", ".brep")


@functools.lru_cache(maxsize=1)
def gmsh_version() -> str | None:
    """Gmsh's version, or None where the module does not import (not installed, or a system
    library it links to is missing: Debian libglu1-mesa libxcursor1 libxft2 libxinerama1).
    Asked of a child process: importing Gmsh loads its own OpenMP runtime into the process, which
    changed the round-off of later threaded factorizations here (a borderline bifurcation test
    went from "bifurcation in tension" to "no convergence" after a Gmsh import)."""
    import subprocess
    import sys

    try:
        proc = subprocess.run([sys.executable, "-c", "import gmsh; print(gmsh.__version__)"],
                              capture_output=True, text=True, timeout=60)
    except (OSError, subprocess.TimeoutExpired):
        return None
    return proc.stdout.strip() or None if proc.returncode == 0 else None


def in_own_process(fn, *args):
    """``fn(*args)`` in a fresh Python process (vlab/geometry/gmsh_worker.py), so that Gmsh's
    OpenMP threads never live in vlab's process: a process that has run Gmsh and PARDISO and
    then forks (vlab compare's workers) left its children hung in libgomp (measured in the test
    suite). Not multiprocessing's spawn: it re-runs the caller's main script, which a user's
    script need not guard."""
    import pickle
    import subprocess
    import sys

    job = pickle.dumps((fn.__module__, fn.__name__, args))
    proc = subprocess.run([sys.executable, "-m", "vlab.geometry.gmsh_worker"], input=job, capture_output=True)
    if proc.returncode != 0 or not proc.stdout:
        tail = proc.stderr.decode(errors="replace").strip().splitlines()[-3:]
        raise MeshImportError("specimen.file", f"the Gmsh process failed (exit {proc.returncode}): "
                              f"{' / '.join(tail) or 'no message'}")
    status, *value = pickle.loads(proc.stdout)
    if status == "error":
        field, message = value
        raise MeshImportError(field, message.removeprefix(f"{field} "))
    return value[0]


@contextlib.contextmanager
def _session():
    import gmsh

    gmsh.initialize(argv=["vlab"], readConfigFiles=False, interruptible=False)
    gmsh.option.setNumber("General.Terminal", 0)  # Gmsh prints nothing; vlab reports what matters
    try:
        yield gmsh
    finally:
        gmsh.finalize()


def _check_file(path: Path) -> None:
    if path.suffix.lower() not in CAD_SUFFIXES:
        raise MeshImportError("specimen.file", f"must be a Gmsh .geo, STEP (.step, .stp) or .brep file, "
                              f"got {path.name!r}")
    if not path.is_file():
        raise MeshImportError("specimen.file", f"{str(path)!r} does not exist")
    if gmsh_version() is None:
        raise MeshImportError("specimen.file", "needs Gmsh: pip install \"vlab[cad]\" (gmsh from PyPI; on "
                              "Debian also libglu1-mesa libxcursor1 libxft2 libxinerama1)")


def _load(gmsh, path: Path) -> None:
    try:
        if path.suffix.lower() == ".geo":
            gmsh.open(str(path))
        else:
            gmsh.model.occ.importShapes(str(path))
            gmsh.model.occ.synchronize()
    except Exception as exc:  # Gmsh raises a bare Exception with its own message
        raise MeshImportError("specimen.file", f"Gmsh cannot read {path.name}: {exc}") from None
    if not gmsh.model.getEntities(3):
        raise MeshImportError("specimen.file", f"{path.name} holds no volume (a solid is needed)")


def inspect_cad(path: Path) -> tuple[list[str], list[float], list[float]]:
    """The named physical groups of a CAD file and the bounding box of its volumes (no meshing)."""
    _check_file(path)
    return in_own_process(_inspect, path)


def _inspect(path: Path):
    with _session() as gmsh:
        _load(gmsh, path)
        names = sorted(gmsh.model.getPhysicalName(d, t) for d, t in gmsh.model.getPhysicalGroups())
        boxes = np.array([gmsh.model.getBoundingBox(3, tag) for _, tag in gmsh.model.getEntities(3)])
        return names, boxes[:, :3].min(axis=0).tolist(), boxes[:, 3:].max(axis=0).tolist()


def mesh_cad(path: Path, size: float) -> ImportedMesh:
    """Mesh the CAD file with Gmsh tetrahedra of largest edge ``size`` (mm) and read it back."""
    _check_file(path)
    return in_own_process(_mesh, path, size)


def _mesh(path: Path, size: float) -> ImportedMesh:
    with tempfile.TemporaryDirectory(prefix="vlab-gmsh-") as tmp, _session() as gmsh:
        _load(gmsh, path)
        gmsh.option.setNumber("Mesh.MeshSizeMax", float(size))
        gmsh.option.setNumber("Mesh.ElementOrder", 1)
        gmsh.option.setNumber("Mesh.MshFileVersion", 2.2)  # meshio misreads the cell sets of some 4.1 files
        # Netgen's optimiser after Gmsh's: Gmsh alone left slivers (scaled Jacobian 0.03) that vlab's
        # mesh check refuses, on the ISO 527-2 1A dogbone at mesh.size 2.83
        gmsh.option.setNumber("Mesh.OptimizeNetgen", 1)
        # without a physical volume Gmsh would save only the grip faces: save every element
        gmsh.option.setNumber("Mesh.SaveAll", 0 if gmsh.model.getPhysicalGroups(3) else 1)
        try:
            gmsh.model.mesh.generate(3)
        except Exception as exc:
            raise MeshImportError("specimen.file", f"Gmsh could not mesh {path.name} at mesh.size {size:g}: "
                                  f"{exc}") from None
        out = Path(tmp) / "cad.msh"
        gmsh.write(str(out))
        return read_mesh(out)


def add_box_regions(data: ImportedMesh, boxes: dict[str, tuple]) -> ImportedMesh:
    """``data`` with one region per box (name -> (min corner, max corner)): the vertices inside."""
    regions = dict(data.regions)
    for name, (lo, hi) in boxes.items():
        inside = np.all((data.points >= np.asarray(lo) - 1e-9) & (data.points <= np.asarray(hi) + 1e-9), axis=1)
        regions[name] = np.flatnonzero(inside)
    return ImportedMesh(data.points, data.cell, data.cells, {k: v for k, v in regions.items() if len(v)})

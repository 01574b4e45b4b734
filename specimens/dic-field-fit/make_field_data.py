"""Write the virtual DIC data of specimens/dic-field-fit/ (run: python specimens/dic-field-fit/make_field_data.py).

SYNTHETIC: vlab runs block-clamped.toml (a Neo-Hookean block, mu = 0.4 MPa, K = 2 MPa, pulled
between clamped grips, so the strain is not uniform near the grips), the virtual camera
(vlab.dic.camera) renders the speckled top face at the reference and at every recorded level from
the FE displacement, vlab's DIC (vlab.dic.correlate) correlates each level against the reference,
and the folder gets what `vlab run` writes for a scene with [instruments.dic]:

    field/fields/level-<k>.csv   vlab dic's CSV of level k
    field/levels.csv             image, displacement (grip travel (λ − 1) L_grip, mm), force (N)
    field/dic.json               the DIC settings and the camera (pixels, mm_per_px, centre_mm, face)

`vlab fit specimens/dic-field-fit/field-fit.toml` then identifies mu back from a 30 % wrong start.
``write_folder`` is what tests/test_fit_field.py calls with its own scene, camera and noise.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
CAMERA = {"pixels": (400, 136), "mm_per_px": 0.025, "face": (2, 1), "noise": 0.005}
DIC = {"subset": 25, "step": 8, "strain_window": 5}


def _solve(scene_path: Path):
    """The run's nodal displacement (n_nodes, 3) at every recorded level, the grip travel (mm)
    and the load-cell force (N)."""
    from vlab.run import run_scene
    from vlab.scene import load_scene

    states = []
    result = run_scene(load_scene(scene_path), on_level=lambda level: states.append(level.evaluation.u.copy()))
    if not result.converged:
        raise SystemExit(f"{scene_path}: the test did not complete")
    grip = (np.array(result.curve.stretch[0]) - 1.0) * result.specimen.grip_separation[0]
    return result.specimen.mesh, [u.reshape(-1, 3) for u in states], grip, np.array(result.curve.force[0])


def _frames(mesh, states, camera: dict, seed: int):
    """The reference image and one per level, rendered by vlab.dic.camera; the camera's centre."""
    from vlab.dic.camera import Camera, Speckle, paint, render
    from vlab.dic.face import face_of

    face = face_of(mesh, *camera["face"])
    lo, hi = face.bounds
    centre = tuple(float(c) for c in (lo + hi) / 2)
    cam = Camera(pixels=camera["pixels"], mm_per_px=camera["mm_per_px"], noise=camera["noise"], seed=seed,
                 centre=centre)
    pattern = paint(face, cam, Speckle(size=4.0, density=0.5, seed=seed))
    images = [render(cam, face, pattern, np.zeros((mesh.p.shape[1], 3)), frame=0)]
    images += [render(cam, face, pattern, u, frame=k + 1) for k, u in enumerate(states)]
    return images, centre


def write_folder(folder: Path, scene_path: Path, camera: dict = CAMERA, dic: dict = DIC, seed: int = 0) -> dict:
    """Render, correlate and write ``folder`` (fields/, levels.csv, dic.json); returns dic.json's dict."""
    from vlab.dic import output
    from vlab.dic.correlate import Correlator, Settings, settings_dict

    mesh, states, grip, force = _solve(scene_path)
    images, centre = _frames(mesh, states, camera, seed)
    settings = Settings(**dic)
    correlator = Correlator(images[0].astype(float), settings)
    (folder / "fields").mkdir(parents=True, exist_ok=True)
    rows, previous, converged = ["image,displacement,force"], None, {}
    for k, image in enumerate(images[1:], start=1):
        previous = correlator.correlate(image.astype(float), guess=previous)
        output.write_csv(folder / "fields" / f"level-{k}.csv", previous)
        rows.append(f"level-{k},{grip[k - 1]:.12g},{force[k - 1]:.12g}")
        converged[f"level-{k}"] = previous.converged
    (folder / "levels.csv").write_text("\n".join(rows) + "\n")
    data = {"settings": settings_dict(settings), "converged_share": converged,
            "camera": {"pixels": list(camera["pixels"]), "mm_per_px": camera["mm_per_px"], "centre_mm": list(centre),
                       "face": {"axis": "xyz"[camera["face"][0]], "side": camera["face"][1]},
                       "noise": camera["noise"], "bit_depth": 16, "supersample": 3, "speckle_px": 4.0}}
    (folder / "dic.json").write_text(json.dumps(data, indent=1))
    return data


if __name__ == "__main__":
    sys.exit(print(json.dumps(write_folder(HERE / "field", HERE / "block-clamped.toml")["converged_share"])))

"""What results.json records about the declared effects, the protocol and the history state."""

from __future__ import annotations

from dataclasses import asdict

import numpy as np


def effects_summary(scene, body, levels) -> dict:
    """Declared effects with their parameters, the protocol, and per recorded level the largest
    cell value of each history variable (e.g. viscous_stress, MPa); the smallest for the
    Mullins ``softening`` η, whose strongest value is its least."""
    history: dict[str, list[float]] = {}
    if body.history is not None:
        for level in levels:
            cells = body.history.cell_fields_of(level.evaluation) or {}
            for name, values in cells.items():
                if name == "softening":
                    history.setdefault(name + "_min", []).append(float(np.min(values)))
                elif name != "cauchy":
                    history.setdefault(name + "_max", []).append(float(np.max(values)))
    return {"declared": {spec.name: asdict(spec) for spec in scene.effects},
            "protocol": _protocol(scene.test.protocol),
            "history": history,
            "units": {"tau": "s", "g": "mm/s²", "strain_rate": "1/s", "ramp_time": "s",
                      "hold_time": "s", "viscous_stress_max": "MPa (‖Σ Q_i‖, largest cell)",
                      "plastic_strain_max": "1 (accumulated plastic strain α, largest cell)",
                      "max_energy_max": "MPa (Mullins W_max, largest cell)",
                      "softening_min": "1 (Mullins η, smallest cell; 1 = primary curve)"}}


def _protocol(protocol) -> dict:
    """The protocol's fields; ``reversed`` only when set (fully reversed shear cycles)."""
    out = asdict(protocol)
    if not out.get("reversed"):
        out.pop("reversed", None)
    return out

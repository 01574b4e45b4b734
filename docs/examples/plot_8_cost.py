"""
What accuracy costs
===================

``vlab.cost`` (the code of ``vlab cost``) on a small scene: a 10 mm Neo-Hookean cube pulled 10 %
between clamped grips, which hold the ends' width so the state is not homogeneous and has no closed
form. The study re-runs the scene over the mesh size (5, 2.5 and 1.25 mm Q1 hexahedra), the load
steps, Newton's tolerance and the model; its reference for each quantity is the Richardson
extrapolation of the mesh family, error ≈ C hᵖ with the observed order p from the three sizes,
where the family converges monotonically (else the most resolved run, and the notes say so); the
chart draws each run's largest relative error of E, ν, the final force and stress against its
compute time. The tutorial "What accuracy costs" reads such a chart step by step (with Q2 too).
"""

from gallery_helpers import SCRATCH, show_images

import vlab

block = vlab.Scene.from_dict({
    "name": "cost-block",
    "specimen": {"shape": "block", "size": [10.0, 10.0, 10.0]},
    "mesh": {"size": 2.5, "cell": "hex"},
    "material": {"model": "neo-hookean", "E": 10.0, "nu": 0.3},
    "test": {"kind": "uniaxial", "grips": "clamped", "stretch": 1.1, "steps": 2},
})
# one worker: the build shares CI's cores; the cache in the scratch folder, not reports/.cache
study = vlab.cost(block, target=0.01, levels=3, ratio=2.0, orders=[1], cells=["hex"], workers=1,
                  cache=SCRATCH / "cost-cache")
print(study.recommendation)
for quantity, note in study.notes.items():  # the reference of each quantity, and why
    print(f"{quantity}: {note}")
table = study.to_pandas()[["knob", "value", "largest error", "DOFs", "wall [s]"]]
print(table.to_string(formatters={"value": lambda v: f"{v:g}" if isinstance(v, float) else str(v)}))

# %%
# The chart of the report (``error_time.png``): the Pareto front circled, the recommended run
# starred (the cheapest within the 1 % target, dashed).

study.write_report(SCRATCH / "cost-block-cost")
show_images([SCRATCH / "cost-block-cost" / "error_time.png"], "vlab.cost: error against compute time")

"""A cost study times the solve, not the compiler: every kernel a run calls is compiled (or
loaded from numba's cache) by vlab.study.warm before the run's clock starts."""

import json
import os
import subprocess
import sys

from vlab.study.summary import RunKnobs

SCRIPT = r"""
import json, sys
from vlab.scene import parse_scene
from vlab.study.warm import warm_kernels

def signatures():
    # every compiled kernel vlab loaded: numba dispatchers in the generated kernel modules
    total = 0
    for name, module in list(sys.modules.items()):
        if name.startswith("vlab_kernel_"):
            total += sum(len(getattr(f, "signatures", ())) for f in vars(module).values())
    return total

def scene(order, cell):
    return parse_scene({"name": "w", "specimen": {"shape": "block", "size": [4.0, 4.0, 4.0]},
                        "mesh": {"size": 1.0, "order": order, "cell": cell},
                        "material": {"model": "neo-hookean", "E": 10.0, "nu": 0.3},
                        "test": {"kind": "uniaxial", "stretch": 1.2, "steps": 2}})

from vlab.run import run_scene
warmed = scene(2, "tet")
compile_s = warm_kernels(warmed)
before = signatures()
run_scene(warmed)
after_warmed = signatures()
run_scene(scene(1, "hex"))          # not warmed: its kernels compile (or load) inside the run
after_cold = signatures()
print("RESULT " + json.dumps({"compile_s": compile_s, "before": before, "after_warmed": after_warmed,
                              "after_cold": after_cold, "again": warm_kernels(warmed)}))
"""


def test_a_warmed_run_compiles_nothing_inside_its_clock_and_an_unwarmed_one_does():
    env = {k: v for k, v in os.environ.items() if k != "VLAB_KERNEL"}  # the compiled kernels on
    proc = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True, env=env, timeout=600)
    line = [x for x in proc.stdout.splitlines() if x.startswith("RESULT ")]
    assert line, proc.stderr[-2000:]
    out = json.loads(line[0][7:])
    assert out["before"] > 0 and out["compile_s"] > 0.0
    assert out["after_warmed"] == out["before"]   # the timed run met only compiled kernels
    assert out["after_cold"] > out["after_warmed"]  # the probe sees compilation when it happens
    assert out["again"] == 0.0                    # once per process and element kind


def test_cost_study_summaries_of_the_old_format_are_not_reused():
    """Summaries cached before the warm-up booked compilation as mesh time: format 3 re-keys them."""
    assert RunKnobs().as_dict()["summary_format"] == 3

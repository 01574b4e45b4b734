"""The whole-test solves of an FE-in-the-loop fit on Dask, through the sweeps' cluster path.

``--workers N`` starts a LocalCluster of N one-thread worker processes, ``--scheduler
tcp://HOST:PORT`` uses an existing cluster (its address checked and probed first, as for
``vlab sweep``: vlab.study.scheduler); without either the solves run in the fitting process.
Levenberg–Marquardt asks for one whole test at a time, so a cluster buys no parallelism inside
one fit: it moves the FE work to the cluster's machines (a large specimen, a laptop client), next
to sweeps and cost studies. The cache stays on the client, as for sweeps: looked up before a
task is submitted, written when it returns (vlab.identify.fe_sensitivity.simulate(run=...)).
A task that fails comes back as the RuntimeError or SceneError it raised on the worker.
"""

from __future__ import annotations

from vlab.identify.fe_sensitivity import Simulation, simulate

__all__ = ["DaskSolves"]


class DaskSolves:
    """``run(fe, values) -> Simulation`` on a Dask cluster (a context manager: closes the client
    and any LocalCluster it started)."""

    def __init__(self, execution):
        from vlab.study.sweep import cluster_client

        self.execution = execution
        self._context = cluster_client(execution)
        self.client = None
        self.submitted = 0

    def __enter__(self) -> "DaskSolves":
        self.client = self._context.__enter__()  # SchedulerError if the address is no Dask scheduler
        return self

    def __exit__(self, *exc) -> bool:
        self._context.__exit__(*exc)
        return False

    def __call__(self, fe: dict, values: dict) -> Simulation:
        task = {k: v for k, v in fe.items() if k not in ("scene", "cache")}  # the worker re-parses the scene
        self.submitted += 1
        future = self.client.submit(simulate, task, dict(values), key=f"vlab-fit-solve-{self.submitted}", pure=False)
        return future.result()

    def describe(self) -> dict:
        e = self.execution
        return {"dask": True, "scheduler": e.scheduler, "workers": None if e.scheduler else e.workers,
                "tasks": self.submitted}

"""The report's matplotlib figures drawn by a second process, beside the solver and the writer.

A run's figures (stress–strain overlay, lateral or thickness strain, the protocol's loops and
relaxation curves) are a pure function of its results dicts (:func:`draw_figures`). Drawn by
the command's own process they come after the solve, on one core: matplotlib's import (0.3–0.9
CPU-s) and two figures (0.2–0.4 s each), while the second core idles (benchmarks/RESULTS.md,
"command overhead"). :class:`FigureWorker` starts a Python process running :func:`main` (this
vlab on its path) when a run starts: the worker imports matplotlib and vlab's plot modules and draws a small figure (the
font cache, the Agg renderer) on the other core while the command imports the solver and solves,
then waits for its one job. The report writer sends the job before it writes the VTU files,
renders and page, and collects the figures' list after them.

Protocol: stdin carries one JSON job (:func:`figure_job` plus the folder), stdout one answer line,
``ANSWER`` then ``{"figures": [[file, caption], ...]}`` or ``{"error": ..., "traceback": ...}``; an OS error
(a full disk, a folder removed) is ``{"error": ..., "errno": n, "filename": ...}`` without a traceback and is
raised in the command as that OSError, so the report writer says what it says of its own OS errors
(exit 2 naming the folder and the cause, nothing written). End of input with
no job ends the worker quietly (a run that failed before its report). Whatever goes wrong with the
worker (it could not be started, it died, it answered nothing or an error) is raised in the command
as :class:`FigureWorkerError` naming the cause with the worker's stderr; the report folder is then
discarded as for any error of the writer, so nothing is half-written. Where the worker cannot be
started at all (no interpreter to run), the figures are drawn in process.
"""

from __future__ import annotations

import json
import logging
import os
import subprocess
import sys
import tempfile
import threading
from pathlib import Path

log = logging.getLogger(__name__)

PLOT_MODULES = ("matplotlib.figure", "matplotlib.backends.backend_agg", "matplotlib.ticker",
                "vlab.report.stretch_plots", "vlab.report.comparison_plots", "vlab.report.biaxial_plots",
                "vlab.report.effect_plots", "vlab.report.kind_plots", "vlab.report.html")
ANSWER = "vlab-figure-worker-answer: "  # starts the answer's line on the worker's stdout
ANSWER_TIMEOUT_S = 600.0  # the figures of a large comparison take seconds; a stuck worker is killed


class FigureWorkerError(RuntimeError):
    """The figure worker failed; the message names the cause and ends with its stderr."""


def figure_job(datas: list[dict], true_measures: bool, departures: dict, lateral_ratio: bool) -> dict:
    """What :func:`draw_figures` needs, as JSON (the folder is added by the writer)."""
    return {"datas": datas, "true": bool(true_measures), "departures": departures,
            "stretch_kind": bool(lateral_ratio)}


def draw_figures(job: dict) -> list:
    """Draw the job's figures into ``job["folder"]``; returns their html Figures in page order.

    Uniaxial and biaxial tests (``stretch_kind``): each kind's figures (vlab/report/stretch_plots.py),
    then the protocol's, without offset notation on any tick label; the other kinds: the kind's own
    figure (vlab/report/kind_plots.py), then the protocol's where the kind has effects."""
    import matplotlib

    from vlab.report.effect_plots import effect_figures
    from vlab.report.html import Figure
    from vlab.report.kind_plots import KIND_CAPTIONS, kind_of_data, plot_kind
    from vlab.report.stretch_plots import NO_OFFSET, kind_figures

    datas, folder = job["datas"], Path(job["folder"])
    if job["stretch_kind"]:
        figures = kind_figures(datas, folder, job["true"], job["departures"])
        with matplotlib.rc_context(NO_OFFSET):
            return figures + effect_figures(datas, folder)
    plot_kind(datas, folder / "stress_strain.png")
    kind = kind_of_data(datas[0])
    figures = [Figure("stress_strain.png", KIND_CAPTIONS[kind.name])]
    return figures + (effect_figures(datas, folder) if kind.effects else [])


class Drawn:
    """Figures drawn in process, with the worker's ``result()`` interface."""

    def __init__(self, figures: list):
        self.figures = figures

    def result(self) -> list:
        return self.figures

    def cancel(self) -> None:
        pass


def start_figures(job: dict, worker: "FigureWorker | None"):
    """The job sent to ``worker`` (its figures come with ``.result()``), or drawn now without one."""
    if worker is not None and worker.running():
        worker.submit(job)
        return worker
    if worker is not None and worker.proc is not None:  # it ended before its job: say why, draw here
        log.warning("%s; figures drawn in process",
                    worker._failure(f"ended before its job (exit status {worker.proc.returncode})"))
    return Drawn(draw_figures(job))


def wanted(mode: str, cores: int | None = None, others: int | None = None) -> bool:
    """Whether a command should start a worker: ``mode`` "on", "off" or "auto".

    "auto": a worker where it pays (benchmarks/command_overhead.py, on the 2-core machine): not
    where matplotlib is already imported (drawing here costs less than a new process), and only
    with a core to spare: ``cores`` usable (vlab.settings.usable_cores) ≥ 2, of which at most
    ``cores`` − 1 are taken by ``others`` (tasks running besides this one, /proc/loadavg). Measured
    overhead of block16's run: 2.65 s with the worker against 3.77 s without on an idle machine,
    10.99 against 11.25 s whole command with one core busy, but 12.74 against 12.05 s on one core."""
    if mode != "auto":
        return mode == "on"
    if "matplotlib" in sys.modules:
        return False
    from vlab.settings import usable_cores

    cores = usable_cores() if cores is None else cores
    others = running_besides_this() if others is None else others
    return cores >= 2 and cores - others >= 1


def running_besides_this() -> int:
    """Tasks running or runnable on the machine now besides the caller (Linux: /proc/loadavg's
    'running/total' field counts the caller too); 0 where it cannot be read."""
    try:
        with open("/proc/loadavg", encoding="ascii") as fh:
            return max(int(fh.read().split()[3].split("/")[0]) - 1, 0)
    except (OSError, IndexError, ValueError):
        return 0


class FigureWorker:
    """The worker process of one report; a context manager that never leaves the process behind."""

    def __init__(self, command: list[str] | None = None):
        self.stderr = tempfile.TemporaryFile()
        # the vlab that imported this module, appended to the worker's path (never ahead of the
        # standard library) for a process started from a directory that does not hold it
        root = str(Path(__file__).resolve().parents[2])
        self.command = command or [sys.executable, "-c", f"import sys; sys.path.append({root!r}); "
                                   "import vlab.report.figure_worker as w; w.main()"]
        self.proc: subprocess.Popen | None = None
        self.sender: threading.Thread | None = None

    def start(self) -> "FigureWorker":
        """Start the process; where that is impossible (OSError), none: figures drawn in process."""
        try:
            self.proc = subprocess.Popen(self.command, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                         stderr=self.stderr, close_fds=True)
        except OSError as exc:  # no interpreter to run: the writer draws in process
            log.warning("figure worker not started (%s): figures drawn in process", exc)
            self.proc = None
        return self

    def running(self) -> bool:
        return self.proc is not None and self.sender is None and self.proc.poll() is None

    def submit(self, job: dict) -> None:
        """Send the job from a thread (a pipe write blocks until the worker reads it)."""
        payload = json.dumps(job).encode()
        self.sender = threading.Thread(target=self._send, args=(payload,), name="vlab-figure-job", daemon=True)
        self.sender.start()

    def _send(self, payload: bytes) -> None:
        try:
            self.proc.stdin.write(payload)
            self.proc.stdin.close()
        except OSError:  # the worker died: result() reports it with its stderr
            pass

    def result(self) -> list:
        """The figures the worker drew; FigureWorkerError if it failed in any way."""
        from vlab.report.html import Figure

        self.sender.join(ANSWER_TIMEOUT_S)
        self.proc.stdin = None  # closed by the sender: communicate() only reads the answer
        try:
            if self.sender.is_alive():
                raise subprocess.TimeoutExpired(self.command, ANSWER_TIMEOUT_S)
            answer, _ = self.proc.communicate(timeout=ANSWER_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
            raise FigureWorkerError(self._failure(f"no answer within {ANSWER_TIMEOUT_S:g} s (killed)")) from None
        lines = [ln for ln in answer.decode(errors="replace").splitlines() if ln.startswith(ANSWER)]
        try:
            reply = json.loads(lines[-1][len(ANSWER):]) if lines else None
        except ValueError:
            reply = None
        if isinstance(reply, dict) and isinstance(reply.get("errno"), int):
            raise OSError(reply["errno"], os.strerror(reply["errno"]), reply.get("filename"))
        if not isinstance(reply, dict) or "figures" not in reply:
            cause = reply.get("error", "") if isinstance(reply, dict) else f"exit status {self.proc.returncode}"
            raise FigureWorkerError(self._failure(cause))
        self._forward_stderr()
        return [Figure(file, caption) for file, caption in reply["figures"]]

    def cancel(self) -> None:
        """Stop a submitted job now (the report failed): nothing more is written to its folder."""
        if self.proc is not None and self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()

    def _stderr_text(self) -> str:
        self.stderr.seek(0)
        return self.stderr.read().decode(errors="replace").strip()

    def _failure(self, cause: str) -> str:
        tail = "\n".join(self._stderr_text().splitlines()[-20:])
        return f"the figure worker (vlab.report.figure_worker, pid {self.proc.pid}) failed: {cause}" + (
            f"\n{tail}" if tail else "")

    def _forward_stderr(self) -> None:
        """Warnings the worker printed (e.g. matplotlib's) are the command's warnings too."""
        for line in self._stderr_text().splitlines():
            log.warning("figure worker: %s", line)

    def close(self) -> None:
        """End of input (an idle worker exits), then wait briefly; kill what is still running."""
        if self.proc is not None and self.proc.poll() is None:
            if self.sender is None:
                try:
                    self.proc.stdin.close()
                except OSError:
                    pass
            try:
                self.proc.wait(timeout=5.0)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        self.stderr.close()

    def __enter__(self) -> "FigureWorker":
        return self.start()

    def __exit__(self, *exc) -> None:
        self.close()


def _warm() -> None:
    """Import the plot modules and draw once: the font cache and the Agg renderer are loaded."""
    import importlib

    for name in PLOT_MODULES:
        importlib.import_module(name)
    from vlab.report import figures as plt

    fig, ax = plt.subplots(figsize=(1.0, 1.0), dpi=50)
    ax.plot([0.0, 1.0], [0.0, 1.0], "-o", ms=2.5)
    ax.set_title("warm-up", fontsize=8)
    fig.canvas.draw()


def main() -> None:
    """The worker: warm up, read one job, draw it, answer; the exit skips finalization.

    Anything else printed to stdout (a sitecustomize, a library's notice) goes to stderr while
    the worker runs, and the answer is the last line that starts with ANSWER."""
    import traceback

    answer, sys.stdout = sys.stdout, sys.stderr
    reply = None
    try:
        _warm()
        raw = sys.stdin.buffer.read()
        if raw.strip():
            reply = {"figures": [[f.file, f.caption] for f in draw_figures(json.loads(raw))]}
    except OSError as exc:  # a fault of the file system, not of vlab: its cause, no traceback
        reply = {"error": f"{exc.strerror or exc}", "errno": exc.errno,
                 "filename": None if exc.filename is None else str(exc.filename)}
    except Exception as exc:  # noqa: BLE001 - every failure goes back to the command
        reply = {"error": f"{type(exc).__name__}: {exc}", "traceback": traceback.format_exc()}
        traceback.print_exc()
    if reply is not None:
        answer.write(f"\n{ANSWER}{json.dumps(reply)}\n")
    answer.flush()
    sys.stderr.flush()
    os._exit(0)


if __name__ == "__main__":
    main()

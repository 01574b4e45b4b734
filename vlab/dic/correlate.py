"""One DIC analysis: the subset grid, the seeds, IC-GN, the strain window (vlab.dic)."""

from __future__ import annotations

from dataclasses import asdict, dataclass, field

import numpy as np

from vlab.dic import icgn, seed, strain


class DICError(ValueError):
    """Settings or images DIC cannot use (exit 2); the message names the setting or image
    (``setting``: the name of the bad setting, if one is)."""

    def __init__(self, message: str, setting: str | None = None):
        super().__init__(message)
        self.setting = setting


@dataclass(frozen=True)
class Settings:
    """DIC settings (px unless said): subset side (odd), step between subset centres, strain
    window (odd, in grid points), integer search radius, IC-GN tolerance (px) and iteration cap,
    the ZNCC below which a converged subset is refused, the interpolation of the deformed image."""

    subset: int = 31
    step: int = 10
    strain_window: int = 5
    search: int = 20
    tolerance: float = 1e-4
    max_iterations: int = 50
    min_zncc: float = 0.9
    interpolation: str = "bicubic"
    shape_function: str = "affine"

    def check(self, shape: tuple[int, int] | None = None) -> None:
        def need(ok, name, allowed):
            if not ok:
                raise DICError(f"{name} = {getattr(self, name)!r}: {allowed}", name)

        need(isinstance(self.subset, int) and self.subset >= 7 and self.subset % 2 == 1, "subset",
             "must be an odd integer ≥ 7 (px)")
        need(isinstance(self.step, int) and self.step >= 1, "step", "must be an integer ≥ 1 (px)")
        need(isinstance(self.strain_window, int) and self.strain_window >= 3 and self.strain_window % 2 == 1,
             "strain_window", "must be an odd integer ≥ 3 (grid points)")
        need(isinstance(self.search, int) and self.search >= 1, "search", "must be an integer ≥ 1 (px)")
        need(0 < self.tolerance <= 0.1, "tolerance", "must be in (0, 0.1] px")
        need(isinstance(self.max_iterations, int) and self.max_iterations >= 1, "max_iterations", "must be ≥ 1")
        need(-1 <= self.min_zncc < 1, "min_zncc", "must be in [-1, 1)")
        need(self.interpolation in icgn.ORDERS, "interpolation", f"must be one of {', '.join(icgn.ORDERS)}")
        need(self.shape_function == "affine", "shape_function", "must be 'affine' (the one implemented)")
        if shape is not None and min(shape) < self.subset + 2:
            raise DICError(f"subset = {self.subset} px does not fit in a {shape[1]} × {shape[0]} px image "
                           f"(it needs at least {self.subset + 2} px each way)")


@dataclass
class Field:
    """The DIC result on the subset grid (rows = y, columns = x): centres, displacements (px),
    the affine gradients of IC-GN, Green–Lagrange strains from the strain window, ZNCC,
    iterations and status codes (vlab.dic.icgn.STATUS); NaN where a subset failed."""

    x: np.ndarray
    y: np.ndarray
    u: np.ndarray
    v: np.ndarray
    exx: np.ndarray
    eyy: np.ndarray
    exy: np.ndarray
    zncc: np.ndarray
    iterations: np.ndarray
    status: np.ndarray
    params: np.ndarray = field(repr=False)  # (rows, cols, 6)

    @property
    def converged(self) -> float:
        """The share of the subsets in the region of interest (all, without one) that converged to
        an accepted correlation."""
        asked = self.status != icgn.OUTSIDE
        return float((self.status[asked] == icgn.OK).mean()) if asked.any() else 0.0

    def counts(self) -> dict[str, int]:
        return {name: int((self.status == code).sum()) for code, name in icgn.STATUS.items()}


def grid(shape: tuple[int, int], settings: Settings) -> tuple[np.ndarray, np.ndarray]:
    """Subset centres: every ``step`` px from the first centre whose subset (plus the 2-px
    gradient stencil) fits the image, centred so the margins are equal."""
    half = settings.subset // 2 + 2
    axes = []
    for n in (shape[1], shape[0]):
        count = (n - 1 - 2 * half) // settings.step + 1
        first = (n - 1 - (count - 1) * settings.step) // 2
        axes.append(first + settings.step * np.arange(count))
    return axes[0], axes[1]


class Correlator:
    """DIC of any number of deformed images against one reference (the reference side once)."""

    def __init__(self, reference: np.ndarray, settings: Settings = Settings(), compiled: bool | None = None,
                 roi: np.ndarray | None = None):
        """``roi``: a bool image (the reference's shape) of the region of interest; a subset is
        correlated only if its centre pixel is in it (None: every subset; status OUTSIDE else)."""
        settings.check(reference.shape)
        self.compiled = compiled
        self.reference, self.settings = reference, settings
        self.xs, self.ys = grid(reference.shape, settings)
        X, Y = np.meshgrid(self.xs, self.ys)
        self.cx, self.cy = X.ravel(), Y.ravel()
        self.active = np.ones(self.cx.size, bool) if roi is None else np.asarray(roi, bool)[self.cy, self.cx]
        self.refd = icgn.prepare(reference, self.cx, self.cy, settings.subset // 2, compiled)

    def correlate(self, deformed: np.ndarray, guess: Field | None = None) -> Field:
        """The field of ``deformed``. Seeding: the integer FFT search (within ``search`` px of
        ``guess``, e.g. the previous image of a sequence, where it converged) on a coarse grid of
        subsets about one subset apart; IC-GN there; every other subset starts from the affine
        prediction of its nearest converged coarse subset; a subset that fails from there gets
        its own integer search and a second IC-GN."""
        self._check_match(deformed)
        shape = (self.ys.size, self.xs.size)
        run = _Run(self, deformed, guess)
        coarse = _coarse_subsets(shape, self.settings)
        coarse = coarse[self.active[coarse]]
        run.status[~self.active] = icgn.OUTSIDE
        run.refine(coarse, run.searched(coarse))
        good = np.zeros(run.n, bool)
        good[coarse] = run.status[coarse] == icgn.OK
        rest = np.setdiff1d(np.flatnonzero(self.active), coarse)
        if good.any() and rest.size:
            run.refine(rest, _predicted(run.p, good, rest, shape, self.cx, self.cy))
        elif rest.size:
            run.refine(rest, run.searched(rest))
        retry = np.flatnonzero((run.status == icgn.NOT_CONVERGED) | (run.status == icgn.LEFT_IMAGE))
        retry = retry[~np.isin(retry, coarse)] if good.any() else np.array([], dtype=int)
        if retry.size:
            run.refine(retry, run.searched(retry))
        return self._field(run, shape)

    def _check_match(self, deformed: np.ndarray) -> None:
        if deformed.shape != self.reference.shape:
            raise DICError(f"the deformed image is {deformed.shape[1]} × {deformed.shape[0]} px, the "
                           f"reference {self.reference.shape[1]} × {self.reference.shape[0]} px: they must match")

    def _field(self, run: _Run, shape: tuple[int, int]) -> Field:
        """The Field of a finished run: a converged subset below ``min_zncc`` is refused
        (LOW_CORRELATION), every refused subset NaN; strains from the strain window."""
        s, p, status = self.settings, run.p, run.status
        status[(status == icgn.OK) & ~(run.zncc >= s.min_zncc)] = icgn.LOW_CORRELATION
        p[status != icgn.OK] = np.nan
        U, V = p[:, 0].reshape(shape), p[:, 3].reshape(shape)
        exx, eyy, exy = strain.strain_window(U, V, s.step, s.strain_window)
        X, Y = self.cx.reshape(shape), self.cy.reshape(shape)
        return Field(X, Y, U, V, exx, eyy, exy, run.zncc.reshape(shape), run.its.reshape(shape),
                     status.reshape(shape), p.reshape(*shape, 6))


class _Run:
    """One deformed image's correlation in progress: the affine parameters p (n, 6) of every
    subset, their ZNCC, iterations and status, and the integer-search guesses (gu, gv)."""

    def __init__(self, correlator: Correlator, deformed: np.ndarray, guess: Field | None):
        self.c, self.deformed, s = correlator, deformed, correlator.settings
        self.n = n = correlator.cx.size
        self.gu, self.gv = np.zeros(n), np.zeros(n)
        if guess is not None:  # the guess counts only where it converged
            ok = (guess.status == icgn.OK).ravel()
            self.gu[ok], self.gv[ok] = guess.u.ravel()[ok], guess.v.ravel()[ok]
        self.coeffs = icgn.coefficients(deformed, s.interpolation)
        self.p = np.zeros((n, 6))
        self.zncc, self.its = np.full(n, np.nan), np.zeros(n, dtype=np.int64)
        self.status = np.full(n, icgn.NOT_CONVERGED, dtype=np.int64)

    def refine(self, idx: np.ndarray, p0: np.ndarray) -> None:
        """IC-GN of the subsets idx from p0, their results stored."""
        c, s = self.c, self.c.settings
        self.p[idx], self.zncc[idx], self.its[idx], self.status[idx] = icgn.refine(
            c.refd, self.coeffs, p0, idx, s.interpolation, s.tolerance, s.max_iterations, c.compiled)

    def searched(self, idx: np.ndarray) -> np.ndarray:
        """Starts p0 of the subsets idx from the integer search about their guesses (gradients 0)."""
        c, s = self.c, self.c.settings
        u0, v0, _ = seed.integer_seeds(c.reference, self.deformed, c.cx[idx], c.cy[idx], s.subset // 2,
                                       self.gu[idx], self.gv[idx], s.search)
        p0 = np.zeros((idx.size, 6))
        p0[:, 0], p0[:, 3] = u0, v0
        return p0


def _coarse_subsets(shape: tuple[int, int], s: Settings) -> np.ndarray:
    """Flat indices of the coarse grid: every ``stride`` ≈ subset/step grid points from stride//2,
    plus the last row and column (so the coarse grid reaches every edge)."""
    stride = max(1, int(round(s.subset / s.step)))
    rows, cols = np.meshgrid(np.arange(shape[0]), np.arange(shape[1]), indexing="ij")
    mask = (rows % stride == stride // 2) | (rows == shape[0] - 1)
    mask &= (cols % stride == stride // 2) | (cols == shape[1] - 1)
    return np.flatnonzero(mask.ravel())


def _predicted(p: np.ndarray, good: np.ndarray, rest: np.ndarray, shape: tuple[int, int], cx, cy) -> np.ndarray:
    """Starts of the subsets ``rest`` from the nearest converged (``good``) subset n, carried
    affinely over the centre offset (dx, dy): u0 = u + u_x dx + u_y dy, v0 = v + v_x dx + v_y dy,
    the gradients kept (p = [u, u_x, u_y, v, v_x, v_y])."""
    from scipy import ndimage

    _, (ni, nj) = ndimage.distance_transform_edt(~good.reshape(shape), return_indices=True)
    near = (ni * shape[1] + nj).ravel()[rest]
    pn = p[near]
    dx, dy = (cx[rest] - cx[near]).astype(float), (cy[rest] - cy[near]).astype(float)
    p0 = pn.copy()
    p0[:, 0] += pn[:, 1] * dx + pn[:, 2] * dy
    p0[:, 3] += pn[:, 4] * dx + pn[:, 5] * dy
    return p0


def settings_dict(settings: Settings) -> dict:
    return asdict(settings)

"""Isotropic elastic constants: any two of E, nu, lambda, mu (= G), K, M fix the rest.

Units: MPa for E, lambda, mu, K, M; nu is dimensionless. Valid for a stable isotropic solid:
E > 0, mu > 0, K > 0, M > 0 and -1 < nu < 1/2 (lambda may have either sign), every modulus in
1e-100..1e100 MPa (double precision; MODULUS_RANGE). nu = 1/2
(incompressible) is not supported; use up to 0.4999.

Closed forms used by :func:`from_pair` (L = lambda, G = mu):

====== =================================================================================
pair   formulas
====== =================================================================================
E, nu  L = E nu/((1+nu)(1-2nu)), G = E/(2(1+nu)), K = E/(3(1-2nu)), M = E(1-nu)/((1+nu)(1-2nu))
E, L   R = sqrt(E^2 + 9L^2 + 2EL); nu = 2L/(E+L+R), G = (E-3L+R)/4, K = (E+3L+R)/6,
       M = (E-L+R)/2   (rationalised forms are used where a difference would cancel:
       nu = (R-E-L)/(4L) and K = -2EL/(3(R-E-3L)) for L < 0, G = 2EL/(R+3L-E) for L > 0)
E, G   nu = E/(2G) - 1, L = G(E-2G)/(3G-E), K = EG/(3(3G-E)), M = G(4G-E)/(3G-E)
E, K   nu = (3K-E)/(6K), G = 3KE/(9K-E), L = 3K(3K-E)/(9K-E), M = 3K(3K+E)/(9K-E)
E, M   S = s sqrt((9M-E)(M-E)) with s = +1 (root="plus") or -1 (root="minus");
       nu = (E-M+S)/(4M), G = (3M+E-S)/8, L = (M-E+S)/4, K = (3M-E+S)/6.
       Two roots: M >= E for every valid solid and M = E only at nu = 0; "plus" gives the
       nu >= 0 branch, "minus" the nu <= 0 branch (both coincide at M = E). E/9 < M < E has
       no real solution. (Cancelling differences are evaluated in rationalised form.)
nu, L  E = L(1+nu)(1-2nu)/nu, G = L(1-2nu)/(2nu), K = L(1+nu)/(3nu), M = L(1-nu)/nu;
       undefined at nu = 0 (then L = 0 for every E).
nu, G  E = 2G(1+nu), L = 2G nu/(1-2nu), K = 2G(1+nu)/(3(1-2nu)), M = 2G(1-nu)/(1-2nu)
nu, K  E = 3K(1-2nu), L = 3K nu/(1+nu), G = 3K(1-2nu)/(2(1+nu)), M = 3K(1-nu)/(1+nu)
nu, M  E = M(1+nu)(1-2nu)/(1-nu), L = M nu/(1-nu), G = M(1-2nu)/(2(1-nu)), K = M(1+nu)/(3(1-nu))
L, G   E = G(3L+2G)/(L+G), nu = L/(2(L+G)), K = L + 2G/3, M = L + 2G
L, K   E = 9K(K-L)/(3K-L), G = 3(K-L)/2, nu = L/(3K-L), M = 3K - 2L
L, M   G = (M-L)/2, E = (M-L)(M+2L)/(M+L), nu = L/(M+L), K = (M+2L)/3
G, K   E = 9KG/(3K+G), L = K - 2G/3, nu = (3K-2G)/(2(3K+G)), M = K + 4G/3
G, M   E = G(3M-4G)/(M-G), L = M - 2G, nu = (M-2G)/(2M-2G), K = M - 4G/3
K, M   G = 3(M-K)/4, E = 9K(M-K)/(3K+M), L = (3K-M)/2, nu = (3K-M)/(3K+M)
====== =================================================================================

Every denominator is checked (or proven positive by an earlier check) before dividing:
non-physical input raises :class:`ModuliError`, never ZeroDivisionError or inf.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Mapping

__all__ = ["Moduli", "ModuliError", "from_pair", "KEYS", "ALIASES", "MIXED_NU_LIMIT"]

KEYS = ("E", "nu", "lambda", "mu", "K", "M")
ALIASES = {"G": "mu", "lmbda": "lambda"}
_PREFIX = "material."
_NU_RANGE = "-1 < nu < 0.5"
MODULUS_RANGE = (1e-100, 1e100)  # MPa, |E|, |lambda|, mu, K, M (see _check_magnitudes)
MIXED_NU_LIMIT = 0.4999  # verified limit of mesh.formulation = "mixed" (Cook's membrane study)
_INCOMPRESSIBLE = ("nu = 0.5 is exact incompressibility, an infinite bulk modulus, which no formulation "
                   f"here supports; for a nearly incompressible solid use nu <= {MIXED_NU_LIMIT:g} with "
                   "mesh.formulation = 'mixed', the verified limit of the locking-free formulation")


class ModuliError(ValueError):
    """Invalid or non-physical elastic constants; the message names the field."""


@dataclass(frozen=True)
class Moduli:
    """A complete isotropic set. E, lmbda, mu, K, M in MPa; nu dimensionless."""

    E: float
    nu: float
    lmbda: float
    mu: float
    K: float
    M: float

    def as_dict(self) -> dict[str, float]:
        return {"E": self.E, "nu": self.nu, "lambda": self.lmbda, "mu": self.mu,
                "K": self.K, "M": self.M}


def _fmt(x: float) -> str:
    return f"{x:g}"


def _nu_error(field: str, nu: float, origin: str = "") -> ModuliError:
    extra = f" ({_INCOMPRESSIBLE})" if nu == 0.5 else ""
    return ModuliError(f"{field} = {_fmt(nu)}{origin} is outside the allowed range {_NU_RANGE}{extra}")


def _canonical(values: Mapping[str, float]) -> dict[str, float]:
    out: dict[str, float] = {}
    for key, val in values.items():
        name = ALIASES.get(key, key)
        if name not in KEYS:
            raise ModuliError(f"unknown elastic constant {_PREFIX}{key} "
                              f"(allowed: {', '.join(KEYS)}; G = mu, lmbda = lambda)")
        if name in out:
            raise ModuliError(f"{_PREFIX}{name} given twice (as {name} and an alias)")
        if isinstance(val, bool) or not isinstance(val, (int, float)):
            raise ModuliError(f"{_PREFIX}{name} must be a number, got {val!r}")
        out[name] = float(val)
    if len(out) != 2:
        raise ModuliError(f"give exactly two of {', '.join(KEYS)}; got {', '.join(values) or 'none'}")
    for name, val in out.items():
        field = _PREFIX + name
        if not math.isfinite(val):
            raise ModuliError(f"{field} must be a finite number (got {val})")
        if name == "nu":
            if not -1.0 < val < 0.5:
                raise _nu_error(field, val)
        elif name != "lambda" and val <= 0.0:
            raise ModuliError(f"{field} must be > 0 (got {_fmt(val)})")
    return out


def from_pair(values: Mapping[str, float], root: str = "plus") -> Moduli:
    """Build the full :class:`Moduli` from exactly two constants (see the module docstring).

    ``values`` keys: E, nu, lambda, mu, K, M ("G" is accepted for mu, "lmbda" for lambda).
    ``root`` selects the branch for the (E, M) pair only: "plus" gives nu >= 0, "minus"
    gives nu <= 0. Raises :class:`ModuliError` (a ValueError) naming the offending field.
    """
    if root not in ("plus", "minus"):
        raise ModuliError(f"{_PREFIX}root must be 'plus' or 'minus', got {root!r}")
    v = _canonical(values)
    names = tuple(k for k in KEYS if k in v)
    a, b = (v[k] for k in names)
    given = " and ".join(f"{_PREFIX}{k} = {_fmt(v[k])}" for k in names)

    def bad(why: str) -> ModuliError:
        return ModuliError(f"{given} give a non-physical solid: {why}; a stable isotropic "
                           f"solid needs mu > 0 and {_NU_RANGE}")

    def check(nu: float, mu: float) -> None:
        if not -1.0 < nu < 0.5:
            extra = f" ({_INCOMPRESSIBLE})" if abs(nu - 0.5) < 1e-12 else ""
            raise bad(f"nu = {_fmt(nu)}{extra}")
        if not mu > 0.0:
            raise bad(f"mu = {_fmt(mu)}")

    if names == ("E", "nu"):
        E, nu = a, b
        mu = E / (2 * (1 + nu))
        lm = E * nu / ((1 + nu) * (1 - 2 * nu))
        K = E / (3 * (1 - 2 * nu))
        M = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
    elif names == ("E", "lambda"):
        E, lm = a, b
        R = math.sqrt(E * E + 9 * lm * lm + 2 * E * lm)
        if lm < 0:
            nu = (R - E - lm) / (4 * lm)
            K = -2 * E * lm / (3 * (R - E - 3 * lm))
            mu = (E - 3 * lm + R) / 4
        else:
            nu = 2 * lm / (E + lm + R)
            K = (E + 3 * lm + R) / 6
            mu = 2 * E * lm / (R + 3 * lm - E) if lm > 0 else E / 2
        M = (E - lm + R) / 2
        check(nu, mu)
    elif names == ("E", "mu"):
        E, mu = a, b
        nu = E / (2 * mu) - 1
        check(nu, mu)  # nu < 0.5  <=>  3 mu - E > 0
        d = 3 * mu - E
        lm, K, M = mu * (E - 2 * mu) / d, E * mu / (3 * d), mu * (4 * mu - E) / d
    elif names == ("E", "K"):
        E, K = a, b
        nu = (3 * K - E) / (6 * K)
        if not nu > -1.0:  # nu > -1  <=>  9K - E > 0
            raise bad(f"nu = {_fmt(nu)}")
        d = 9 * K - E
        mu, lm, M = 3 * K * E / d, 3 * K * (3 * K - E) / d, 3 * K * (3 * K + E) / d
        check(nu, mu)
    elif names == ("E", "M"):
        E, M = a, b
        disc = (9 * M - E) * (M - E)
        if disc < 0:
            raise bad("no real nu solves M = E(1-nu)/((1+nu)(1-2nu)) for E/9 < M < E")
        S = math.sqrt(disc)
        if root == "plus":
            nu = (E - M + S) / (4 * M)
            mu = 2 * E * M / (3 * M + E + S)
            lm, K = (M - E + S) / 4, (3 * M - E + S) / 6
            check(nu, mu)
        else:
            nu = (E - M - S) / (4 * M)
            mu = (3 * M + E + S) / 8
            check(nu, mu)  # now M >= E, so M - E + S >= 0 and 3M - E + S > 0
            lm = -2 * M * (M - E) / (M - E + S) if M > E else 0.0
            K = 2 * E * M / (3 * (3 * M - E + S))
    elif names == ("nu", "lambda"):
        nu, lm = a, b
        if nu == 0.0:
            raise ModuliError(f"the pair ({_PREFIX}lambda, {_PREFIX}nu) is undefined at nu = 0 "
                              f"(then lambda = 0 for every E); give another pair, e.g. E and nu")
        mu = lm * (1 - 2 * nu) / (2 * nu)
        check(nu, mu)
        E, K, M = lm * (1 + nu) * (1 - 2 * nu) / nu, lm * (1 + nu) / (3 * nu), lm * (1 - nu) / nu
    elif names == ("nu", "mu"):
        nu, mu = a, b
        d = 1 - 2 * nu
        E, lm = 2 * mu * (1 + nu), 2 * mu * nu / d
        K, M = 2 * mu * (1 + nu) / (3 * d), 2 * mu * (1 - nu) / d
    elif names == ("nu", "K"):
        nu, K = a, b
        E, lm = 3 * K * (1 - 2 * nu), 3 * K * nu / (1 + nu)
        mu, M = 3 * K * (1 - 2 * nu) / (2 * (1 + nu)), 3 * K * (1 - nu) / (1 + nu)
    elif names == ("nu", "M"):
        nu, M = a, b
        E = M * (1 + nu) * (1 - 2 * nu) / (1 - nu)
        lm, mu, K = M * nu / (1 - nu), M * (1 - 2 * nu) / (2 * (1 - nu)), M * (1 + nu) / (3 * (1 - nu))
    elif names == ("lambda", "mu"):
        lm, mu = a, b
        if not lm + mu > 0:
            raise bad("lambda + mu <= 0 (nu <= -1)")
        nu = lm / (2 * (lm + mu))
        check(nu, mu)
        E, K, M = mu * (3 * lm + 2 * mu) / (lm + mu), lm + 2 * mu / 3, lm + 2 * mu
    elif names == ("lambda", "K"):
        lm, K = a, b
        mu = 3 * (K - lm) / 2
        check(0.0, mu)  # mu > 0  =>  3K - lambda > 2K > 0
        nu = lm / (3 * K - lm)
        check(nu, mu)
        E, M = 9 * K * (K - lm) / (3 * K - lm), 3 * K - 2 * lm
    elif names == ("lambda", "M"):
        lm, M = a, b
        mu = (M - lm) / 2
        check(0.0, mu)
        if not M + lm > 0:
            raise bad("M + lambda <= 0 (nu <= -1)")
        nu = lm / (M + lm)
        check(nu, mu)
        E, K = (M - lm) * (M + 2 * lm) / (M + lm), (M + 2 * lm) / 3
    elif names == ("mu", "K"):
        mu, K = a, b
        nu = (3 * K - 2 * mu) / (2 * (3 * K + mu))
        E, lm, M = 9 * K * mu / (3 * K + mu), K - 2 * mu / 3, K + 4 * mu / 3
    elif names == ("mu", "M"):
        mu, M = a, b
        if not M - mu > 0:
            raise bad("M <= mu (nu out of range)")
        nu = (M - 2 * mu) / (2 * (M - mu))
        check(nu, mu)
        E, lm, K = mu * (3 * M - 4 * mu) / (M - mu), M - 2 * mu, M - 4 * mu / 3
    else:  # ("K", "M")
        K, M = a, b
        mu = 3 * (M - K) / 4
        check(0.0, mu)
        nu = (3 * K - M) / (3 * K + M)
        E, lm = 9 * K * (M - K) / (3 * K + M), (3 * K - M) / 2
    check(nu, mu)
    moduli = Moduli(E=E, nu=nu, lmbda=lm, mu=mu, K=K, M=M)
    _check_magnitudes(moduli, v)
    return moduli


def _check_magnitudes(moduli: Moduli, given: Mapping[str, float]) -> None:
    """The given moduli (|lambda| unless 0) and the E, mu they imply within MODULUS_RANGE, MPa: forces, energies and their
    squares (residual norms) must stay inside double precision on any mesh; at 1e-300 MPa the
    squared nodal forces underflowed to 0, a residual read as 0 and a "converged" test off its
    curve by 1.7 %, at 1e300 they overflowed. Both ends of the range reproduce the analytic
    block curve to 1.2e-11 (measured, Neo-Hookean, stretch 1.5)."""
    lo, hi = MODULUS_RANGE
    values = moduli.as_dict()
    # the given constants, and the E and mu they imply (mu sets the force scale); a derived
    # lambda may be ~0 (nu ~ 0) and a derived K, M at most ~1700 E (nu = 0.4999): no range issue
    for name in dict.fromkeys([*given, "E", "mu"]):
        value = values[name]
        if name == "nu" or (name == "lambda" and value == 0.0) or lo <= abs(value) <= hi:
            continue
        origin = "" if name in given else " (derived from " + " and ".join(
            f"{_PREFIX}{k} = {_fmt(x)}" for k, x in given.items()) + ")"
        raise ModuliError(f"{_PREFIX}{name} = {_fmt(value)} MPa{origin} is outside the allowed range "
                          f"{lo:g}..{hi:g} MPa (|{name}|): beyond it the solver's forces and their "
                          f"squares under- or overflow double precision")

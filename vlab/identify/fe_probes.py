"""The exact first-order change of each instrument reading of a test along a sensitivity solution.

At a converged level the fitted constants p_j move the state by du/dp_j (zero on the prescribed
DOFs: K_ff du_f/dp_j = −g_f, vlab.identify.fe_levels) and the reactions by

    df/dp_j = g + K du/dp_j     on the prescribed DOFs,   0 on the free ones (equilibrium holds),

g = ∂f_int/∂p_j at fixed u (N per unit of p_j). A reading R(u, f) then moves by
dR/dp_j = ∂R/∂u · du/dp_j + ∂R/∂f · df/dp_j. A probe factory takes the prepared test and returns
``probe(level, du, df) -> (n_p,)``, du and df being (n_dofs, n_p), one column per constant.
Each reading's formula is in its factory's docstring (units: N, mm, MPa, rad); every one is
checked against whole-test finite differences in tests/test_fit_fe_kinds.py (Taylor test).
"""

from __future__ import annotations

import numpy as np

__all__ = ["prescribed", "load_cell", "extensometer", "torque", "end_stretch", "cavity_pressure",
           "liquid_pressure", "liquid_volume_ratio", "pole_height", "scaled"]


def prescribed(prepared, axis: int = 0):
    """A reading the test prescribes (grip stretch, twist, the cavity's stretch): dR/dp = 0."""
    return lambda level, du, df: np.zeros(du.shape[1])


def load_cell(prepared, axis: int = 0):
    """F_a = c_a Σ_{grip a} f (N, c_a the symmetry factor): dF_a/dp = c_a Σ_{grip a} df/dp."""
    dofs = np.asarray(prepared.loading.moving_dofs[axis])
    c = prepared.specimen.force_factor(axis)
    return lambda level, du, df: c * df[dofs].sum(axis=0)


def scaled(factory, factor_of):
    """A probe of ``factory`` times a constant of the prepared test (a load cell over A₀: stress)."""
    def make(prepared, axis: int = 0):
        probe, k = factory(prepared, axis), factor_of(prepared, axis)
        return lambda level, du, df: k * probe(level, du, df)
    return make


def extensometer(prepared, axis: int = 0):
    """e_a = |x_b − x_a| / L0 − 1 between the gauge marks (mirror images reflected back):
    de_a/dp = n_a · (δx_b − δx_a) / L0, n_a the unit vector between the deformed marks."""
    from vlab.geometry.symmetry import reflect_back
    from vlab.measure.instruments import extensometers

    space, specimen = prepared.space, prepared.specimen
    ext = extensometers(space, [specimen.extensometers[axis]], specimen.symmetry)[0]
    dim = ext._dim

    def marks(u):
        x = ext._X + ext._probe @ u.reshape(-1, dim)
        return [reflect_back(x[i], ext._signs[i], ext._planes) for i in (0, 1)]

    def probe(level, du, df):
        a, b = marks(level.evaluation.u)
        n = (b - a) / np.linalg.norm(b - a)
        out = np.empty(du.shape[1])
        for j in range(du.shape[1]):  # reflections only flip components: δx of a mark is linear in du
            d = ext._probe @ du[:, j].reshape(-1, dim)
            moved = [reflect_back(ext._X[i] + d[i], ext._signs[i], ext._planes)
                     - reflect_back(ext._X[i], ext._signs[i], ext._planes) for i in (0, 1)]
            out[j] = float(n @ (moved[1] - moved[0])) / ext.length0
        return out

    return probe


def _end_nodes(prepared):
    return np.asarray(prepared.loading.moving_dofs[0]) // 3


def torque(prepared, axis: int = 0):
    """T = Σ_end (y f_z − z f_y) (N·mm; y = Y + u_y, z = Z + u_z current, f the turning end's
    reactions): dT/dp = Σ (δu_y f_z + y δf_z − δu_z f_y − z δf_y)."""
    nodes = _end_nodes(prepared)
    X = prepared.space.node_coordinates[nodes]

    def probe(level, du, df):
        u, f = level.evaluation.u, level.evaluation.f_int
        y, z = X[:, 1] + u[3 * nodes + 1], X[:, 2] + u[3 * nodes + 2]
        fy, fz = f[3 * nodes + 1], f[3 * nodes + 2]
        return (du[3 * nodes + 1].T @ fz + df[3 * nodes + 2].T @ y
                - du[3 * nodes + 2].T @ fy - df[3 * nodes + 1].T @ z)

    return probe


def end_stretch(prepared, axis: int = 0):
    """λ = 1 + mean(u_x of the turning end) / L: dλ/dp = mean(δu_x) / L (a free end's; 0 held)."""
    nodes = _end_nodes(prepared)
    length = prepared.specimen.grip_separation[0]
    return lambda level, du, df: du[3 * nodes].mean(axis=0) / length


def cavity_pressure(prepared, axis: int = 0):
    """p = Σ f_i · X_i / (3 λ² V₀) over the cavity wall's nodes (MPa; λ = mean |x_i| / |X_i|):
    dp/dp = Σ δf_i · X_i / (3 λ² V₀) − 2 p δλ / λ, δλ = mean (x_i · δu_i) / (|x_i| |X_i|)."""
    nodes = _end_nodes(prepared)
    X = prepared.space.node_coordinates[nodes]
    R = np.linalg.norm(X, axis=1)
    V0 = prepared.specimen.area0[0]
    dofs = 3 * nodes[:, None] + np.arange(3)

    def probe(level, du, df):
        u, f = level.evaluation.u, level.evaluation.f_int
        x = X + u[dofs]
        r = np.linalg.norm(x, axis=1)
        lam = float(np.mean(r / R))
        p = float(np.sum(f[dofs] * X)) / (3.0 * lam * lam * V0)
        dlam = np.einsum("ni,nij->j", x / (r * R)[:, None], du[dofs]) / len(nodes)
        return np.einsum("ni,nij->j", X, df[dofs]) / (3.0 * lam * lam * V0) - 2.0 * p * dlam / lam

    return probe


def _wetted_volume_change(prepared):
    """(level, du) -> δV (n_p,): the enclosed volume's change, ∂V/∂x · δu over the wetted nodes."""
    from vlab.fe.liquid import enclosed_volume_gradient

    tri = np.asarray(prepared.loading.liquid.triangles)
    X = prepared.space.node_coordinates

    def change(level, du):
        nodes, grad = enclosed_volume_gradient(X + level.evaluation.u.reshape(-1, 3), tri)
        dofs = (3 * nodes[:, None] + np.arange(3)).ravel()
        return grad.ravel() @ du[dofs]

    return change


def liquid_pressure(prepared, axis: int = 0):
    """The chamber's liquid, p = K_f (V_p(t) − V) / V₀ under volume control (vlab.fe.liquid):
    dp/dp = −(K_f / V₀) δV, δV = ∂V/∂x · δu (the pumped V_p(t) is prescribed)."""
    change, k = _wetted_volume_change(prepared), prepared.loading.liquid.stiffness
    return lambda level, du, df: -k * change(level, du)


def liquid_volume_ratio(prepared, axis: int = 0):
    """v = (V₀ + V) / V₀ of the bulge's chamber: dv/dp = δV / V₀."""
    change, V0 = _wetted_volume_change(prepared), prepared.specimen.area0[0]
    return lambda level, du, df: change(level, du) / V0


def pole_height(prepared, axis: int = 0):
    """h = mean u_z over the pole's nodes (mm): dh/dp = mean δu_z."""
    X = prepared.space.node_coordinates
    pole = np.flatnonzero(prepared.specimen.regions["pole"](X))
    return lambda level, du, df: du[3 * pole + 2].mean(axis=0)

"""
Effects and protocols
=====================

One file per effect of the ``[effects]`` registry and per protocol: rate dependence, gravity, plasticity, Mullins softening (alone and with rate dependence), noisy instruments. A test with a protocol shows its protocol's plot (hysteresis, relaxation, creep).
"""

from gallery_helpers import show

# %%
# ``block-viscoelastic-relaxation.toml``
# --------------------------------------
#
# A 1 s ramp to stretch 1.2, then the stress relaxes towards the long-term modulus.

show('block-viscoelastic-relaxation')

# %%
# ``block-viscoelastic-creep.toml``
# ---------------------------------
#
# The force reached after the ramp is held (force control) and the block creeps.

show('block-viscoelastic-creep')

# %%
# ``block-gravity.toml``
# ----------------------
#
# Self-weight of a tall, soft gel block (density 1100 kg/m³) stretched along x.

show('block-gravity')

# %%
# ``block-plasticity-load-unload.toml``
# -------------------------------------
#
# J2 plasticity loaded past yield and unloaded: the permanent set.

show('block-plasticity-load-unload')

# %%
# ``block-mullins-cyclic.toml``
# -----------------------------
#
# Cycles of rising amplitude with Ogden–Roxburgh (Mullins) softening.

show('block-mullins-cyclic')

# %%
# ``block-viscoelastic-mullins-cyclic.toml``
# ------------------------------------------
#
# Both together: a two-term Prony series on the Maxwell branches and Ogden–Roxburgh softening of the
# long-term response, cycled to stretch 1.5, 2.0 and 2.5 at 0.1 /s. Each loop is rate-dependent
# hysteresis on top of the softened reloading path. The gallery runs 8 steps per ramp (the budget's
# 4 would draw each loop as a triangle).

show('block-viscoelastic-mullins-cyclic', {"test.steps": 8})

# %%
# ``block-noise.toml``
# --------------------
#
# Noisy instruments: E and ν reported with their 95 % intervals.

show('block-noise')

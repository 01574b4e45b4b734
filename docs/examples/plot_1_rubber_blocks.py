"""
Rubber models on a block
========================

Blocks between roller grips, each checked against the analytic homogeneous state (dashed in the curve): the built-in default scene and one file per rubber card of the model registry.
"""

from gallery_helpers import show

# %%
# ``block-neo-hookean.toml``
# --------------------------
#
# The built-in default scene (``vlab run`` without a file): a Neo-Hookean block pulled to 50 % stretch.

show('block-neo-hookean')

# %%
# ``block-mooney-rivlin.toml``
# ----------------------------
#
# A Mooney–Rivlin card with Treloar-type constants, to stretch 2.

show('block-mooney-rivlin')

# %%
# ``block-yeoh.toml``
# -------------------
#
# A Yeoh card in uniaxial compression (stretch 0.6).

show('block-yeoh')

# %%
# ``block-ogden.toml``
# --------------------
#
# Treloar's three-term Ogden card (Ogden 1972) to stretch 2.5.

show('block-ogden')

# %%
# ``block-gent.toml``
# -------------------
#
# A Gent card close to its locking limit (Jm = 10).

show('block-gent')

# %%
# ``block-arruda-boyce.toml``
# ---------------------------
#
# The eight-chain model in equibiaxial tension.

show('block-arruda-boyce')

# %%
# ``block-rubber-compare.toml``
# -----------------------------
#
# The scene of ``vlab compare specimens/block-rubber-compare.toml`` (five cards with μ0 = 0.6 MPa to stretch 3); here its own ``[material]`` card only.

show('block-rubber-compare')

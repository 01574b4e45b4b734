"""
Sheets and cruciforms
=====================

Thin sheets in plane stress and cruciforms for biaxial tests.
"""

from gallery_helpers import show

# %%
# ``sheet-strip-clamped.toml``
# ----------------------------
#
# A thin rubber strip between clamped grips: the lateral contraction is held at the grips.

show('sheet-strip-clamped')

# %%
# ``sheet-equibiaxial.toml``
# --------------------------
#
# A square membrane stretched equally along x and y by roller grips.

show('sheet-equibiaxial')

# %%
# ``cruciform-slotted.toml``
# --------------------------
#
# ISO 16842-style slotted arms, load ratio 2:1; E and ν from the per-axis readings.

show('cruciform-slotted')

# %%
# ``cruciform-thinned.toml``
# --------------------------
#
# An equibiaxial cruciform whose centre is thinned from 2 mm to 1 mm.

show('cruciform-thinned')

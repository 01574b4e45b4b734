"""
Planar tension and simple shear
===============================

The lab's specimens for pure shear and simple shear: a wide, short strip clamped along its long edges, a layer bonded between rigid plates and a double-lap sandwich. Their curves are stress against stretch, or shear and normal stress against the amount of shear γ.
"""

from gallery_helpers import show

# %%
# ``planar-tension-neo-hookean.toml``
# -----------------------------------
#
# Planar tension (pure shear) of a strip 100 mm wide and 10 mm high.

show('planar-tension-neo-hookean')

# %%
# ``shear-plates-neo-hookean.toml``
# ---------------------------------
#
# A layer between rigid plates: one plate held, the other moved along x.

show('shear-plates-neo-hookean')

# %%
# ``double-lap-neo-hookean.toml``
# -------------------------------
#
# Two layers around a rigid central plate, which moves.

show('double-lap-neo-hookean')

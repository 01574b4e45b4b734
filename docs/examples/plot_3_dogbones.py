"""
Dogbones, imported and CAD meshes
=================================

Dumb-bells of five standards between clamped grips, one from explicit dimensions, a user's Gmsh mesh and a dumb-bell drawn in CAD (Gmsh, the ``cad`` extra). E and ν are read by the extensometer over the standard's gauge length.
"""

from gallery_helpers import show

# %%
# ``dogbone-iso527-2-1a.toml``
# ----------------------------
#
# ISO 527-2 type 1A multipurpose bar.

show('dogbone-iso527-2-1a')

# %%
# ``dogbone-iso527-2-1ba.toml``
# -----------------------------
#
# ISO 527-2 type 1BA small bar (a finer gauge section).

show('dogbone-iso527-2-1ba')

# %%
# ``dogbone-astm-d638-iv.toml``
# -----------------------------
#
# ASTM D638 type IV.

show('dogbone-astm-d638-iv')

# %%
# ``dogbone-iso37-2.toml``
# ------------------------
#
# ISO 37 type 2 rubber dumb-bell on P2 tetrahedra.

show('dogbone-iso37-2')

# %%
# ``dogbone-astm-d412-c.toml``
# ----------------------------
#
# ASTM D412 die C rubber dumb-bell.

show('dogbone-astm-d412-c')

# %%
# ``dogbone-custom.toml``
# -----------------------
#
# A dogbone from explicit dimensions, the keys the shipped standards use.

show('dogbone-custom')

# %%
# ``mesh-import-bar.toml``
# ------------------------
#
# A user's mesh (``meshes/bar.msh``, Gmsh 2.2) with physical groups as grips.

show('mesh-import-bar')

# %%
# ``dogbone-cad-1a.toml``
# -----------------------
#
# A dumb-bell drawn in CAD (``cad/dumbbell-1a.geo``) meshed by Gmsh and Netgen.

show('dogbone-cad-1a')

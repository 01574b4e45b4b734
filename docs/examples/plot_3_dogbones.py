"""
Dogbones, imported and CAD meshes
=================================

Dumb-bells of five standards between clamped grips, one from explicit dimensions, one watched by a virtual camera with DIC, a user's Gmsh mesh and a dumb-bell drawn in CAD (Gmsh, the ``cad`` extra). E and ν are read by the extensometer over the standard's gauge length.
"""

from gallery_helpers import SCRATCH, show, show_images

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
# ``dogbone-dic.toml``
# --------------------
#
# A small dogbone whose top face a virtual camera watches (``[instruments.dic]``): the speckled
# face is rendered at every level from the FE displacement, correlated by vlab's DIC, and the
# report holds the DIC virtual extensometer's E and ν beside the point extensometers' and the
# last level's DIC, FE levelled through the same subsets and strain window, and their difference.

show('dogbone-dic')
show_images([SCRATCH / 'dogbone-dic' / 'dic' / 'maps.png'], 'dogbone-dic: DIC, levelled FE and their difference')

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

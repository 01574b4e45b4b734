"""Subset-based 2-D digital image correlation (DIC) and the speckle images it is tested on.

- :mod:`vlab.dic.images` reads and writes grey images (8- or 16-bit PNG or TIFF);
- :mod:`vlab.dic.speckle` is an analytic speckle pattern (a sum of Gaussians) rendered exactly
  through a known displacement (each pixel integrated by supersampling), the oracle of the tests;
- :mod:`vlab.dic.seed` finds the integer displacement of each subset (FFT cross-correlation);
- :mod:`vlab.dic.icgn` refines it (inverse-compositional Gauss–Newton, affine shape function,
  bicubic B-spline interpolation), vectorised over subsets;
- :mod:`vlab.dic.strain` the strain window (local least-squares plane → Green–Lagrange strain);
- :mod:`vlab.dic.correlate` joins them; :mod:`vlab.dic.command` is ``vlab dic``.
- :mod:`vlab.dic.metrics` the DIC Challenge 2.0 metrics on synthetic images,
  :mod:`vlab.dic.resolution` the spatial resolution and MEI of a scene's own camera.

Image coordinates throughout: x to the right (column), y down (row), in pixels, the centre of
pixel (row i, column j) at (x, y) = (j, i).
"""

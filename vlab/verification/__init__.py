"""The verification suite: hard cases run end to end against known answers (`vlab stability`:
limit points, inversion, missing grips, buckling against Euler, incompressible dumb-bells) and
fixed benchmark problems (Cook's membrane). It sits above run: it runs scenes and writes reports."""

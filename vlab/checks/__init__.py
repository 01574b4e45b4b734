"""Run-time checks of a test: admissibility of a request, and the stability of every converged
state (inertia of the tangent, load limit points, buckling modes, seeded imperfections).
The restraint of a set-up (rigid-body modes left free) is checked in vlab.loading.restraint."""

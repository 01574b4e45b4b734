"""Stability of a test: admissibility of a request, restraint of the set-up, and the stability of
every converged state (inertia of the tangent, load limit points)."""

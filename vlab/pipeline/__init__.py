"""The three stages vlab.run sequences: prepare (mesh, space, body, grips), solve (load stepping
with a list of observers) and measure (curve, E and ν, analytic reference, diagnostics), and the
typed result they produce (RunResult, Diagnostics, SolverObjects)."""

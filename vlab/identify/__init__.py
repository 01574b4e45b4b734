"""Material-parameter identification: ``vlab fit``.

laws.py        the models in principal stretches (w_i = λ_i ∂ψ/∂λ_i), their card names and bounds
states.py      homogeneous responses of the test kinds (incompressible, or compressible with K)
jacobian.py    exact parameter derivatives of any response by the complex step
fitfile.py     the fit file (validated like a scene) and datasets.py: the CSVs
solve.py       bounded least squares from many seeded starts
uncertainty.py covariance, intervals, correlations, delta-method bands, identifiability
drucker.py     Drucker stability of a card along each kind and over the (λ1, λ2) plane
fitting.py     FITFILE -> result dict; ranking.py: several models; report.py: fit.json + index.html
specimens.py   several specimens (data.specimen): a fit per specimen, the pooled fit, statistics
card.py        the fitted [material] card (an incompressible fit's K = K_over_mu · μ0, stated)
fe_loop.py     FE in the loop: a specimen's instrument readings fitted through vlab's own test
fe_spec.py     its [fe] table; fe_stress.py: flat constants and ∂P/∂p of every model (complex step)
fe_levels.py   sensitivities per recorded level with the step's factor; fe_sensitivity.py: one
               whole test (cached); fe_dask.py: the whole-test solves on a Dask cluster
"""

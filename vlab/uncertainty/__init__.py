"""Uncertainty budgets of a virtual test: ``vlab budget``.

classes.py   ISO 7500-1 load-cell and ISO 9513 extensometer classes, dogbone tolerances (cited)
spec.py      the scene's [uncertainty] table, validated: the input quantities and their distributions
model.py     one sample: the perturbed scene (remeshed specimen, card, window, resolution) and the
             lab's analysis (nominal dimensions, instrument errors)
analysis.py  linearised GUM from paired runs, Monte Carlo statistics, first-order Sobol indices
budget.py    the paired runs and the samples as sweeps (Dask, cache, resume), then the budget
report.py    budget.json, samples.csv, tornado and histogram PNGs, index.html; command.py: the CLI
"""

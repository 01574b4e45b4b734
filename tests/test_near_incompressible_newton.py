"""Near-incompressible Newton (issue 20): the mixed Q1/P0 body converges like a displacement one.

Iteration counts, not times, are asserted: ≤ 6 Newton iterations in every one of 10 load steps
on de Souza Neto's Cook's membrane (ν = 0.4999) and on deal.II step-44's block, with the same
answer as Newton on W(u) alone (θ recomputed at every iterate), which needs cutbacks on the block."""

import pytest

from vlab.fe.newton import NewtonOptions
from vlab.verification.cooks_membrane import SOUZA_NETO, CookCase, solve_cook
from vlab.verification.step44_block import solve_block

MAX_PER_STEP = 6


def test_cooks_membrane_q1p0_at_nu_4999_converges_in_at_most_six_iterations_per_step():
    three_field = solve_cook(CookCase(order=1, divisions=4, **SOUZA_NETO))
    reduced = solve_cook(CookCase(order=1, divisions=4, three_field=False, **SOUZA_NETO))
    assert len(three_field.per_step) == 10 and max(three_field.per_step) <= MAX_PER_STEP
    assert three_field.tip_uy == pytest.approx(reduced.tip_uy, rel=1e-6)
    assert three_field.iterations < reduced.iterations


def test_step44_block_q1p0_converges_in_at_most_six_iterations_per_step_without_cutbacks():
    block = solve_block(4)
    assert not block.failure and len(block.per_step) == 10, block
    assert max(block.per_step) <= MAX_PER_STEP and block.iterations == sum(block.per_step)
    assert 0.5 < block.compression < 0.9  # mm: heavily compressed, not inverted


def test_the_watchdog_takes_full_steps_the_monotone_line_search_halves():
    """The first full step of a load step raises W near ν = ½; the watchdog accepts it (and W
    comes back below its reference), the monotone line search halves it and needs more steps."""
    case = CookCase(order=1, divisions=4, **SOUZA_NETO)
    watchdog = solve_cook(case)
    monotone = solve_cook(case, NewtonOptions(rtol=1e-9, max_iterations=30, watchdog=0))
    assert watchdog.tip_uy == pytest.approx(monotone.tip_uy, rel=1e-9)
    assert sum(watchdog.per_step) < sum(monotone.per_step)

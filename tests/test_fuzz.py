"""Property test: any scene either converges with sane invariants or fails cleanly with a cause."""

import collections
import json
import os

import pytest
from hypothesis import HealthCheck, event, given, settings

from fuzz_scenes import run_and_check, scenes

OUTCOMES: collections.Counter = collections.Counter()


@settings(max_examples=100, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(scenes())
def test_random_scenes_converge_sanely_or_fail_cleanly(raw):
    outcome = run_and_check(raw)  # asserts the invariants of the outcome it reports
    assert outcome != "stopped: other", "a stop whose cause is none of the diagnosed kinds"
    event(outcome)


@settings(max_examples=15, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(scenes(mixed_only=True))
def test_random_mixed_formulation_scenes_converge_sanely_or_fail_cleanly(raw):
    outcome = run_and_check(raw)
    assert outcome != "stopped: other", "a stop whose cause is none of the diagnosed kinds"
    event(outcome)


@pytest.mark.slow
@settings(max_examples=1000, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(scenes())
def test_a_thousand_random_scenes(raw):
    outcome = run_and_check(raw)
    assert outcome != "stopped: other", "a stop whose cause is none of the diagnosed kinds"
    OUTCOMES[outcome] += 1
    event(outcome)
    path = os.environ.get("VLAB_FUZZ_OUTCOMES")
    if path:
        with open(path, "w") as fh:
            json.dump(dict(OUTCOMES), fh, indent=1)

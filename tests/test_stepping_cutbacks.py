"""The substeps of one load level (vlab.fe.stepping._Cutbacks): halving on failure, doubling
after easy steps, and no try beyond a state the stability monitor rejected, so a run stops on the
instability it found rather than on a non-convergence past it (the perfectly plastic strip of
tests/test_diagnosis_words.py stopped with "no convergence in 25 iterations" under SuperLU)."""

from vlab.fe.newton import NewtonFailure, NewtonRecord
from vlab.fe.stepping import Rejected, _Cutbacks


def _record():
    return NewtonRecord()


def test_a_failure_halves_the_substep_and_an_easy_step_doubles_it():
    steps = _Cutbacks(max_cutbacks=4)
    assert steps.next_try(0.0) == 1.0
    assert steps.failed(NewtonFailure("no convergence", _record(), None), 1.0, 1.0) is None
    assert steps.next_try(0.0) == 0.5
    steps.accepted(0.5, easy=True)
    assert steps.next_try(0.5) == 1.0


def test_no_substep_goes_beyond_a_rejected_state():
    steps = _Cutbacks(max_cutbacks=6)
    steps.failed(Rejected("loss of stability", _record(), None), 1.0, 2.0)
    assert steps.next_try(0.0) == 0.5
    steps.accepted(0.5, easy=True)  # ds back to 1: the next try would be 1.5, but 1.0 was rejected
    assert steps.next_try(0.5) == 1.0
    steps.failed(Rejected("loss of stability", _record(), None), 0.75, 1.75)
    steps.accepted(0.625, easy=True)
    assert steps.next_try(0.625) == 0.75  # the lower rejection is the ceiling now


def test_a_rejected_state_accepted_later_lifts_the_ceiling():
    steps = _Cutbacks(max_cutbacks=6)
    steps.failed(Rejected("limit point", _record(), None), 0.5, 0.5)
    steps.accepted(0.5, easy=False)  # reached again from nearer and accepted (another branch)
    assert steps.ceiling == 1.0 and steps.next_try(0.5) == 1.0


def test_the_run_stops_on_the_last_rejection_not_on_a_later_non_convergence():
    steps = _Cutbacks(max_cutbacks=2)
    unstable = Rejected("no stable state beyond stretch 1.018", _record(), None)
    assert steps.failed(unstable, 1.0, 1.02) is None
    assert steps.failed(NewtonFailure("no convergence in 25 iterations", _record(), None), 0.5, 1.01) is None
    t, failure = steps.failed(NewtonFailure("no convergence in 25 iterations", _record(), None), 0.25, 1.005)
    assert failure is unstable and t == 1.02


def test_without_a_rejection_the_last_failure_is_diagnosed():
    steps = _Cutbacks(max_cutbacks=1)
    steps.failed(NewtonFailure("first", _record(), None), 1.0, 1.0)
    t, failure = steps.failed(NewtonFailure("second", _record(), None), 0.5, 0.5)
    assert failure.reason == "second" and t == 0.5

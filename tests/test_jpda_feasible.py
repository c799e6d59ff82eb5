"""Eq. (1) of the JPDA chapter (Table I) against brute-force enumeration."""

import itertools

import numpy as np
import pytest

from projtrack.jpda import count_feasible_events, iter_feasibility_matrices


def _brute_force_count(m: int, T: int) -> int:
    """Count assignments of m measurements to {clutter, 1..T}, each target used at most once."""
    count = 0
    for assign in itertools.product(range(T + 1), repeat=m):
        used = [t for t in assign if t]
        if len(used) == len(set(used)):
            count += 1
    return count


@pytest.mark.parametrize("m", range(0, 6))
@pytest.mark.parametrize("T", range(0, 6))
def test_eq1_equals_brute_force(m, T):
    assert count_feasible_events(m, T) == _brute_force_count(m, T)


@pytest.mark.parametrize("m,T", [(1, 1), (2, 3), (4, 4), (5, 2), (3, 5)])
def test_enumerator_matches_eq1_and_yields_feasible_matrices(m, T):
    mats = list(iter_feasibility_matrices(np.ones((m, T + 1), dtype=int)))
    assert len(mats) == count_feasible_events(m, T)
    assert len({m_.tobytes() for m_ in mats}) == len(mats)  # all distinct
    for omega in mats:
        assert np.all(omega.sum(axis=1) == 1)  # one event per measurement
        assert np.all(omega[:, 1:].sum(axis=0) <= 1)  # a target explains at most one


def test_fig2_example_has_eight_feasibility_matrices():
    # Validation matrix of Fig. 1 of the chapter: rows 110, 111, 101.
    v = np.array([[1, 1, 0], [1, 1, 1], [1, 0, 1]])
    mats = list(iter_feasibility_matrices(v))
    assert len(mats) == 8
    assert all(np.all(om <= v) for om in mats)


def test_table1_corner_and_symmetry():
    assert count_feasible_events(10, 10) == 234_662_231
    assert count_feasible_events(7, 3) == count_feasible_events(3, 7) == 358
    assert count_feasible_events(0, 4) == 1


@pytest.mark.parametrize("bad", [-1, 2.5, "3", None, True])
def test_count_rejects_bad_sizes(bad):
    with pytest.raises((TypeError, ValueError), match="m must"):
        count_feasible_events(bad, 2)
    with pytest.raises((TypeError, ValueError), match="T must"):
        count_feasible_events(2, bad)


def test_enumerator_rejects_bad_validation_matrices():
    with pytest.raises(ValueError, match="2-D"):
        list(iter_feasibility_matrices(np.ones(3)))
    with pytest.raises(ValueError, match="only 0 and 1"):
        list(iter_feasibility_matrices(np.full((2, 2), 2)))
    with pytest.raises(ValueError, match="clutter column"):
        list(iter_feasibility_matrices(np.array([[0, 1], [1, 1]])))


def test_colexicographic_order_places_the_papers_cases_1_and_5():
    v = np.array([[1, 1, 0], [1, 1, 1], [1, 0, 1]])
    case1 = np.array([[1, 0, 0]] * 3)
    case5 = np.array([[0, 1, 0], [0, 0, 1], [1, 0, 0]])
    colex = list(iter_feasibility_matrices(v, order="colexicographic"))
    lex = list(iter_feasibility_matrices(v))
    assert np.array_equal(colex[0], case1) and np.array_equal(colex[4], case5)
    assert not np.array_equal(lex[4], case5)  # the default order differs
    assert sorted(m_.tobytes() for m_ in colex) == sorted(m_.tobytes() for m_ in lex)
    # measurement 1's target changes fastest
    first_rows = [int(np.argmax(m_[0])) for m_ in colex[:2]]
    assert first_rows == [0, 1]


def test_enumerator_rejects_unknown_order():
    with pytest.raises(ValueError, match="order must be"):
        list(iter_feasibility_matrices(np.ones((2, 2), dtype=int), order="random"))

"""The vectorised pair bookkeeping against Becker and Weispfenning's UPDATE, transcribed literally.

Reference: T. Becker and V. Weispfenning, "Groebner Bases", Springer 1993,
p. 230 (procedure UPDATE), run on plain tuples. The pairs {h, g} are popped
from C in decreasing order of g, so that of several pairs with one lcm the one
with the least g is the one the loop keeps (the popped pair is dropped while an
equal one remains in C), the representative :class:`CriticalPairs` picks; with
that, both must hold exactly the same pairs after every step.
"""

from __future__ import annotations

import random

import pytest

from observability.identifiability.order import degrevlex_key
from observability.identifiability.pairs import CriticalPairs


def _lcm(a, b):
    return tuple(map(max, a, b))


def _divides(a, b):
    return all(x <= y for x, y in zip(a, b))


def _coprime(a, b):
    return all(x == 0 or y == 0 for x, y in zip(a, b))


def _bw_update(G, B, h, leads):
    """[BW] p. 230, line by line."""
    lh = leads[h]
    C = [(g, h) for g in sorted(G, reverse=True)]
    D = []
    while C:
        g1, _ = C.pop(0)
        common = _lcm(lh, leads[g1])
        if _coprime(lh, leads[g1]) or not any(_divides(_lcm(lh, leads[g2]), common) for g2, _ in C + D):
            D.append((g1, h))
    E = [(g, h) for g, h in D if not _coprime(lh, leads[g])]
    kept = []
    for g1, g2 in B:
        common = _lcm(leads[g1], leads[g2])
        if not _divides(lh, common) or _lcm(leads[g1], lh) == common or _lcm(leads[g2], lh) == common:
            kept.append((g1, g2))
    return [g for g in G if not _divides(lh, leads[g])] + [h], kept + E


def _random_monomial(rng, nvars):
    return tuple(rng.choice((0, 0, 1, 1, 2, 3)) for _ in range(nvars))


@pytest.mark.parametrize("seed", range(60))
def test_the_pairs_are_those_of_becker_and_weispfenning_update(seed):
    rng = random.Random(seed)
    nvars = rng.randint(2, 6)
    pairs, leads, G, B = CriticalPairs(nvars), [], [], []
    popped = 0
    for _ in range(rng.randint(5, 40)):
        if B and rng.random() < 0.4:
            a, b = pairs.pop()
            least = min(degrevlex_key(_lcm(leads[x], leads[y])) for x, y in B)
            assert (a, b) in B and degrevlex_key(_lcm(leads[a], leads[b])) == least
            B.remove((a, b))
            popped += 1
        else:
            leads.append(_random_monomial(rng, nvars))
            assert pairs.add(leads[-1]) == len(leads) - 1
            G, B = _bw_update(G, B, len(leads) - 1, leads)
        assert sorted(pairs.basis) == sorted(G)
        assert len(pairs) == len(B)
    drained = [pairs.pop() for _ in range(len(B))]
    assert sorted(drained) == sorted(B)
    keys = [degrevlex_key(_lcm(leads[a], leads[b])) for a, b in drained]
    assert keys == sorted(keys)


def test_the_criteria_by_hand():
    """x*y joins x, y, x*y**2 (numbered 0, 1, 2, then 3).
    - Before it: {x, y} is coprime (never formed); {x, x*y**2} and {y, x*y**2} share the lcm x*y**2, so one stays,
      {x, x*y**2} (the least g).
    - Its new pairs: with x and with y the lcm x*y (neither coprime to x*y), so one pair of that class stays,
      {x, x*y}; with x*y**2 the lcm x*y**2, a multiple of x*y: dropped.
    - The old pair {x, x*y**2}: x*y divides its lcm x*y**2, but lcm(x*y**2, x*y) is that lcm, so the chain
      criterion keeps it.
    - x*y**2 leaves the basis (x*y divides it).
    Left: {x, x*y} (degree 2), then {x, x*y**2} (degree 3)."""
    pairs = CriticalPairs(2)
    for lead in [(1, 0), (0, 1), (1, 2), (1, 1)]:
        pairs.add(lead)
    assert sorted(pairs.basis) == [0, 1, 3]
    assert [pairs.pop() for _ in range(len(pairs))] == [(0, 3), (0, 2)]


def test_a_coprime_pair_takes_its_lcm_class_with_it():
    """y joins x and x*y: with x the lcm x*y (coprime), with x*y the lcm x*y: one class with a coprime member, so no
    new pair (Buchberger's first criterion: {x, y} reduces to zero, and {x*y, y} has the same lcm). The old pair
    {x, x*y}: y divides its lcm x*y, and lcm(x*y, y) = x*y equals it: kept. x*y leaves the basis."""
    pairs = CriticalPairs(2)
    for lead in [(1, 0), (1, 1), (0, 1)]:
        pairs.add(lead)
    assert sorted(pairs.basis) == [0, 2]
    assert [pairs.pop() for _ in range(len(pairs))] == [(0, 1)]

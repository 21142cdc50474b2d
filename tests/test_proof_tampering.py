"""A tampering corpus (issue 61): genuine proofs of models of every kind, each edited
in every field the checker reads; with the model tied (``verify-proof --model``)
every edit is refused and every genuine proof accepted. By hand, then by
hypothesis: whatever one field becomes, the checker never accepts a claim other
than the true one (the genuine proof's rank, which the hand derivations below give).
"""

from __future__ import annotations

import copy
import functools
import json

import pytest
import sympy
from hypothesis import given, strategies as st

from observability import models
from observability.analysis.verdict import analyze
from observability.model.system import System
from observability.rank import proofcheck
from observability.report.proofs import proof_evidence, proof_model

#: (system, true rank by hand), one of each kind.
CORPUS = {
    # polynomial, with an input: L_f h = u' x1^2 beside h's gradient (issue 31): 2 of 2.
    "polynomial": (System(["x1", "x2"], {"x1": "x2", "x2": "-u*x1"}, {"h": "u*x1**2 + x2**2"}, inputs=["u"],
                          name="pendulum"), 2),
    # rational: f d (x_L - c) sees c, x_L, d only through x_L - c and a scale: translation and scaling, 2 of 4.
    "rational": (models.build("slam1.5d"), 2),
    # trigonometric: the unicycle's squared distance to the origin keeps the rotation about it, 2 of 3.
    "trigonometric": (System(["x", "y", "th"], {"x": "v*cos(th)", "y": "v*sin(th)", "th": "w"},
                             {"r": "x**2 + y**2"}, inputs=["v", "w"], name="trig"), 2),
    # exp and log: y = e^a + log b is one function of two constants, 1 of 2.
    "exp-log": (System(["a", "b"], {"a": "0", "b": "0"}, {"y": "exp(a) + log(b)"}, name="explog"), 1),
    # a root inside an expression: y = x + sqrt(z + 1), constants, 1 of 2.
    "root": (System(["x", "z"], {"x": "0", "z": "0"}, {"y": "x + sqrt(z + 1)"}, name="inside"), 1),
    # a root analysed through its radicand: 3 sqrt(x^2 + y^2) sees the distance only, 1 of 2.
    "radicand": (System(["x", "y"], {"x": "0", "y": "0"}, {"r": "3*sqrt(x**2 + y**2)"}, name="range"), 1),
    # discrete time: slam1.5d's map keeps the translation and the scaling, 2 of 4.
    "discrete": (models.build("slam1.5d", {"time": "discrete"}), 2),
    # a continuous invariant span: x3' = x3^3 keeps the span of d/dx3, y = x1 sees x1, x2: 2 of 3.
    "span": (System(["x1", "x2", "x3"], {"x1": "x2", "x2": "0", "x3": "x3**3"}, {"y": "x1"}, name="cubic"), 2),
    # a discrete invariant span: every row is a gradient of z b (test_proof.py), 1 of 4.
    "discrete span": (System(["x", "y", "z", "b"], {"x": "2*x", "y": "y**3", "z": "z", "b": "b"}, {"h": "z*b"},
                             time="discrete", name="discrete-span"), 1),
    # an unknown input of degree 1: x, x' = v, x'' = w, x''' = w' from y = x: 4 of 4.
    "unknown input": (System(["x", "v"], {"x": "v", "v": "w"}, {"y": "x"}, unknown_inputs=["w"],
                             unknown_input_degree=1, name="unknown"), 4),
    # a free parameter: y1 = x1 + x2 and y2 = p (x1 + x2) see one function, 1 of 2.
    "parameter": (System(["x1", "x2"], {"x1": "0", "x2": "0"}, {"y1": "x1 + x2", "y2": "p*(x1 + x2)"},
                         parameters=["p"], name="line"), 1),
    # a known parameter value: x1' = 3 x2, y = x1 gives x1 and 3 x2: 2 of 2.
    "known value": (System(["x1", "x2"], {"x1": "k*x2", "x2": "0"}, {"y": "x1"}, parameters={"k": 3},
                           name="known"), 2),
    # a generator that moves with an input (x1' = u x2, h = x2): 1 of 2.
    "input generator": (System(["x1", "x2"], {"x1": "u*x2", "x2": "0"}, {"h": "x2"}, inputs=["u"], name="drift"), 1),
    # a branch on a region: h1 = |sin x| + sin x is 2 sin x on (0, pi) (slope 2 cos x), 0 on (pi, 2 pi); h2 = y:
    # 2 of 2 around the point (x = 7/5 at seed 1, in (0, pi)), 1 on the other region.
    "branch": (System(["x", "y"], {"x": "0", "y": "0"}, {"h1": "sqrt(1 - cos(x)**2) + sin(x)", "h2": "y"},
                      name="abs-sine"), 2),
    # atan2 off its cut, with a generator: the angle of (x1, x2) is kept by the scaling (x1, x2), 1 of 2.
    "atan2": (System(["x1", "x2"], {"x1": "0", "x2": "0"}, {"y": "atan2(x2, x1)"}, name="angle"), 1),
}
#: The words a claim adds on a region (the file format): the functions with branches listed.
REGION = " on the region around the point where its functions with branches ({}) are analytic (the rank may differ on other regions)"
#: The functions with branches each proof's claim is qualified by, by hand ([]: the whole domain). exp-log: log b
#: is analytic on b > 0, a half-space; root: sqrt(z + 1) on z > -1, a half-space; radicand: sqrt(x^2 + y^2)
#: off the origin, whose complement is connected (codimension 2); branch: 1 - cos(x)^2 = sin(x)^2 vanishes
#: on every x = k pi, which cut the line into pieces; atan2 is not analytic on its cut x1 <= 0, x2 = 0. The
#: others have no function with branches.
REGIONS = {"branch": ["sqrt(1 - cos(x)**2)"], "atan2": ["atan2(x2, x1)"]}


@functools.cache
def _written(kind: str) -> tuple[str, str]:
    """The genuine proof and the model table to tie it to, as the JSON text the
    writer gives: data computed once, with nothing of the checker (a cached
    verdict of the checker would be reused by mutation runs, which fork after
    the first call, and hide the checker's mutants)."""
    system, rank = CORPUS[kind]
    result = analyze(system, seed=1)
    assert (result.rank, result.proof) == (rank, "proven"), kind
    return json.dumps(proof_evidence(system, result)), json.dumps(proof_model(system))


def _genuine(kind: str) -> tuple[str, dict, dict]:
    """(the accepted line, the genuine proof, the model table to tie it to): the
    checker run afresh on the written proof."""
    proof, model = (json.loads(text) for text in _written(kind))
    return proofcheck.check(copy.deepcopy(proof), model), proof, model


def _claimed(p: dict, rank: int, n: int) -> None:
    p.update(rank=rank, n_states=n, claim=f"the generic rank of the observability matrix of {p['model']['name']} is "
                                          f"{rank} of {n}")


def _edits(proof: dict) -> dict:
    """Every field the checker reads, edited so that the proof no longer holds."""
    n, r = proof["n_states"], proof["rank"]
    lower, model = proof["lower_bound"], proof["model"]
    others = [*model["parameters"], *model["inputs"], *model["outputs"]]
    first = model["states"][0]
    minor = lower["minor"]
    edits = {
        "claim": lambda p: p.update(claim=p["claim"].replace(f"{r} of {n}", f"{n if r < n else r - 1} of {n}")),
        "n_states": lambda p: p.update(n_states=n + 1),
        "n_states and claim": lambda p: _claimed(p, r, n + 1),
        "exact flag": lambda p: p["lower_bound"].update(exact=not lower["exact"]),
        "minor value": lambda p: p["lower_bound"].update(
            minor=str(sympy.Rational(minor) + 1) if lower["exact"] else str(float(minor) * 1.001)),
        "point: a state dropped": lambda p: p["lower_bound"]["point"]["states"].pop(first),
        "point: a value not a number": lambda p: p["lower_bound"]["point"]["states"].update({first: "x"}),
        "row of an order no proof needs": lambda p: p["lower_bound"]["rows"].__setitem__(
            0, [lower["rows"][0][0] if lower["rows"] else next(iter(model["outputs"])), n + 1]),
        "dynamics": lambda p: p["model"]["dynamics"].update({first: f"{model['dynamics'][first]} + 1"}),
        "outputs": lambda p: p["model"]["outputs"].update(
            {k: f"2*({v}) + {first}" for k, v in list(model["outputs"].items())[:1]}),
        "state renamed": lambda p: p["model"].update(states=["renamed", *model["states"][1:]]),
        "model name": lambda p: (p["model"].update(name="other"), _claimed(p, r, n)),
        "time": lambda p: p["model"].update(time="discrete" if model["time"] == "continuous" else "continuous"),
        "a generator added": lambda p: p["upper_bound"]["generators"].append({"name": "extra", "vector": {first: "1"}}),
    }
    if r < n:
        edits["rank up"] = lambda p: _claimed(p, r + 1, n)
        edits["a generator zero"] = lambda p: p["upper_bound"]["generators"].__setitem__(0, {"name": "z", "vector": {}})
        edits["a generator with a parameter's component"] = lambda p: p["upper_bound"]["generators"][0]["vector"].update(
            {others[0] if others else "t": "1"})
    if r > 0:
        edits["rank down"] = lambda p: _claimed(p, r - 1, n)
        edits["a column to a parameter, input or output"] = lambda p: p["lower_bound"]["columns"].__setitem__(
            0, others[0] if others else "t")
        if r > 1:
            edits["rows: one listed twice"] = lambda p: p["lower_bound"]["rows"].__setitem__(0, lower["rows"][-1])
        edits["rows: one of no output"] = lambda p: p["lower_bound"]["rows"].__setitem__(0, ["nothing", 0])
    if model["parameters"]:
        name = next(iter(model["parameters"]))
        edits["parameter value"] = lambda p: p["model"]["parameters"].update({name: "7"})
    if model.get("analysed_outputs"):
        name = next(iter(model["analysed_outputs"]))
        edits["radicand"] = lambda p: p["model"]["analysed_outputs"].update({name: "x**2"})
    return edits | _region_edits(proof)


def _region_edits(proof: dict) -> dict:
    """The claim's region edited: dropped with the claim cut back to the whole
    domain, added to a claim about the whole domain, or naming other functions."""
    bare = f"the generic rank of the observability matrix of {proof['model']['name']} is {proof['rank']} of " \
           f"{proof['n_states']}"
    region = proof.get("region")
    added = {"qualified": True, "where": [f"sqrt({proof['model']['states'][0]})"]}
    edits = {"region: the claim's words with a region of other functions": lambda p: p.update(
                 claim=bare + REGION.format(added["where"][0]), region=added),
             "region: its qualified flag false": lambda p: p.update(region={**(region or added), "qualified": False})}
    if region:
        edits["region: stripped, claim cut back"] = lambda p: (p.pop("region"), p.update(claim=bare))
        edits["region: stripped, claim kept"] = lambda p: p.pop("region")
        edits["region: claim cut back, region kept"] = lambda p: p.update(claim=bare)
        edits["region: a function dropped from it"] = lambda p: p.update(region={"qualified": True, "where": []})
    else:
        edits["region: added to a claim about the whole domain"] = lambda p: p.update(region=added)
        edits["region: its words added to the claim"] = lambda p: p.update(claim=bare + REGION.format("sqrt(x)"))
    return edits


@pytest.mark.parametrize("kind", list(CORPUS))
def test_every_edit_of_a_genuine_proof_is_refused(kind):
    """Each genuine proof is accepted with the model it was written for, and every
    edit of _edits refused."""
    line, proof, model = _genuine(kind)
    rank, n = CORPUS[kind][1], CORPUS[kind][0].n
    assert line.startswith(f"accepted: the generic rank of the observability matrix of {model['name']} is {rank} of {n} (")
    for name, edit in _edits(proof).items():
        tampered = copy.deepcopy(proof)
        edit(tampered)
        accepted, lines = proofcheck._answer(json.dumps(tampered), model)
        assert not accepted and lines[0].startswith("rejected: "), (kind, name, lines)


@pytest.mark.parametrize("kind", list(CORPUS))
def test_the_claim_and_region_are_the_ones_derived_by_hand(kind):
    """Each proof states its rank on the whole domain, or on the region around its
    point where the functions REGIONS lists (by hand, above) are analytic: its
    "claim" and "region" fields are exactly those words."""
    _, proof, model = _genuine(kind)
    rank, n = CORPUS[kind][1], CORPUS[kind][0].n
    bare = f"the generic rank of the observability matrix of {model['name']} is {rank} of {n}"
    where = REGIONS.get(kind, [])
    assert proof["claim"] == bare + (REGION.format(", ".join(where)) if where else "")
    assert proof.get("region") == ({"qualified": True, "where": where} if where else None)


FIELDS = st.sampled_from([
    ("rank",), ("n_states",), ("claim",), ("model", "name"), ("model", "time"), ("model", "states"),
    ("model", "inputs"), ("model", "parameters"), ("model", "dynamics"), ("model", "outputs"),
    ("model", "analysed_outputs"), ("lower_bound", "rows"), ("lower_bound", "columns"), ("lower_bound", "minor"),
    ("lower_bound", "exact"), ("lower_bound", "point", "states"), ("lower_bound", "point", "parameters"),
    ("lower_bound", "point", "inputs"), ("upper_bound", "generators"), ("upper_bound", "kind"), ("format",),
])
VALUES = st.recursive(
    st.one_of(st.none(), st.booleans(), st.integers(-3, 5), st.sampled_from(
        ["0", "1", "-1", "1/2", "1/0", "x", "x1", "x2", "u", "p", "h", "y", "2*x1", "exp(x1)", "sqrt(x1)",
         "symmetries", "invariant span", "continuous", "discrete", "1e-30", "(log(6) - log(2) - log(3))"])),
    lambda inner: st.one_of(st.lists(inner, max_size=3), st.dictionaries(st.sampled_from(
        ["x1", "x2", "x", "u", "p", "h", "y", "name", "vector"]), inner, max_size=3)),
    max_leaves=6)


@given(kind=st.sampled_from(["polynomial", "exp-log", "parameter", "span", "discrete", "radicand", "branch"]),
       field=FIELDS,
       where=st.integers(0, 3), value=VALUES)
def test_no_edit_of_one_field_makes_the_checker_accept_a_false_claim(kind, field, where, value):
    """Whatever one field (or one entry of it) becomes, the checker tied to the
    model either refuses, or accepts the genuine claim (an edit that leaves a
    true proof, such as an unused input value, may be accepted): never another."""
    proof, model = (json.loads(text) for text in _written(kind))
    tampered = copy.deepcopy(proof)
    target = tampered
    for key in field[:-1]:
        target = target[key]
    old = target[field[-1]]
    if isinstance(old, dict) and old:
        old[sorted(old)[where % len(old)]] = value
    elif isinstance(old, list) and old:
        old[where % len(old)] = value
    else:
        target[field[-1]] = value
    accepted, lines = proofcheck._answer(json.dumps(tampered), model)
    assert lines[0].startswith("rejected: ") if not accepted else lines[0] == _genuine(kind)[0]


CLAIMS = st.sampled_from(["", "the generic rank of the observability matrix of {name} is {rank} of {n}",
                          "the generic rank of the observability matrix of {name} is {rank} of {n}" + REGION,
                          "the generic rank of the observability matrix of {name} is {rank} of {n} on a region",
                          "{claim}", "{claim} ", "{claim}\x1b[0m"])
WHERE = st.lists(st.sampled_from(["sqrt(1 - cos(x)**2)", "atan2(x2, x1)", "sqrt(x)", "log(b)", "", "x > 0"]),
                 max_size=2)


@given(kind=st.sampled_from(["branch", "atan2", "exp-log", "radicand", "polynomial"]), claim=CLAIMS, where=WHERE,
       qualified=st.sampled_from([True, False, None, 1]), drop=st.booleans())
def test_no_claim_or_region_but_the_derived_ones_is_accepted(kind, claim, where, qualified, drop):
    """Issue 61's last wrong answer: a file whose region was stripped and claim cut
    back to the whole domain was accepted. Any "claim" and "region" other than the
    genuine ones (written by hand in REGIONS) is refused, naming the field."""
    proof, model = (json.loads(text) for text in _written(kind))
    genuine = (proof["claim"], proof.get("region"))
    rank, n = CORPUS[kind][1], CORPUS[kind][0].n
    tampered = copy.deepcopy(proof)
    tampered["claim"] = claim.replace("({})", "({where})").format(
        name=model["name"], rank=rank, n=n, claim=proof["claim"], where=", ".join(where))
    tampered.pop("region", None)
    if not drop:
        tampered["region"] = {"qualified": qualified, "where": where}
    accepted, lines = proofcheck._answer(json.dumps(tampered), model)
    if (tampered["claim"], tampered.get("region")) == genuine:
        assert accepted, lines
    else:
        assert not accepted and lines[0].startswith(("rejected: the claim ", "rejected: the region ")), lines

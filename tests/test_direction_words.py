"""The words beside a direction say what its vector does (review 2).

References are hand derivations: each docstring gives the vector and what it
does to each state; an invariant is claimed only when its derivative along the
vector is zero by hand."""

import sympy

from observability import System, analyze
from observability.directions.naming import classify

x, y, z, b = sympy.symbols("x y z b")


def _static(names: str, outputs: dict, **kwargs) -> System:
    return System(names.split(), {n: "0" for n in names.split()}, outputs, **kwargs)


def test_equal_and_opposite_moves_are_not_called_together():
    """x' = v, b' = 0, z = x + b: the null field is (1, -1): x + s, b - s, which
    keeps x + b (d(x + b)(1, -1) = 1 - 1 = 0) -- the states move in opposite
    directions, not together (the old words)."""
    bias = System(["x", "b"], {"x": "v", "b": "0"}, {"z": "x + b"}, inputs=["v"])
    (direction,) = analyze(bias, seed=1).unobservable_directions
    assert {k: sympy.sympify(v) for k, v in direction.vector.items()} in ({"x": 1, "b": -1}, {"x": -1, "b": 1})
    assert direction.description == "moves x and b by equal and opposite amounts (b + x unchanged)"
    assert "together" not in direction.description


def test_unequal_moves_say_each_amount_and_the_kept_combination():
    """h = 2x - y: the field (1, 2) moves x by 1 and y by 2 per unit, keeping
    2x - y (2 * 1 - 1 * 2 = 0): not equally, so not "together"."""
    name, description = classify([sympy.Integer(1), sympy.Integer(2)], _static("x y", {"h": "2*x - y"}))
    assert name == "translation of x, y"
    assert description == "moves x by 1 and y by 2 per unit (2*x - y unchanged)"


def test_equal_moves_are_together_and_a_single_state_moves_alone():
    """(1, 1) moves x and y by the same amount (together, x - y kept); (0, 1)
    moves y only."""
    system = _static("x y", {"h": "x - y"})
    assert classify([sympy.Integer(1), sympy.Integer(1)], system)[1] == "moves these states together, by equal amounts"
    assert classify([sympy.Integer(0), sympy.Integer(1)], system)[1] == "moves y only"


def test_a_shifted_state_that_is_not_an_angle_is_not_said_to_turn():
    """Static x, y, z with h1 = z - atan2(y, x), h2 = x^2 + y^2: the field
    (y, -x, -1) rotates (x, y) about the origin (x' = y, y' = -x) and shifts z by
    -1 per unit (d atan2(y, x) along it is (x (-x) - y y) / (x^2 + y^2) = -1, as
    z's). z is neither a declared angle nor read through sin or cos, so it is
    shifted (a screw motion), not turned; declared an angle, or read as cos(z)
    by an extra output, it turns with the rotation (its shift is a turn)."""
    outputs = {"h1": "z - atan2(y, x)", "h2": "x**2 + y**2"}
    field = [y, -x, sympy.Integer(-1)]
    name, description = classify(field, _static("x y z", outputs))
    assert name == "rotation about (x, y) = (0, 0) with z shifted"
    assert description == "rotates the pairs (x, y) and shifts z with them (not an angle)"
    for system in (_static("x y z", outputs, angles=["z"]), _static("x y z", {**outputs, "h3": "cos(z)"})):
        name, description = classify(field, system)
        assert name == "rotation about (x, y) = (0, 0)"
        assert description == "rotates the pairs (x, y) and turns z with them"


def test_one_function_written_twice_is_listed_once():
    """h1 = x exp(2y) + y and h2 = x exp(y)^2 + y are one function (exp(y)^2 =
    exp(2y)): the observable functions list it once."""
    result = analyze(_static("x y", {"h1": "x*exp(2*y) + y", "h2": "x*exp(y)**2 + y"}), seed=1)
    assert result.rank == 1
    assert [sympy.sympify(f) for f in result.observable_functions] == [x * sympy.exp(2 * y) + y]


def test_a_field_with_a_constant_part_is_affine_not_linear():
    """h = x - y^2: the field (2y, 1) keeps it (2y - 2y = 0) and has the constant
    component 1: x' = A x + b with b = (0, 1) != 0, affine; (y, 0) (for h = y) is
    linear (b = 0). Neither a scaling nor a rotation."""
    affine = classify([2 * y, sympy.Integer(1)], _static("x y", {"h": "x - y**2"}))
    linear = classify([y, sympy.Integer(0)], _static("x y", {"h": "y"}))
    assert affine == ("unnamed direction", "an affine field that is neither a pure scaling nor a pure rotation")
    assert linear == ("unnamed direction", "a linear field that is neither a pure scaling nor a pure rotation")


def test_opposite_sign_scalings_are_a_squeeze_not_a_scaling():
    """Review 7, d6.toml: x+ = -y, y+ = x, h = x y. The exact null space of
    dh = (y, x) is spanned by (x, -y) (sympy below), which stretches x and
    shrinks y: d(x y)(x, -y) = y x - x y = 0, a hyperbolic squeeze with x y kept,
    not a scaling (no common factor). Equal-sign weights stay a scaling."""
    system = System(["x", "y"], {"x": "-y", "y": "x"}, {"h": "x*y"}, time="discrete")
    (null,) = sympy.Matrix([[y, x]]).nullspace()
    assert sympy.simplify(null[0] / null[1] + x / y) == 0  # proportional to (x, -y)
    (direction,) = analyze(system, seed=1).unobservable_directions
    assert direction.name == "squeeze"
    assert "x*y unchanged" in direction.description and "stretches x and shrinks y" in direction.description
    assert classify([3 * x, y / 2], _static("x y", {"h": "x**2*y**6"}))[0] == "scaling"


def test_a_squeeze_about_a_centre_names_the_kept_monomial():
    """(2 x, -2 (y - 1)) squeezes about y = 1: x (y - 1) is kept, since its
    derivative along the field is 2 x (y - 1) - 2 x (y - 1) = 0. Weights of
    both signs that do not sum to zero change volume (determinant e^(t (1 - 2)))
    and stay a scaling: slam1.5d's lengths up and inverse depth down."""
    name, description = classify([2 * x, -2 * y + 2], _static("x y", {"h": "x*(y - 1)"}))
    assert name == "squeeze about y = 1"
    assert "x*(y - 1) unchanged" in description
    assert classify([x, -2 * y], _static("x y", {"h": "x**2*y"}))[0] == "scaling"


def test_a_rotation_of_three_states_names_its_axis():
    """Review 7, m_tilted.toml: outputs x + y + z and x^2 + y^2 + z^2. The null
    space of their gradients (1, 1, 1) and 2 (x, y, z) is (y - z, z - x, x - y)
    = (1, 1, 1) x (x, y, z) (cross product by hand), a rotation about the fixed
    axis (1, 1, 1), which the field does not move (y - z, z - x, x - y all 0)."""
    system = _static("x y z", {"a": "x + y + z", "r": "x**2 + y**2 + z**2"})
    (null,) = sympy.Matrix([[1, 1, 1], [2 * x, 2 * y, 2 * z]]).nullspace()
    axis_cross = sympy.Matrix([1, 1, 1]).cross(sympy.Matrix([x, y, z]))
    assert sympy.simplify(null.cross(axis_cross)) == sympy.zeros(3, 1)
    (direction,) = analyze(system, seed=1).unobservable_directions
    assert direction.name == "rotation of (x, y, z) about the axis (1, 1, 1)"
    # (1, 2, 1) x (x, y, z) = (2 z - y, x - z, y - 2 x) by hand; its negative is classified
    name, _ = classify([y - 2 * z, z - x, 2 * x - y], system)
    assert name == "rotation of (x, y, z) about the axis (1, 2, 1)"

# The linear two-compartment model with an input into the first compartment, elimination from both and the
# first compartment measured, in SI.jl's notation (the biology tutorial, docs/tutorials/biology.md, and the
# experiment-design example of docs/guide/planning.md).
ode = @ODEmodel(
    x1'(t) = -(a01 + a21) * x1(t) + a12 * x2(t) + u(t),
    x2'(t) = a21 * x1(t) - (a02 + a12) * x2(t),
    y1(t) = x1(t)
)

#!/usr/bin/env python3
"""Writes andrews.yaml: Andrews' squeezing mechanism (seven bodies, planar) from the data of
the IVP test set (problem "andrews", Mazzia and Magherini, after Hairer and Wanner, Solving
ODEs II, section VII.7, and Schiehlen's benchmark). The node positions at t = 0 follow from
the test set's consistent initial angles; every body is a planar_rigid_body on two of its
joint points, with its mass, centre of mass and inertia. Run: python3 make_andrews.py
"""
from math import cos, sin, sqrt

# Test set parameters [kg, kg m^2, m, N m, N/m].
m1, m2, m3, m4, m5, m6, m7 = 0.04325, 0.00365, 0.02373, 0.00706, 0.07050, 0.00706, 0.05498
i1, i2, i3, i4, i5, i6, i7 = 2.194e-6, 4.410e-7, 5.255e-6, 5.667e-7, 1.169e-5, 5.667e-7, 1.912e-5
xa, ya, xb, yb, xc, yc = -0.06934, -0.00227, -0.03635, 0.03273, 0.014, 0.072
d, da, e, ea, rr, ra = 28e-3, 115e-4, 2e-2, 1421e-5, 7e-3, 92e-5
ss, sa, sb, sc, sd = 35e-3, 1874e-5, 1043e-5, 18e-3, 2e-2
ta, tb, u, ua, ub = 2308e-5, 916e-5, 4e-2, 1228e-5, 449e-5
zf, zt, fa, mom, c0, l0 = 2e-2, 4e-2, 1421e-5, 0.033, 4530.0, 0.07785
# Consistent initial angles (test set, y0) [rad]; the mechanism starts at rest.
be, th, ga, ph, de, om, ep = (-0.0617138900142764496358948458001, 0.0, 0.455279819163070380255912382449,
                              0.222668390165885884674473185609, 0.487364979543842550225598953530,
                              -0.222668390165885884674473185609, 1.23054744454982119249735015568)


def add(*v):
    return (sum(x[0] for x in v), sum(x[1] for x in v))


def mul(s, v):
    return (s * v[0], s * v[1])


def rot(v):  # +90 degrees
    return (-v[1], v[0])


O, A, B, C = (0.0, 0.0), (xa, ya), (xb, yb), (xc, yc)
eb, ebt = (cos(be), sin(be)), (cos(be + th), sin(be + th))
P = mul(rr, eb)                                     # crank tip (bodies 1-2)
E = add(P, mul(-d, ebt))                            # the joint of bodies 2, 3, 4, 6
Q = add(A, mul(zt, (cos(de), sin(de))))             # bodies 4-5
R = add(A, mul(u, (sin(ep), -cos(ep))))             # bodies 6-7
D = add(B, mul(sd, (cos(ga), sin(ga))), mul(sc, (sin(ga), -cos(ga))))  # spring on body 3
e3 = (sin(ga), -cos(ga))
e4 = (sin(ph + de), -cos(ph + de))
e5 = (cos(de), sin(de))
e6 = (cos(om + ep), sin(om + ep))
e7 = (sin(ep), -cos(ep))
# Centres of mass: where the test set's mass matrix puts them (distances from the pivots;
# for bodies pinned to the ground only the distance matters).
bodies = [
    ("crank", ["O", "P"], m1, i1, add(O, mul(ra, eb))),
    ("rod", ["P", "E"], m2, i2, add(P, mul(-da, ebt))),
    ("body3", ["B", "E", "D"], m3, i3, add(B, mul(sa, e3), mul(sb, rot(e3)))),
    ("body4", ["Q", "E"], m4, i4, add(Q, mul(e - ea, e4))),
    ("body5", ["A", "Q"], m5, i5, add(A, mul(ta, e5), mul(tb, rot(e5)))),
    ("body6", ["R", "E"], m6, i6, add(R, mul(zf - fa, e6))),
    ("body7", ["A", "R"], m7, i7, add(A, mul(ua, e7), mul(ub, rot(e7)))),
]


def f(x):
    return repr(float(x))


def pt(p):
    return "[" + f(p[0]) + ", " + f(p[1]) + "]"


lines = [
    "# Andrews' squeezing mechanism, planar: seven planar rigid bodies, a driving torque of",
    "# 0.033 N m on the crank, a spring of 4530 N/m and natural length 0.07785 m (IVP test set,",
    "# problem 'andrews'; Hairer and Wanner, Solving ODEs II, VII.7). No gravity. Written by",
    "# make_andrews.py. Run: flexsens run examples/andrews/andrews.yaml (t = 0 .. 0.03 s).",
    "# tests/test_andrews.cpp compares the node positions at t = 0.03 s with the test set's",
    "# reference angles.",
    "dimension: 2",
    "gravity: [0, 0]",
    "nodes:",
]
for n, p, g in [("O", O, True), ("A", A, True), ("B", B, True), ("C", C, True), ("P", P, False),
                ("E", E, False), ("Q", Q, False), ("R", R, False), ("D", D, False)]:
    lines.append("  - {name: %s, position: %s%s}" % (n, pt(p), ", ground: true" if g else ""))
lines.append("elements:")
for name, nodes, m, i, com in bodies:
    lines.append("  - {name: %s, type: planar_rigid_body, nodes: [%s], mass: %s, inertia: %s, center_of_mass: %s}"
                 % (name, ", ".join(nodes), f(m), f(i), pt(com)))
lines.append("  - {name: spring, type: spring_damper, nodes: [D, C], stiffness: %s, natural_length: %s}" % (f(c0), f(l0)))
lines.append("  - {name: drive, type: point_torque, nodes: [O, P], torque: %s}" % f(mom))
lines.append("integrator: {type: idas, t_end: 0.03, rtol: 1.0e-10, atol: 1.0e-12, frame_interval: 0.001}")
open("andrews.yaml", "w").write("\n".join(lines) + "\n")

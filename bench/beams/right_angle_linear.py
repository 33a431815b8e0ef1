#!/usr/bin/env python3
"""The right-angle cantilever (examples/frames/right_angle_cantilever.yaml) in its linear range
against an independent linear 3D frame model: Euler-Bernoulli elements with the textbook
consistent mass plus rotary (rho I) and polar (rho J) inertia, 10 per leg, clamped root, the
same triangular elbow force scaled by 1/1000, Newmark (average acceleration, dt 0.01 s).
Prints both models' lowest frequencies and the tip history (scaled back to the full load).
Usage: right_angle_linear.py FLEXSENS OUTDIR"""
import csv, os, shutil, subprocess, sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "..", "..", "examples", "frames", "right_angle_cantilever.yaml")
EA, GJ, EI, RHO_A, RHO_JP, RHO_I = 1e6, 1e3, 1e3, 1.0, 20.0, 10.0
SCALE = 1e-3


def element(L):
    """Local stiffness and mass, DOFs (u, v, w, tx, ty, tz) per end; x-z bending uses (w, -ty)."""
    K, M = np.zeros((12, 12)), np.zeros((12, 12))
    bar, cons = np.array([[1, -1], [-1, 1]]), np.array([[2, 1], [1, 2]])
    kb = EI / L**3 * np.array([[12, 6*L, -12, 6*L], [6*L, 4*L*L, -6*L, 2*L*L], [-12, -6*L, 12, -6*L], [6*L, 2*L*L, -6*L, 4*L*L]])
    mt = RHO_A * L / 420 * np.array([[156, 22*L, 54, -13*L], [22*L, 4*L*L, 13*L, -3*L*L], [54, 13*L, 156, -22*L],
                                     [-13*L, -3*L*L, -22*L, 4*L*L]])
    mr = RHO_I / (30 * L) * np.array([[36, 3*L, -36, 3*L], [3*L, 4*L*L, -3*L, -L*L], [-36, -3*L, 36, -3*L], [3*L, -L*L, -3*L, 4*L*L]])
    S = np.diag([1, -1, 1, -1])
    for idx, k, m in (([0, 6], EA / L * bar, RHO_A * L / 6 * cons), ([3, 9], GJ / L * bar, RHO_JP * L / 6 * cons),
                      ([1, 5, 7, 11], kb, mt + mr), ([2, 4, 8, 10], S @ kb @ S, S @ (mt + mr) @ S)):
        K[np.ix_(idx, idx)] += k
        M[np.ix_(idx, idx)] += m
    return K, M


def frame(per_leg=10):
    pts = [np.array([10.0 * i / per_leg, 10.0, 0.0]) for i in range(per_leg + 1)]
    pts += [np.array([10.0, 10.0 - 10.0 * i / per_leg, 0.0]) for i in range(1, per_leg + 1)]
    nd = 6 * len(pts)
    K, M = np.zeros((nd, nd)), np.zeros((nd, nd))
    for e in range(len(pts) - 1):
        d = pts[e + 1] - pts[e]
        L = np.linalg.norm(d)
        ex, ez = d / L, np.array([0.0, 0.0, 1.0])
        T = np.kron(np.eye(4), np.vstack([ex, np.cross(ez, ex), ez]))
        k, m = element(L)
        idx = np.arange(6 * e, 6 * e + 12)
        K[np.ix_(idx, idx)] += T.T @ k @ T
        M[np.ix_(idx, idx)] += T.T @ m @ T
    return K[6:, 6:], M[6:, 6:], 6 * per_leg + 2 - 6, 6 * (len(pts) - 1) + 2 - 6


def newmark(K, M, load_dof, dt=0.01, t_end=30.0):
    force = lambda t: SCALE * 50.0 * (t if t < 1 else (2 - t if t < 2 else 0.0))
    u, v = np.zeros(len(K)), np.zeros(len(K))
    a = np.zeros(len(K))
    solve = np.linalg.inv(K + 4 / dt**2 * M)
    hist = [(0.0, u.copy())]
    for n in range(1, int(round(t_end / dt)) + 1):
        f = np.zeros(len(K))
        f[load_dof] = force(n * dt)
        un = solve @ (f + M @ (4 / dt**2 * u + 4 / dt * v + a))
        an = 4 / dt**2 * (un - u) - 4 / dt * v - a
        v, u, a = v + dt / 2 * (a + an), un, an
        hist.append((n * dt, u.copy()))
    return hist


def main():
    flexsens, out = sys.argv[1], sys.argv[2]
    K, M, elbow, tip = frame()
    w = np.sqrt(np.sort(np.linalg.eigvals(np.linalg.solve(M, K)).real)[:6])
    print("frame model, lowest frequencies [rad/s]:", " ".join("%.5f" % x for x in w))
    os.makedirs(out, exist_ok=True)
    scene = os.path.join(out, "linear_range.yaml")  # beside a copy of its load table
    shutil.copy(os.path.join(os.path.dirname(SCENE), "impulse.csv"), out)
    with open(SCENE) as f:
        text = f.read().replace("force: [0, 0, 50]", "force: [0, 0, %g]" % (50 * SCALE))
    with open(scene, "w") as f:
        f.write(text)
    run = subprocess.run([flexsens, "run", scene, "--out", os.path.join(out, "run")], capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(run.stderr)
    with open(os.path.join(out, "run", "series.csv")) as f:
        rows = list(csv.reader(f))
    head = [h.strip() for h in rows[0]]
    data = np.array(rows[1:], float)
    t, z = data[:, head.index("t")], data[:, head.index("tip_z")]
    hist = newmark(K, M, elbow)
    tr = np.array([h[0] for h in hist])
    zr = np.array([h[1][tip] for h in hist])
    diff = np.max(np.abs(np.interp(tr, t, z) - zr)) / np.max(np.abs(zr))
    print("tip z at full-load scale, t: frame model / flexsens")
    for s in (1.0, 1.5, 2.0, 2.5, 3.0, 5.0, 8.0, 15.0, 25.0):
        i = int(round(s / 0.01))
        print("  %5.1f  %8.4f  %8.4f" % (s, zr[i] / SCALE, np.interp(s, t, z) / SCALE))
    print("largest |difference| over 30 s / largest |tip z|: %.2e" % diff)


if __name__ == "__main__":
    main()

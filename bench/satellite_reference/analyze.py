#!/usr/bin/env python3
"""Convergence of the massless satellite's IDAS runs (run.sh) and the fixed-step runs beside
them (fixed.sh): writes results.md and figure12.png in this folder.
   /usr/bin/python3 bench/satellite_reference/analyze.py [CASE ...]   (default SAT1 SAT2)
For each case: the IDAS runs at rtol = atol = 1e-6, 1e-8, 1e-10 (those that exist), how far
each got, and how x_B2 and dx_B2/dL_B1B2 differ between consecutive tolerances, relative to
the largest |value| of the tightest run over the common time; the agreement time is the last
frame up to which the 1e-8 and 1e-10 runs agree to 1e-4 of that scale at every frame. The runs
named *_staggered are the earlier ones with IDAS' staggered sensitivity corrector (kept as
history: they stopped); nominal_rRTOL are the motion alone, without sensitivities. The growth section measures how fast perturbations grow along the
motion: the spread of the four opening angles in the symmetric case (SAT1) and |dx_B2/dL|."""
import math
import csv, json, os, re, sys

here = os.path.dirname(os.path.abspath(__file__))
runs = os.path.join(here, 'runs')
OUT, SENS = 'xB2', 'dxB2/dL_B1B2'
RTOLS = ['1e-6', '1e-8', '1e-10']
# run.sh with SENS_ERROR_CONTROL=false: the sensitivities out of IDAS' error test
NOSERR = '1e-8_noserr'
# run.sh with SENS_TOLERANCE=state: IDAS' own sensitivity tolerances, estimated from the state's
# (before the scene asked for normwise ones); they stopped
STATE = ['1e-8_state', '1e-8_noserr_state']
# normwise with the norm taken apart over dq/dp and dv/dp (3fd5529, renamed runs/CASE_rRTOL_blocks)
STATE += ['1e-8_blocks']
# the earlier runs with the staggered sensitivity corrector (run.sh before the scene asked for
# the simultaneous one), renamed runs/CASE_rRTOL_staggered
STAGGERED = ['1e-6_staggered', '1e-8_staggered', '1e-10_staggered', '1e-8_noserr_staggered']
FIXED = [('bdf1_dt0.02', 'BDF-1, dt 0.02 s (the paper)'), ('trapezoidal_dt1e-3', 'trapezoidal, dt 1e-3 s'),
         ('trapezoidal_dt1e-4', 'trapezoidal, dt 1e-4 s'),
         ('ga0.8_dt1e-3', 'generalized-alpha rho_inf 0.8, dt 1e-3 s'),
         ('ga0.9_dt1e-3', 'generalized-alpha rho_inf 0.9, dt 1e-3 s'),
         ('ga0.95_dt1e-3', 'generalized-alpha rho_inf 0.95, dt 1e-3 s'),
         ('ga0.99_dt1e-3', 'generalized-alpha rho_inf 0.99, dt 1e-3 s'),
         ('ga0.99_dt1e-4', 'generalized-alpha rho_inf 0.99, dt 1e-4 s'),
         ('ga1_dt1e-3', 'generalized-alpha rho_inf 1, dt 1e-3 s'), ('ga1_dt1e-4', 'generalized-alpha rho_inf 1, dt 1e-4 s'),
         ('trapezoidal_proj_dt1e-3', 'trapezoidal with projections, dt 1e-3 s'),
         ('trapezoidal_proj_dt1e-4', 'trapezoidal with projections, dt 1e-4 s'),
         ('ga1_proj_dt1e-3', 'generalized-alpha rho_inf 1 with projections, dt 1e-3 s'),
         ('ga0.99_proj_dt1e-3', 'generalized-alpha rho_inf 0.99 with projections, dt 1e-3 s')]
# drawn in figure12.png beside IDAS (the others are in the tables)
PLOTTED = {'bdf1_dt0.02': 'tab:red', 'trapezoidal_dt1e-4': 'tab:blue', 'ga0.8_dt1e-3': 'tab:green',
           'ga0.99_dt1e-4': 'tab:purple', 'trapezoidal_proj_dt1e-4': 'tab:cyan'}


def note_of(line):
    """The first 400 characters of a run's failure or suspect line, and the growth of the
    accelerations when the failure names it (it comes later in the message)."""
    note = line[:400]
    m = re.search(r'the accelerations grew from [^:]*', line)
    if m and m.start() >= 400:
        note += ' ... ' + m.group(0)
    return note


def load(case, name):
    d = os.path.join(runs, f'{case}_{name}')
    series = os.path.join(d, case, 'series.csv')
    if not os.path.exists(series):
        return None
    rows = list(csv.DictReader(open(series)))
    summ = json.load(open(os.path.join(d, case, 'summary.json')))
    cpu = open(os.path.join(d, 'cpu.txt')).read().split('\n')[-2].split()  # its last line (/usr/bin/time may write 'Command exited ...' before)
    log = open(os.path.join(d, 'run.log')).read().replace('\r', '\n')
    fail = [l for l in log.splitlines() if 'numerical failure' in l or 'SUSPECT' in l]
    nums = [c for c in cpu if re.fullmatch(r'[0-9.]+', c)]
    return {'t': [float(r['t']) for r in rows], 'x': [float(r[OUT]) for r in rows],
            'spread': [max(float(r[f'open{k}']) for k in range(1, 5)) - min(float(r[f'open{k}']) for k in range(1, 5))
                       for r in rows],
            's': [float(r[SENS]) for r in rows], 'status': summ.get('status', '?'),
            'steps': summ.get('statistics', {}).get('steps'), 'cpu': float(nums[0]) + float(nums[1]) if len(nums) >= 2 else None,
            'note': note_of(fail[0]) if fail else '', 'health': summ.get('health', {}),
            'commit': open(os.path.join(d, 'commit.txt')).read().strip() if os.path.exists(os.path.join(d, 'commit.txt')) else '?'}


def load_nominal(rtol):
    """run.sh nominal RTOL: the motion alone (no parameters), written without a case folder."""
    d = os.path.join(runs, f'nominal_r{rtol}')
    if not os.path.exists(os.path.join(d, 'series.csv')):
        return None
    rows = list(csv.DictReader(open(os.path.join(d, 'series.csv'))))
    summ = json.load(open(os.path.join(d, 'summary.json')))
    nums = [c for c in open(os.path.join(d, 'cpu.txt')).read().strip().split('\n')[-1].split() if re.fullmatch(r'[0-9.]+', c)]
    return {'t': [float(r['t']) for r in rows], 'x': [float(r[OUT]) for r in rows],
            'spread': [max(float(r[f'open{k}']) for k in range(1, 5)) - min(float(r[f'open{k}']) for k in range(1, 5))
                       for r in rows],
            'status': summ.get('status', '?'), 'steps': summ.get('statistics', {}).get('steps'),
            'cpu': float(nums[0]) + float(nums[1]) if len(nums) >= 2 else None,
            'commit': open(os.path.join(d, 'commit.txt')).read().strip()}


def compare(a, b, key, tol=1e-4):
    """max |a - b| / max |b| over the common frames, and the last time up to which the difference
    at every frame stays within tol of the largest |b| reached so far, at least 1 (m for x_B2,
    m/m for dx_B2/dL): a running scale, since over 10 s the sensitivities grow to 1e21 and
    differences measured against that end value would call any two runs equal up to ~9 s."""
    n = min(len(a['t']), len(b['t']))
    scale = max(abs(v) for v in b[key][:n]) or 1.0
    worst, worst_run, running, agree = 0.0, 0.0, 0.0, None
    for i in range(n):
        running = max(running, abs(b[key][i]))
        e = abs(a[key][i] - b[key][i])
        worst = max(worst, e / scale)
        worst_run = max(worst_run, e / max(running, 1.0))
        if worst_run <= tol:
            agree = a['t'][i]
    return worst, agree, a['t'][n - 1]


def row(label, a, b):
    wx, ax, tc = compare(a, b, 'x')
    _, ax2, _ = compare(a, b, 'x', 1e-2)
    ws, as_, _ = compare(a, b, 's')
    _, as2, _ = compare(a, b, 's', 1e-2)
    return f'| {label} | {tc:.2f} | {wx:.2e} | {ax} / {ax2} | {ws:.2e} | {as_} / {as2} |'


def growth(d, t0, t1, key):
    """Least-squares slope of ln(running max |value|) over [t0, t1]: the rate [1/s] at which
    the quantity grows (a perturbation's exponential growth shows as a straight line)."""
    pts, top = [], 0.0
    for t, v in zip(d['t'], d[key]):
        top = max(top, abs(v))
        if t0 <= t <= t1 and top > 0:
            pts.append((t, math.log(top)))
    if len(pts) < 3:
        return None
    mt = sum(p[0] for p in pts) / len(pts)
    ml = sum(p[1] for p in pts) / len(pts)
    return sum((p[0] - mt) * (p[1] - ml) for p in pts) / sum((p[0] - mt) ** 2 for p in pts)


def label_of(r):
    return ('rtol ' + r.replace('_noserr', ', sensitivities out of the error test')
            .replace('_staggered', ', staggered corrector')
            .replace('_state', ", IDAS' sensitivity tolerances from the state's")
            .replace('_blocks', ', normwise with the norm apart over dq/dp and dv/dp'))


cases = sys.argv[1:] or ['SAT1', 'SAT2']
md = ['# The massless satellite over 10 s: IDAS reference and fixed-step schemes', '',
      '`bash bench/satellite_reference/run.sh CASE 1e-10 1e-8 1e-6`, `bash bench/satellite_reference/fixed.sh CASE`, '
      'then `/usr/bin/python3 bench/satellite_reference/analyze.py`. Scene `examples/satellite/satellite_massless.yaml` '
      '(springs `inertia: none`, IDAS with `sensitivity_corrector: simultaneous` and `sensitivity_tolerance: normwise`: '
      'each sensitivity held to rtol of its own size), frames every 0.1 s. "max rel. diff" is of the largest |value| '
      'of the tighter run over the common time; "within ... until" uses the largest |value| reached so far (at least '
      '1 m, or 1 for dx_B2/dL): the sensitivities grow to ~1e21 by 10 s, and a difference measured against that would '
      'call any two runs equal up to ~9 s. '
      'A run marked failed stopped at the time given (its frames up to there are kept); one marked suspect reached its end '
      'but flagged its result (here: the sensitivity blow-up check); pairs are compared over their common '
      'frames. "code" is the commit the run\'s binary was built from. The runs "staggered corrector" are the earlier ones '
      'with IDAS\' staggered sensitivity corrector, which stopped: before d1dc9c9 the multipliers and the massless '
      'velocities were in IDAS\' corrector convergence test, where every IDAS run of this model stopped (README, IDAS); '
      '"5471266-pre" is 5471266 without its split of a step that would overshoot a frame by little. '
      'The runs "IDAS\' sensitivity tolerances from the state\'s" are the earlier ones with IDAS\' estimated '
      'sensitivity tolerances (each sensitivity held to the state\'s absolute weights), which stopped once the '
      'sensitivities had grown to ~1e8 (README, IDAS); "normwise with the norm apart over dq/dp and dv/dp" is '
      '3fd5529\'s variant (kept closer to the reference early, stopped at 6.12 s; 702b8eb went back to one norm), '
      '"57adc73-pre" is 57adc73 before its option was renamed (the same tolerances as 702b8eb). '
      'Runs marked interrupted were stopped by hand (SIGINT) at the end of the session that ran them; their frames up to there are kept.', '']
plots = {}
summary = []
for case in cases:
    idas = {r: load(case, 'r' + r) for r in RTOLS + [NOSERR] + STATE + STAGGERED}
    md += [f'## {case}', '', '| run | code | status | reached t [s] | steps | CPU [s] | note |', '|---|---|---|---|---|---|---|']
    for r in RTOLS + [NOSERR] + STATE + STAGGERED:
        d = idas[r]
        if d:
            md.append(f"| IDAS {label_of(r)} | {d['commit']} | {d['status']} | {d['t'][-1]:.2f} | {d['steps']} | {d['cpu']:.0f} | {d['note']} |")
    fixed = {k: load(case, k) for k, _ in FIXED}
    for k, label in FIXED:
        d = fixed[k]
        if d:
            md.append(f"| {label} | {d['commit']} | {d['status']} | {d['t'][-1]:.2f} | {d['steps']} | {d['cpu']:.0f} | {d['note']} |")
    md += ['', '| pair | common time [s] | max rel. diff x_B2 | x_B2 within 1e-4 / 1e-2 until [s] | max rel. diff dx_B2/dL | dx_B2/dL within 1e-4 / 1e-2 until [s] |',
           '|---|---|---|---|---|---|']
    done = [r for r in RTOLS if idas[r]]
    for a, b in zip(done, done[1:]):
        md.append(row(f'rtol {a} vs {b}', idas[a], idas[b]))
    for r in [NOSERR] + STATE + STAGGERED:  # the other runs against the simultaneous ones (tightest first)
        if idas[r]:
            for b in done[::-1]:
                md.append(row(f'{label_of(r)} vs rtol {b} (the scene\'s settings)', idas[r], idas[b]))
                break
    # the fixed-step schemes against the tightest simultaneous IDAS run that reached the end
    # (else the farthest)
    full = [r for r in done if idas[r]['status'] in ('complete', 'suspect') and idas[r]['t'][-1] >= 10 - 1e-9]
    best = full[-1] if full else (max(done, key=lambda r: idas[r]['t'][-1]) if done else None)
    if best:
        for k, label in FIXED:
            if fixed[k]:
                md.append(row(f'{label} vs IDAS rtol {best}', fixed[k], idas[best]))
    md.append('')
    # the reference's reach: 1e-8 against 1e-10
    if idas['1e-8'] and idas['1e-10']:
        _, ax, tc = compare(idas['1e-8'], idas['1e-10'], 'x')
        _, as_, _ = compare(idas['1e-8'], idas['1e-10'], 's')
        summary.append(f'- {case}: rtol 1e-8 and 1e-10 agree to 1e-4 of the largest value on x_B2 up to t = {ax} s '
                       f'and on dx_B2/dL_B1B2 up to t = {as_} s (common time {tc:.1f} s).')
    # how fast perturbations grow: the rate of the envelope of |dx_B2/dL| and, in the symmetric
    # case, of the spread of the four panels' opening angles (round-off breaks the symmetry)
    ref = idas[best] if best else None
    if ref:
        t1 = ref['t'][-1]
        gs = growth(ref, 1.5, min(t1, 5.0), 's')
        gp = growth(ref, 1.5, min(t1, 5.0), 'spread')
        if gs:
            summary.append(f'- {case}, IDAS rtol {best}: |dx_B2/dL_B1B2| grows as exp({gs:.2f} t/s) over 1.5 .. '
                           f'{min(t1, 5.0):.1f} s (e-folding time {1 / gs:.2f} s); at t = {t1:.1f} s it is {ref["s"][-1]:.3g}.')
        if case == 'SAT1' and gp:
            summary.append(f'- SAT1 is symmetric (four equal panels); the spread of the four opening angles grows as '
                           f'exp({gp:.2f} t/s) over 1.5 .. {min(t1, 5.0):.1f} s, to {max(ref["spread"]):.2e} rad.')
    plots[case] = (idas, fixed, best)
# The motion alone: IDAS without sensitivities (run.sh nominal RTOL), against each other and
# against the runs with sensitivities (same motion, other step sequences).
nominal = {r: load_nominal(r) for r in RTOLS}
if any(nominal.values()):
    md += ['## The motion alone (no sensitivities)', '',
           'IDAS on the scene without its parameters and cases (`run.sh nominal RTOL`): the state alone, with the same '
           'tolerances. x_B2 relative to the largest |x_B2| of the second run of each pair.', '',
           '| run | code | status | reached t [s] | steps | CPU [s] |', '|---|---|---|---|---|---|']
    for r in RTOLS:
        d = nominal[r]
        if d:
            md.append(f"| IDAS rtol {r}, no sensitivities | {d['commit']} | {d['status']} | {d['t'][-1]:.2f} | "
                      f"{d['steps']} | {d['cpu']:.0f} |")
    md += ['', '| pair | common time [s] | max rel. diff x_B2 | x_B2 within 1e-4 / 1e-2 until [s] |', '|---|---|---|---|']
    nd = [r for r in RTOLS if nominal[r]]
    for a, b in zip(nd, nd[1:]):
        wx, ax, tc = compare(nominal[a], nominal[b], 'x')
        ax2 = compare(nominal[a], nominal[b], 'x', 1e-2)[1]
        md.append(f'| no sensitivities, rtol {a} vs {b} | {tc:.2f} | {wx:.2e} | {ax} / {ax2} |')
    for case in cases:
        for r in RTOLS:
            a = load(case, 'r' + r)
            if a and nominal.get(r):
                wx, ax, tc = compare(a, nominal[r], 'x')
                ax2 = compare(a, nominal[r], 'x', 1e-2)[1]
                md.append(f'| {case} rtol {r} (with sensitivities) vs no sensitivities rtol {r} | {tc:.2f} | {wx:.2e} | '
                          f'{ax} / {ax2} |')
    md.append('')
md += ['## Reach of the reference and growth of perturbations', ''] + summary + ['']

try:
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(3, len(plots), figsize=(6 * len(plots), 10), squeeze=False)
    for j, (case, (idas, fixed, best)) in enumerate(plots.items()):
        agree = None
        if idas['1e-8'] and idas['1e-10']:
            agree = compare(idas['1e-8'], idas['1e-10'], 's')[1]
        for r, style in zip(RTOLS, [':', '--', '-']):
            d = idas[r]
            if d:
                lab = 'IDAS rtol ' + r
                ax[0][j].plot(d['t'], d['x'], style, color='k', label=lab)
                ax[1][j].plot(d['t'], d['s'], style, color='k', label=lab)
                ax[2][j].semilogy(d['t'][1:], [abs(v) for v in d['s'][1:]], style, color='k', label=lab + ': |dx_B2/dL|')
                if case == 'SAT1':
                    ax[2][j].semilogy(d['t'][1:], [v for v in d['spread'][1:]], style, color='tab:orange',
                                      label=lab + ': spread of the 4 opening angles [rad]')
        for r, style in zip(RTOLS, [':', '--', '-']):
            if nominal.get(r):
                ax[0][j].plot(nominal[r]['t'], nominal[r]['x'], style, color='tab:gray', lw=1,
                              label=f'IDAS rtol {r}, no sensitivities')
        for k, label in FIXED:
            d, c = fixed[k], PLOTTED.get(k)
            if d and c:
                ax[0][j].plot(d['t'], d['x'], color=c, lw=1, label=label)
                ax[1][j].plot(d['t'], d['s'], color=c, lw=1, label=label)
        if agree is not None:
            for a in ax[:, j]:
                a.axvline(agree, color='grey', lw=0.8)
            ax[1][j].text(agree, 10.5, f' rtol 1e-8 = 1e-10 to 1e-4 up to {agree:.1f} s', fontsize=7, color='grey')
        ax[0][j].set_title(f'{case}: x_B2 [m]')
        ax[1][j].set_title(f'{case}: dx_B2/dL_B1B2 [-] (clipped to +-12)')
        ax[2][j].set_title(f'{case}: growth (log scale)')
        ax[2][j].set_xlabel('t [s]')
        ax[1][j].set_ylim(-12, 12)
        ax[0][j].legend(fontsize=7)
        ax[2][j].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(here, 'figure12.png'), dpi=110)
    md += ['![x_B2 and dx_B2/dL_B1B2 over 10 s](figure12.png)', '']
except ImportError:
    md += ['(matplotlib missing: no figure)', '']
open(os.path.join(here, 'results.md'), 'w').write('\n'.join(md) + '\n')
print('\n'.join(md))

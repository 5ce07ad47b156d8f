"""IDA against Newmark-β on the skew statistics of the baseline (a chaotic response).

Three studies, each a sub-command (run one heavy job at a time on a 2-core machine):

* ``impact`` — one pocket impact of an unloaded roller in the bearing at rest (deterministic,
  non-chaotic): restitution and peak penetration from IDA and Newmark-β (h ladder) against the
  1-DOF equation of the impact with the model's own pocket law (DOP853, rtol 1e-12), for
  several approach rates. A few seconds.
* ``run`` — one long run of the baseline with any integrator, from the standard initial state or
  from a state saved by an earlier run; records |skew| (all rollers, ``--per-rev`` samples per
  cage revolution) and the full state at every revolution boundary into an ``.npz``.
* ``analyse`` — per-revolution and per-3-revolution statistics of such runs (skew RMS, mean
  per-roller peak, 99th and 90th percentiles; the skew amplitude, mean over rollers of each
  roller's peak |skew|, over consecutive 3-revolution windows), means with batch-means
  standard errors.

Examples (the commands behind the comparison in docs/theory.md, "Newmark-β")::

    B="python benchmarks/run.py skew-statistics"
    $B impact
    $B run ida ida.npz --warm 1 --revs 10;     $B run ida ida2.npz --from ida.npz:-1 --revs 30
    $B run nm:2e-6 nm.npz --warm 1 --revs 10;  $B run nm:2e-6 nm2.npz --from nm.npz:-1 --revs 30
    $B run lsoda:1e-6 lsoda.npz --from ida.npz:1 --revs 20
    $B run ida z05.npz --from ida.npz:1 --revs 20 --set cage.damping_ratio=0.05
    $B run ida ens_1e-4.npz --warm 1 --revs 3 --eps=1e-4    # one member of an ensemble
    $B analyse IDA=ida.npz,ida2.npz NM=nm.npz,nm2.npz LSODA=lsoda.npz Z05=z05.npz

SPEC: ``ida[:rtol]`` (atol = rtol/100 when given), ``nm:h`` (Newmark-β, step h [s]),
``lsoda|radau|bdf[:rtol]`` (the scipy peers of solvers/scipy_peers.py).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from bearingdae import load_scene
from bearingdae.physics.cage import pocket_damping, pocket_force
from bearingdae.solvers import ida, newmark, scipy_peers
from bearingdae.solvers.algebraic import initial_state
from bearingdae.system.model import build_model
from bearingdae.system.residual import PARAM_NAMES

from run import fail, header, summary

CASE = "yang20_baseline"
PEERS = {"lsoda": "LSODA", "radau": "Radau", "bdf": "BDF"}


# ---------------------------------------------------------------------------------------------
# impact
# ---------------------------------------------------------------------------------------------
def impact_reference(P, th0, rate, t_out, zeta=None):
    """θ, θ' of I_t θ'' = (L/2)(F_b - F_a), the pocket law at both ends (DOP853)."""
    from scipy.integrate import solve_ivp

    L, It = P["L"], P["It"]
    c = P["cdamp"] if zeta is None else pocket_damping(P["Kp"], P["mass"], zeta)
    law = (P["cp"], P["Kp"], c, P["eps_p"], P["f_p"])

    def rhs(t, z):
        f_a = pocket_force(-0.5 * L * z[0], -0.5 * L * z[1], *law)[0]
        f_b = pocket_force(0.5 * L * z[0], 0.5 * L * z[1], *law)[0]
        return [z[1], 0.5 * L * (f_b - f_a) / It]

    return solve_ivp(rhs, (0.0, t_out[-1]), [th0, rate], method="DOP853", rtol=1e-12,
                     atol=1e-15, t_eval=t_out, max_step=1e-7).y


def impact(args):
    m = build_model(load_scene(CASE, {"operating.speed_rpm": 0.0, "operating.moment_Nm": 0.0}))
    P = dict(zip(PARAM_NAMES, m.data[0]))
    lay, j, gap = m.layout, 10, 2e-4  # roller at azimuth π: no race load
    i_sk, i_sr = lay.index("skew_angle", j), lay.index("skew_rate", j)
    th0 = P["cp"] / P["L"] - gap
    steps = [float(h) for h in args.steps.split(",")]
    print(f"symmetric skew impact of roller {j} (bearing at rest), start {gap * 1e3:g} mrad "
          f"short of both bars; restitution e = -rebound rate / approach rate; errors relative "
          "to the 1-DOF reference (DOP853 rtol 1e-12); Newmark's are positive = too elastic")
    for rate in (float(r) for r in args.rates.split(",")):
        t_out = 4e-6 * np.arange(int(round((2 * gap / rate + 2e-4) / 4e-6)) + 1)
        y0, yp0 = initial_state(m)
        y0 = y0.copy()
        y0[i_sk], y0[i_sr] = th0 / m.scale[i_sk], rate / m.scale[i_sr]

        def measures(th, w):
            return -w[-1] / rate, (0.5 * P["L"] * np.abs(th) - 0.5 * P["cp"]).max()

        e_ref, pen_ref = measures(*impact_reference(P, th0, rate, t_out))
        row = [f"rate {rate:g} rad/s: reference e {e_ref:.4f}, penetration {pen_ref * 1e9:.1f} nm"
               f" (ζ = 0.095: e {measures(*impact_reference(P, th0, rate, t_out, 0.095))[0]:.4f})"]
        runs = [("IDA 1e-6", lambda: ida.integrate(m, y0, yp0, t_out))]
        runs += [(f"NM {h * 1e6:g} µs", lambda h=h: newmark.Newmark(
            newmark.NewmarkOptions(step_s=h)).integrate(m, y0, yp0, t_out)) for h in steps]
        for name, fn in runs:
            r = fn()
            e, pen = measures(r.y[:, i_sk] * m.scale[i_sk], r.y[:, i_sr] * m.scale[i_sr])
            row.append(f"{name}: e {e / e_ref - 1:+.1e}, pen {pen / pen_ref - 1:+.1e}")
        print("\n   ".join(row))


# ---------------------------------------------------------------------------------------------
# run
# ---------------------------------------------------------------------------------------------
def _value(text):
    return int(text) if text.lstrip("-").isdigit() else float(text)


def run(args):
    parts = args.spec.split(":")
    kind = parts[0]
    over = {k: _value(v) for k, v in (s.split("=", 1) for s in args.set)}
    over.setdefault("numerics.max_steps", 10**8)  # Newmark refuses runs over max_steps
    if kind in ("ida", *PEERS) and len(parts) > 1:
        over["numerics.rtol"] = float(parts[1])
        over["numerics.atol"] = float(parts[1]) / 100
    m = build_model(load_scene(CASE, over))
    lay = m.layout
    if args.src:
        path, _, k = args.src.partition(":")
        y0 = np.load(path)["states"][int(k or -1)].copy()
        yp0 = np.zeros_like(y0)  # y' of the differential rows from the equations of motion
        diff = m.mass > 0
        yp0[diff] = -m.residual(0.0, y0, np.zeros_like(y0))[diff] / m.mass[diff]
    else:
        y0, yp0 = initial_state(m)
    if args.eps:
        i = lay.index("spin_speed", 5)
        y0 = y0.copy()
        y0[i] *= 1 + args.eps
    period = 2 * np.pi / m.final_cage_speed()
    n_out = int(round((args.warm + args.revs) * args.per_rev))
    t_out = np.arange(n_out + 1) * period / args.per_rev
    t0 = time.perf_counter()
    if kind == "ida":
        r = ida.integrate(m, y0, yp0, t_out)
    elif kind == "nm":
        options = newmark.NewmarkOptions(step_s=float(parts[1]))
        r = newmark.Newmark(options).integrate(m, y0, yp0, t_out)
    elif kind in PEERS:
        r = scipy_peers.ScipyPeer(PEERS[kind]).integrate(m, y0, yp0, t_out)
    else:
        fail(f"unknown solver spec {args.spec[:100]!r}: allowed are ida[:rtol], nm:h, "
             "lsoda|radau|bdf[:rtol]")
    wall = time.perf_counter() - t0
    ik = [lay.index("skew_angle", j) for j in range(lay.rollers)]
    ic = lay.index("cage_speed")
    np.savez_compressed(args.out, t=r.t, skew=r.y[:, ik] * m.scale[ik],
                        cage=r.y[:, ic] * m.scale[ic], states=r.y[::args.per_rev],
                        period=period, warm=args.warm, per_rev=args.per_rev, wall=wall,
                        ok=r.success, spec=args.spec)
    print(f"{args.spec} from {args.src or 'initial state'} eps {args.eps:g}: {r.message}, "
          f"wall {wall:.3g} s -> {args.out}", flush=True)


# ---------------------------------------------------------------------------------------------
# analyse
# ---------------------------------------------------------------------------------------------
STATS = ("rms", "peak", "p99", "p90")


def revolution_blocks(path, sub):
    """Per recorded cage revolution: skew RMS over time and rollers, mean over rollers of each
    roller's peak, 99th and 90th percentile of |skew| [mrad], at per_rev / sub samples/rev."""
    d = np.load(path, allow_pickle=True)
    per = int(d["per_rev"])
    i0 = int(round(float(d["warm"]) * per))
    sk = np.abs(d["skew"][i0:]) * 1e3
    out = []
    for b in range((sk.shape[0] - 1) // per):
        s = sk[b * per:(b + 1) * per:sub]
        out.append((np.sqrt((s ** 2).mean()), s.max(0).mean(), np.percentile(s, 99),
                    np.percentile(s, 90)))
    return np.array(out)


def window_amplitudes(path, revs=3, sub=5):
    """The skew amplitude (mean over rollers of max |skew| over ``revs`` revolutions,
    every ``sub``-th sample) over consecutive windows [mrad]."""
    d = np.load(path, allow_pickle=True)
    per = int(d["per_rev"])
    sk = np.abs(d["skew"][int(round(float(d["warm"]) * per)):]) * 1e3
    n = revs * per
    return np.array([sk[w * n:(w + 1) * n + 1:sub].max(0).mean()
                     for w in range((sk.shape[0] - 1) // n)])


def mean_se(x):
    """Mean and batch-means standard error, widened for a positive lag-1 correlation ρ by
    sqrt((1 + ρ)/(1 - ρ))."""
    x = np.asarray(x, float)
    rho = np.corrcoef(x[:-1], x[1:])[0, 1] if x.size > 3 else 0.0
    widen = np.sqrt((1 + max(rho, 0.0)) / (1 - min(max(rho, 0.0), 0.9)))
    return x.mean(), x.std(ddof=1) / np.sqrt(x.size) * widen


def analyse(args):
    for arg in args.runs:
        label, files = arg.split("=", 1)
        files = files.split(",")
        for sub in (args.per_rev_sub, 1):
            B = np.concatenate([revolution_blocks(f, sub) for f in files])
            cells = [f"{s} {mean_se(B[:, k])[0]:.4f} ± {mean_se(B[:, k])[1]:.4f}"
                     for k, s in enumerate(STATS)]
            print(f"{label:10s} per revolution ({len(B)}), every {sub}. sample: "
                  + ", ".join(cells))
        A = np.concatenate([window_amplitudes(f, sub=args.per_rev_sub) for f in files])
        mu, se = mean_se(A)
        print(f"{label:10s} 3-revolution skew amplitude ({A.size} windows): mean {mu:.3f} ± "
              f"{se:.3f}, sd {A.std(ddof=1):.3f} ({A.std(ddof=1) / mu * 100:.1f} %), "
              f"range {A.min():.3f}-{A.max():.3f}")


def main(argv=None, name="skew-statistics"):
    ap = argparse.ArgumentParser(prog=f"run.py {name}", description=summary(__doc__))
    sub = ap.add_subparsers(dest="cmd", required=True)
    p = sub.add_parser("impact")
    p.add_argument("--rates", default="1,2,4,8")
    p.add_argument("--steps", default="4e-6,2e-6,1e-6,5e-7")
    p.set_defaults(fn=impact)
    p = sub.add_parser("run")
    p.add_argument("spec")
    p.add_argument("out")
    p.add_argument("--from", dest="src")
    p.add_argument("--warm", type=float, default=0.0)
    p.add_argument("--revs", type=float, default=3.0)
    p.add_argument("--per-rev", type=int, default=1000)
    p.add_argument("--eps", type=float, default=0.0,
                   help="relative perturbation of roller 5's initial spin (use --eps=-1e-4)")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    p.set_defaults(fn=run)
    p = sub.add_parser("analyse")
    p.add_argument("runs", nargs="+", metavar="LABEL=FILE[,FILE...]")
    p.add_argument("--per-rev-sub", type=int, default=5,
                   help="use every n-th sample (5: the 200/rev of the scene default)")
    p.set_defaults(fn=analyse)
    a = ap.parse_args(argv)
    header(f"{name} {a.cmd}")
    a.fn(a)


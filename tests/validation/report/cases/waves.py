"""The wave flume (issue 45): a solitary wave from Goring's piston, its run-up on a plane beach
against Synolakis (1987), and regular waves from a piston and a flap.

- Solitary wave (cases/wave_solitary.json: d = 0.4 m, H/d = 0.2): the crest's height at 5, 7.5
  and 10 depths from the paddle above the still level, and the crest's celerity fitted over the
  three gauges (the result's `solitary`, PROTOCOL.md section 1.8). Bounds (the issue's): the
  height ten depths down the flume within 5% of H, the celerity within 2% of sqrt(g (d + H)), at
  the finest dx run.
- Run-up (cases/wave_runup.json: the same flume and piston, a 1:2.75 beach from 10 depths on):
  the largest reading of the run-up gauge over the beach above the still level, R/d, against
  Synolakis' law for non-breaking waves R/d = 2.831 sqrt(cot beta) (H/d)^(5/4) at H/d = 0.05
  and 0.1 (his breaking limit on this slope: H/d = 0.818 (cot beta)^(-10/9) = 0.27); within 10%
  at the finest dx, at the nominal H (the law's offshore height; at the incident crest the
  gauge 5 depths before the toe measures: noted). H/d = 0.2, three quarters of the breaking
  limit, is run and noted beside them. Each run lasts until 2.5 s after the theory's crest
  reaches the toe (a lower wave is longer and slower: its crest trails its front by 3.8 /
  kappa, 7.9 m at H/d = 0.05).
- Regular waves (cases/wave_flume.json: d = 0.4 m, H = 0.05 m, T = 1.27 s, kd = 1.20): the
  zero-up-crossing height one, two and three wavelengths from the paddle and the period, piston
  and flap. Bound (the issue's): the height two wavelengths from the paddle within 5% of H, the
  period within 1%.

- Irregular sea (cases/wave_irregular.json: a JONSWAP sea, Hs = 0.04 m, Tp = 1.27 s, gamma 3.3,
  118 components from seed 7, a piston): each gauge's surface over its window against linear
  theory's superposition of the same components, eta = sum a_i cos(omega_i t + phi_i - k_i x),
  the components computed here independently of sphd (the spectrum, its scaling to Hs, the
  frequencies i / duration, the phases from splitmix64 of the seed). Bounds (ours: the issue
  asks for irregular waves, not a figure): at one wavelength from the paddle the correlation of
  the two series at least 0.9 and Hm0 within 10% of the prediction's over the same window (the
  regular waves lose 3-4% a wavelength at dx 0.02, the short components more). The nominal Hs
  is noted beside: a window of 15-20 s holds 12-16 waves, whose Hm0 varies by itself.

- 3D (cases/wave_flume3d.json: a piston spanning a flume 0.4 m wide, dx = 0.04 m, to t = 10 s):
  the height one wavelength from the paddle against the 2D flume's at the same dx, tank and
  length (wave_flume.json with FLUME2D's sets). Bound (the issue's): within 5%.

The ci level runs the solitary wave and the run-up at H/d = 0.1 at dx = 0.02 m, and the
irregular sea at the case's dx = 0.02 m to t = 12 s (at 0.04 m, one particle over Hs, Hm0
came out -13.5% of linear theory's at one wavelength, the correlation 0.964).
"""
import math
import os

TITLE = "wave flume: solitary wave, run-up on a beach, piston and flap"
G, D = 9.81, 0.4
COT = 2.75                      # the beach's 1:2.75 slope
SOLITARY_H = 0.08
HEIGHT_BOUND, CELERITY_BOUND = 0.05, 0.02
RUNUP_BOUND = 0.10
REGULAR_H, REGULAR_T = 0.05, 1.27
REGULAR_BOUND, PERIOD_BOUND = 0.05, 0.01
TOE, PADDLE = 4.2, 0.2           # the beach's toe and the paddle's face [m]
# TODO(issue 45): the run-up at H/d = 0.05 at dx = 0.005 (+20.6% at 0.01: five particles of
# run-up; about 70,000 particles), and regular waves at kd 0.6 and 2.5 beside 1.2, piston and
# flap, at a dx where the height two wavelengths out converges (the piston at kd 1.2: -7.5% at
# dx 0.02, -5.1% at 0.01); a lent GPU runs these in minutes once the paddle is checked there.
# run-up: (H/d, dx, checked)
RUNS = {"full": {"solitary": [0.02, 0.01],
                 "runup": [(0.05, 0.01, True), (0.1, 0.02, False), (0.1, 0.01, True),
                           (0.2, 0.02, False), (0.2, 0.01, False)],
                 "regular": [("piston", 0.02), ("flap", 0.02)], "3d": True,
                 "irregular": (0.02, 25.0)},
        "ci": {"solitary": [0.02], "runup": [(0.1, 0.02, True)], "regular": [], "3d": False,
               "irregular": (0.02, 12.0)}}
IRREGULAR_CORR, IRREGULAR_HM0 = 0.9, 0.10
# cases/wave_flume.json as the 3D flume's 2D twin: its dx, tank, length and damping zone
FLUME2D = ["dx=0.04", "time.end=10", "output.every=100", "boundary.tank.max.1=0.6",
           "absorption.from=4.9", "absorption.to=7.0", "fluid.0.box.max.0=7.0",
           "boundary.tank.max.0=7.0", "domain.max.0=7.0"]
THREE_D_BOUND = 0.05
RESOLUTION = {"full": "dx = 0.02 and 0.01 m (20 and 40 particles over the depth)",
              "ci": "dx = 0.02 m"}


def synolakis(h):
    """Synolakis' run-up law R/d at H/d = h on the case's slope."""
    return 2.831 * math.sqrt(COT) * h ** 1.25


def kd_of(y):
    """kd from omega^2 d / g = kd tanh(kd), Newton from Eckart's start."""
    x = y / math.sqrt(math.tanh(y))
    for _ in range(60):
        t = math.tanh(x)
        x -= (x * t - y) / (t + x * (1 - t * t))
    return x


def sea_components(w):
    """The irregular sea's components (frequency [Hz], amplitude [m], phase [rad]) as
    PROTOCOL.md section 1.8 defines them, computed here without sphd."""
    hs, tp, dur = w["hs"], w["tp"], w["duration"]
    gamma, state = w.get("gamma", 3.3), w.get("seed", 1)
    fp, df, mask = 1.0 / tp, 1.0 / dur, (1 << 64) - 1
    lo, hi = max(1, math.ceil(0.5 * fp * dur - 1e-9)), math.floor(3 * fp * dur + 1e-9)
    freqs = [i / dur for i in range(lo, hi + 1)]
    shape = [f ** -5 * math.exp(-1.25 * (fp / f) ** 4)
             * gamma ** math.exp(-0.5 * ((f - fp) / ((0.07 if f <= fp else 0.09) * fp)) ** 2)
             for f in freqs]
    scale = hs * hs / 16 / (sum(shape) * df)
    out = []
    for f, s in zip(freqs, shape):
        state = (state + 0x9e3779b97f4a7c15) & mask  # splitmix64
        z = ((state ^ (state >> 30)) * 0xbf58476d1ce4e5b9) & mask
        z = ((z ^ (z >> 27)) * 0x94d049bb133111eb) & mask
        z ^= z >> 31
        out.append((f, math.sqrt(2 * scale * s * df), 2 * math.pi * (z >> 11) * 2.0 ** -53))
    return out


def result(d):
    import json
    import os
    with open(os.path.join(d, "result.json")) as f:
        return json.load(f)


def run(ctx):
    runs = RUNS[ctx.level]
    ctx.note("Resolution: %s; h = 2 dx, 4 layers of walls and paddle, Fourtakas' delta-SPH, "
             "water's viscosity (the flume's numerics, docs/validation.md)." % RESOLUTION[ctx.level])
    # the solitary wave
    sol = runs["solitary"]
    for dx in sol:
        _, d = ctx.sphd_run("cases/wave_solitary.json", ["dx=%g" % dx, "output.every=100"])
        r = result(d)
        s = r["solitary"]
        g = s["gauges"]
        hs = ", ".join("%s %+.1f%%" % (k, 100 * (v["height"] / SOLITARY_H - 1))
                       for k, v in g.items())
        how = ("crests above the still level: %s; %d steps, %.0f s, %d lost; %.0f particles over "
               "H" % (hs, r["steps"], r["wall_time"], r["particles"]["lost"], SOLITARY_H / dx))
        h10 = g["g10d"]["height"] / SOLITARY_H - 1
        cel = s["celerity"] / s["theory"] - 1
        if dx == min(sol):
            ctx.check("solitary, dx = %g m: the crest ten depths down the flume against H, "
                      "relative" % dx, round(h10, 4), HEIGHT_BOUND, abs(h10) <= HEIGHT_BOUND, how)
            ctx.check("solitary, dx = %g m: the crest's celerity (5 to 10 depths) against "
                      "sqrt(g (d + H)) = %.4f m/s, relative" % (dx, s["theory"]), round(cel, 4),
                      CELERITY_BOUND, abs(cel) <= CELERITY_BOUND, how)
        else:
            ctx.note("Solitary wave at dx = %g m: ten depths %+.1f%%, celerity %+.2f%% (%s)."
                     % (dx, 100 * h10, 100 * cel, how))
    # the run-up
    for h, dx, checked in runs["runup"]:
        kappa, c = math.sqrt(0.75 * h) / D, math.sqrt(G * D * (1 + h))
        end = (TOE - PADDLE + 3.8 / kappa) / c + 2.5
        _, d = ctx.sphd_run("cases/wave_runup.json", ["dx=%g" % dx, "output.every=100",
                                                      "time.end=%.2f" % end,
                                                      "wavemaker.waves.height=%g" % (h * D)])
        r = result(d)
        g = r["solitary"]["gauges"]
        R = g["beach"]["height"] / D
        hinc = g["g5d"]["height"] / D
        law, law_inc = synolakis(h), synolakis(hinc)
        rel, rel_inc = R / law - 1, R / law_inc - 1
        how = ("largest reading %.4f m above the still level at t = %.2f s; the incident crest "
               "5 depths before the toe %.4f m (H/d %.4f: the law %.4f, %+.1f%%); %d steps, "
               "%.0f s, %d lost" % (R * D, g["beach"]["time"], hinc * D, hinc, law_inc,
                                    100 * rel_inc, r["steps"], r["wall_time"],
                                    r["particles"]["lost"]))
        label = "run-up, H/d = %g, dx = %g m" % (h, dx)
        if checked:
            ctx.check("%s: R/d = %.4f against Synolakis' %.4f, relative" % (label, R, law),
                      round(rel, 4), RUNUP_BOUND, abs(rel) <= RUNUP_BOUND, how)
        else:
            ctx.note("%s: R/d = %.4f against %.4f (%+.1f%%); %s." % (label, R, law, 100 * rel,
                                                                     how))
    # regular waves
    for paddle, dx in runs["regular"]:
        _, d = ctx.sphd_run("cases/wave_flume.json", ["dx=%g" % dx, "output.every=100",
                                                      "time.end=14",
                                                      "wavemaker.type=%s" % paddle])
        r = result(d)
        w = r["waves"]
        hs = ", ".join("%s %+.1f%% (%d waves)" % (k, 100 * (v["height"] / REGULAR_H - 1),
                                                   v["count"])
                       for k, v in w.items() if v["height"] is not None)
        how = "heights: %s; %d steps, %.0f s; %.1f particles over H" % (
            hs, r["steps"], r["wall_time"], REGULAR_H / dx)
        e2 = w["g2L"]["height"] / REGULAR_H - 1
        ep = w["g1L"]["period"] / REGULAR_T - 1
        ctx.check("regular, %s, dx = %g m: the height two wavelengths from the paddle against "
                  "H, relative" % (paddle, dx), round(e2, 4), REGULAR_BOUND,
                  abs(e2) <= REGULAR_BOUND, how)
        ctx.check("regular, %s, dx = %g m: the period one wavelength from the paddle against "
                  "T, relative" % (paddle, dx), round(ep, 4), PERIOD_BOUND,
                  abs(ep) <= PERIOD_BOUND, how)
    # an irregular sea against linear theory's superposition of its components
    if runs.get("irregular"):
        import h5py
        import json
        import numpy as np
        dx, end = runs["irregular"]
        _, d = ctx.sphd_run("cases/wave_irregular.json", ["dx=%g" % dx, "time.end=%g" % end,
                                                          "output.every=100"])
        r = result(d)
        with open(os.path.join(ctx.src, "cases", "wave_irregular.json")) as f:
            case = json.load(f)
        w, x0 = case["wavemaker"]["waves"], case["wavemaker"]["x"]
        comps = sea_components(w)
        with h5py.File(os.path.join(d, "diag.h5"), "r") as h:
            t = h["t"][:]
            series = {g["name"]: (g["x"], h[g["name"]][:]) for g in case["diagnostics"]["gauges"]}
        fig = ctx.figure("irregular_sea", figsize=(7.5, 5.5))
        for n, (name, (x, eta)) in enumerate(sorted(series.items())):
            t0 = r["waves"][name]["from"]
            m = t >= t0
            pred = np.zeros(m.sum())
            for f, a, ph in comps:
                om = 2 * math.pi * f
                k = kd_of(om * om * D / G) / D
                pred += a * np.cos(om * t[m] + ph - k * (x - x0))
            e = eta[m] - eta[m].mean()
            corr = float(np.corrcoef(e, pred)[0, 1])
            hm0, hm0p = 4 * e.std(), 4 * pred.std()
            rel = hm0 / hm0p - 1
            how = ("over [%.1f, %.1f] s (%d waves): Hm0 %.4f m against the prediction's %.4f m "
                   "(the nominal Hs %.3f m); H1/3 %.4f m; %d steps, %.0f s" % (
                       t0, t[-1], r["waves"][name]["count"], hm0, hm0p, w["hs"],
                       r["waves"][name]["h13"], r["steps"], r["wall_time"]))
            if name == "g1L":
                ctx.check("irregular, dx = %g m, one wavelength from the paddle: the surface's "
                          "correlation with linear theory's" % dx, round(corr, 3),
                          IRREGULAR_CORR, corr >= IRREGULAR_CORR, how)
                ctx.check("irregular, dx = %g m, one wavelength from the paddle: Hm0 against "
                          "linear theory's over the window, relative" % dx, round(rel, 4),
                          IRREGULAR_HM0, abs(rel) <= IRREGULAR_HM0, how)
            else:
                ctx.note("Irregular sea at %s (dx = %g m): correlation %.3f, Hm0 %+.1f%% of "
                         "linear theory's; %s." % (name, dx, corr, 100 * rel, how))
            ax = fig.add_subplot(len(series), 1, n + 1)
            ax.plot(t[m], 1000 * e, lw=0.9, label="sphd")
            ax.plot(t[m], 1000 * pred, lw=0.9, ls="--", label="linear theory")
            ax.set_ylabel("%s: eta [mm]" % name)
            if n == 0:
                ax.set_title("JONSWAP sea, Hs %.2f m, Tp %.2f s, dx = %g m" % (w["hs"], w["tp"], dx))
                ax.legend(fontsize=8)
        ax.set_xlabel("t [s]")
    # 3D against 2D
    if runs["3d"]:
        _, d2 = ctx.sphd_run("cases/wave_flume.json", FLUME2D)
        _, d3 = ctx.sphd_run("cases/wave_flume3d.json", ["output.every=100"])
        r2, r3 = result(d2), result(d3)
        h2, h3 = r2["waves"]["g1L"]["height"], r3["waves"]["g1L"]["height"]
        e = h3 / h2 - 1
        how = ("one wavelength from the paddle: 3D %.4f m (%d waves), 2D %.4f m (%d waves), H = "
               "0.05 m; two wavelengths: 3D %s, 2D %s; 3D %.0f s, 2D %.0f s" % (
                   h3, r3["waves"]["g1L"]["count"], h2, r2["waves"]["g1L"]["count"],
                   r3["waves"]["g2L"]["height"], r2["waves"]["g2L"]["height"],
                   r3["wall_time"], r2["wall_time"]))
        ctx.check("3D flume, dx = 0.04 m: the height one wavelength from the paddle against the "
                  "2D flume's, relative", round(e, 4), THREE_D_BOUND, abs(e) <= THREE_D_BOUND, how)

"""Viscous standing wave (Macia et al., paper 001, section IV; cases/standing_wave.json): one
wavelength in a tank 1 m long, water 0.5 m deep, eps = 2A/H = 0.1, Re = H sqrt(gH)/nu = 500,
free-slip ghost walls, Monaghan's viscous term as a physical viscosity, dx/h = 0.5. The period
and the decay rate of the kinetic-energy envelope, fitted by sphd over the first 8 periods (its
`result.wave`), against 2 pi/omega and Lighthill's 4 nu k^2 (eq. 8); E_kin(t)/E_kin(0) against
eq. (8), Wendland C2 and the renormalised Gaussian.
"""
import math

import numpy as np

TITLE = "standing wave (paper 001): period and kinetic-energy decay against Lighthill"
# H/dx = 50 at the ci level, 100 in full (200 takes hours on one core: tests/CMakeLists.txt's
# validate target runs it through tests/validation/standing_wave.sh)
SETS = {"full": ["dx=0.005", "time.end=6.7"], "ci": ["time.end=6.7"]}
RESOLUTION = {"full": "H/dx = 100 (20,000 particles), 8.4 periods",
              "ci": "H/dx = 50 (5,000 particles), 8.4 periods"}
PERIOD_BOUND = 0.02                       # |T - T_theory| / T_theory, the issue's
RATE_BOUND = {"full": 0.15, "ci": 0.20}   # |beta - 4 nu k^2| / 4 nu k^2: the 15% at
                                          # H/dx = 100; a loose 20% at 50
KERNELS = ("wendland_c2", "renormalized_gaussian")


def run(ctx):
    fig = ctx.figure("ekin", figsize=(6, 4))
    ax = fig.add_subplot(111)
    for kernel in KERNELS:
        events, _ = ctx.sphd_run("cases/standing_wave.json",
                                 SETS[ctx.level] + ["kernel.type=" + kernel],
                                 job="standing_wave_" + kernel)
        assert events[-1].get("state") == "done", events[-1]
        res = [e for e in events if e["type"] == "result"][-1]
        w = res["wave"]
        perr = (w["period"] - w["period_theory"]) / w["period_theory"]
        rerr = (w["decay_rate"] - w["decay_rate_theory"]) / w["decay_rate_theory"]
        ctx.check("%s: period %.4f s against 2 pi/omega = %.4f s (relative)" %
                  (kernel, w["period"], w["period_theory"]), perr, PERIOD_BOUND,
                  abs(perr) <= PERIOD_BOUND, "fitted to %d kinetic-energy peaks" % w["peaks"])
        if kernel == "wendland_c2":
            ctx.check("%s: decay rate %.4f 1/s against 4 nu k^2 = %.4f 1/s (relative)" %
                      (kernel, w["decay_rate"], w["decay_rate_theory"]), rerr,
                      RATE_BOUND[ctx.level], abs(rerr) <= RATE_BOUND[ctx.level],
                      "envelope of the peaks up to t = %.2f s" % w["fit_until"])
        else:
            ctx.note("%s: decay rate %.4f 1/s against 4 nu k^2 = %.4f 1/s (%+.1f%%), alpha %.5f" %
                     (kernel, w["decay_rate"], w["decay_rate_theory"], 100 * rerr,
                      res["viscosity"]["alpha"]))
        diag = [e for e in events if e["type"] == "diag"]
        t = np.array([e["t"] for e in diag])
        e = np.array([e["ekin"] for e in diag])
        ax.plot(t, e / e[0], lw=0.8, label="sphd, " + kernel)
    beta, T = w["decay_rate_theory"], w["period_theory"]
    tt = np.linspace(0, t[-1], 2000)
    ax.plot(tt, 0.5 * np.exp(-beta * tt) * (1 + np.cos(4 * math.pi * tt / T)), "k--", lw=0.8,
            label="eq. (8), Lighthill")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("E_kin / E_kin(0)")
    ax.set_title("standing wave, Re = 500, " + RESOLUTION[ctx.level])
    ax.legend(fontsize=8)

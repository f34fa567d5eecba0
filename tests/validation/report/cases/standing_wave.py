"""Viscous standing wave (Macia et al., paper 001, section IV; cases/standing_wave.json): one
wavelength in a tank 1 m long, water 0.5 m deep, eps = 2A/H = 0.1, Re = H sqrt(gH)/nu = 500,
free-slip ghost walls, Monaghan's viscous term as a physical viscosity, dx/h = 0.5. The period
and the decay rate of the kinetic-energy envelope, fitted by sphd over the first 8 periods (its
`result.wave`), against 2 pi/omega and Lighthill's 4 nu k^2 (eq. 8), for Wendland C2 and the
renormalised Gaussian at H/dx = 50, 100 and 200 (full level; 50 at the ci level).

4 nu k^2 is the leading order in nu of the linear viscous wave's energy decay. At Re = 500 the
next order is not small: the exact linear rate, -2 Re(s) for the root s of Lamb's dispersion
relation (Hydrodynamics, section 349) (s + 2 nu k^2)^2 + omega^2 = 4 nu^2 k^4 sqrt(1 + s/(nu k^2)),
is 7.5% below it (2.4% at Re = 5000). So (issue 22, section 2) Lamb's rate is the yardstick of
convergence: Wendland C2's error against it must shrink from H/dx = 50 to 100 to 200 and be within
3% at 200; against 4 nu k^2 the issue-10 bounds stay for the record (15% at 100, 10% at 200; a
loose 20% at 50, the ci level's only rate check). The renormalised Gaussian's rate is reported
against both and not bounded: that it does not converge to Lamb's rate is a finding about the
kernel (paper 001's subject), not a failure.
"""
import math

import numpy as np

TITLE = "standing wave (paper 001): period and kinetic-energy decay against Lighthill"
H = 0.5                                   # still depth [m]
RESOLUTIONS = {"full": (50, 100, 200), "ci": (50,)}   # H/dx
RESOLUTION = {"full": "H/dx = 50, 100 and 200 (5,000, 20,000 and 80,000 particles), 8.4 periods",
              "ci": "H/dx = 50 (5,000 particles), 8.4 periods"}
PERIOD_BOUND = 0.02                       # |T - T_theory| / T_theory, the issue's
RATE_BOUND = {50: 0.20, 100: 0.15, 200: 0.10}  # |beta - 4 nu k^2| / 4 nu k^2 (Wendland): the
                                               # issue's 15% and 10%; a loose 20% at H/dx = 50
LAMB_BOUND = {200: 0.03}  # |beta - beta_Lamb| / beta_Lamb (Wendland) at the finest resolution
KERNELS = ("wendland_c2", "renormalized_gaussian")
T_END = 6.7                               # 8.4 periods: the fit takes the first 8


def lamb_rate(rate_theory, period_theory):
    """The exact linear decay rate of the kinetic energy [1/s]: -2 Re(s), s the damped root of
    Lamb's relation (s + 2a)^2 + w^2 = 4 a^2 sqrt(1 + s/a), a = nu k^2 = rate_theory / 4 and
    w = 2 pi / period_theory (Newton's method from the inviscid root)."""
    a, w = rate_theory / 4.0, 2.0 * math.pi / period_theory
    s = complex(-2.0 * a, w)
    for _ in range(60):
        m = (1.0 + s / a) ** 0.5
        f = (s + 2.0 * a) ** 2 + w * w - 4.0 * a * a * m
        s -= f / (2.0 * (s + 2.0 * a) - 2.0 * a / m)
    return -2.0 * s.real


def run(ctx):
    res = RESOLUTIONS[ctx.level]
    errors = {k: [] for k in KERNELS}
    lamb_errors = {k: [] for k in KERNELS}
    series = {}
    for kernel in KERNELS:
        for n in res:
            sets = ["dx=%g" % (H / n), "time.end=%g" % T_END, "kernel.type=" + kernel]
            result, diag, _ = ctx.sphd_run_long("cases/standing_wave.json", sets,
                                                "standing_wave-%s-hdx%d" % (kernel, n))
            w = result["wave"]
            perr = (w["period"] - w["period_theory"]) / w["period_theory"]
            rerr = (w["decay_rate"] - w["decay_rate_theory"]) / w["decay_rate_theory"]
            errors[kernel].append(rerr)
            exact = lamb_rate(w["decay_rate_theory"], w["period_theory"])
            lamb_errors[kernel].append((w["decay_rate"] - exact) / exact)
            lamb_what = ("%s, H/dx = %d: decay rate %.4f 1/s against Lamb's exact linear rate "
                         "%.4f 1/s (relative)" % (kernel, n, w["decay_rate"], exact))
            if kernel == "wendland_c2" and n in LAMB_BOUND:
                ctx.check(lamb_what, round(lamb_errors[kernel][-1], 4), LAMB_BOUND[n],
                          abs(lamb_errors[kernel][-1]) <= LAMB_BOUND[n],
                          "-2 Re(s), s the damped root of Lamb's relation (section 349)")
            else:
                ctx.note("%s: %+.1f%%" % (lamb_what, 100 * lamb_errors[kernel][-1]))
            ctx.check("%s, H/dx = %d: period %.4f s against 2 pi/omega = %.4f s (relative)" %
                      (kernel, n, w["period"], w["period_theory"]), perr, PERIOD_BOUND,
                      abs(perr) <= PERIOD_BOUND, "fitted to %d kinetic-energy peaks" % w["peaks"])
            what = "%s, H/dx = %d: decay rate %.4f 1/s against 4 nu k^2 = %.4f 1/s (relative)" % (
                kernel, n, w["decay_rate"], w["decay_rate_theory"])
            if kernel == "wendland_c2":
                ctx.check(what, rerr, RATE_BOUND[n], abs(rerr) <= RATE_BOUND[n],
                          "envelope of the peaks up to t = %.2f s" % w["fit_until"])
            else:  # the issue bounds Wendland's rate; the other kernel's is reported
                ctx.note("%s: %+.1f%% (alpha %.5f)" % (what, 100 * rerr,
                                                       result["viscosity"]["alpha"]))
            series[(kernel, n)] = (diag["t"], diag["ekin"])
            beta, period = w["decay_rate_theory"], w["period_theory"]
    if len(res) > 1:
        e = [abs(x) for x in lamb_errors["wendland_c2"]]
        ctx.check("wendland_c2: |rate error| against Lamb's exact linear rate shrinks from H/dx "
                  "= %s" % " to ".join(str(n) for n in res), max(b - a for a, b in zip(e, e[1:])),
                  0.0, all(a > b for a, b in zip(e, e[1:])), "errors %s" % ", ".join(
                      "%+.2f%%" % (100 * x) for x in lamb_errors["wendland_c2"]))
        ctx.note("wendland_c2 rate errors at H/dx = %s: %s against 4 nu k^2 (growing: the "
                 "leading order's own error is 7.5%% here), %s against Lamb's exact rate "
                 "(shrinking)" % (", ".join(str(n) for n in res), ", ".join(
                     "%+.2f%%" % (100 * x) for x in errors["wendland_c2"]), ", ".join(
                     "%+.2f%%" % (100 * x) for x in lamb_errors["wendland_c2"])))
        ctx.note("renormalized_gaussian rate errors at H/dx = %s: %s against 4 nu k^2, %s "
                 "against Lamb's exact rate. Reported, not bounded: the renormalised Gaussian "
                 "does not converge to Lamb's rate as Wendland C2 does (its error stays near "
                 "the same value as H/dx grows). That is a finding about the kernel, paper 001's "
                 "subject, not a failure of the run." % (
                     ", ".join(str(n) for n in res),
                     ", ".join("%+.2f%%" % (100 * x) for x in errors["renormalized_gaussian"]),
                     ", ".join("%+.2f%%" % (100 * x)
                               for x in lamb_errors["renormalized_gaussian"])))
    ctx.note("The exact linear decay rate used as the yardstick: the kinetic energy of a linear "
             "standing wave in a viscous fluid decays as exp(-beta t) with beta = -2 Re(s), s the "
             "damped root of Lamb's dispersion relation (s + 2 nu k^2)^2 + omega^2 = "
             "4 nu^2 k^4 sqrt(1 + s/(nu k^2)) (Lamb, Hydrodynamics, 6th ed. 1932, section 349; "
             "omega^2 = g k tanh(k H) the inviscid frequency, solved by Newton's method from the "
             "inviscid root). Its leading order in nu is Lighthill's 4 nu k^2 (paper 001, eq. "
             "(8)); here the exact rate is %.1f%% below it." % (100 * (1 - exact / beta)))
    fig = ctx.figure("ekin", figsize=(6.5, 4))
    ax = fig.add_subplot(111)
    finest = res[-1]
    for kernel in KERNELS:
        t, e = series[(kernel, finest)]
        ax.plot(t, e / e[0], lw=0.8, label="sphd, %s, H/dx = %d" % (kernel, finest))
    tt = np.linspace(0, T_END, 2000)
    ax.plot(tt, 0.5 * np.exp(-beta * tt) * (1 + np.cos(4 * math.pi * tt / period)), "k--",
            lw=0.8, label="eq. (8), Lighthill")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("E_kin / E_kin(0)")
    ax.set_title("standing wave, Re = 500, H/dx = %d" % finest)
    ax.legend(fontsize=8)

    fig = ctx.figure("rate_convergence", figsize=(5, 3.6))
    ax = fig.add_subplot(111)
    for kernel in KERNELS:
        ax.plot(res, [100 * x for x in errors[kernel]], "o-", label=kernel + ", vs 4 nu k^2")
        ax.plot(res, [100 * x for x in lamb_errors[kernel]], "s--",
                label=kernel + ", vs Lamb's exact")
    for n in res:
        ax.plot([n, n], [-100 * RATE_BOUND[n], 100 * RATE_BOUND[n]], "_", color="0.4", ms=14)
        if n in LAMB_BOUND:
            ax.plot([n, n], [-100 * LAMB_BOUND[n], 100 * LAMB_BOUND[n]], "_", color="C3", ms=10)
    ax.axhline(0, color="k", lw=0.6)
    ax.set_xscale("log")
    ax.minorticks_off()
    ax.set_xticks(res)
    ax.set_xticklabels([str(n) for n in res])
    ax.set_xlabel("H/dx")
    ax.set_ylabel("decay rate error [%]")
    ax.set_title("decay rate error (bars: Wendland's bounds; red: against Lamb)")
    ax.legend(fontsize=8)

"""Solitary-wave run-up on a vertical wall (Sheu, Chiao & Huang 2011, paper 004, section 5.1;
cases/solitary_wave.json; issues 12 and 22): still depth d = 10 m, wave height H = 2 m, a channel
16d long, the crest starting at x0 = 60 m, MPS with the case's settings (Sheu et al.'s quartic
weight, the mixed source, the corrected gradient, the dynamic stabilization: those under which
still water stays at rest). The largest run-up R on the right wall above the still water (the
`runup` probe less its value at t = 0, which is the depth the lattice's whole rows hold: 9.6 m at
dx = 0.8 m, 10 m at 0.4 m) against the third order of Su & Mirie (1980)
(tests/validation/reference/solitary_wave_runup_vertical_wall.csv).

Issue 22, section 4: the paper's first-order initial field (eqs. (5.1)-(5.2), `initial.order` 1,
the case's) grows into a higher wave than the nominal H, so the bound applies to the wave that
arrives: the case's height gauge `incident` gives the incident crest height H_inc, the crest of a
sech^2 fitted to its record above d before the largest run-up (the reflection leaves the wall then).
The issue asked for the gauge two to three depths before the wall; at H/d = 0.2 the wave is long
(sech^2 half-width about 2.6 d), so there the wall's reflection of its front is already back when
the crest passes: a steady wave plus its mirror image reads 1.06-1.24 H at 3 to 2 depths. The
gauge is therefore at x = 110 m, 5 depths before the wall, where the image adds 0.2% at most; the
case's gauge `x135` at 2.5 depths is fitted and noted beside it. R/d is compared with the
third order at H_inc/d: within 10% at the paper's dx = 0.8 m (every level) and 5% at 0.4 m (full
level); the comparison at the nominal H/d stays beside it (noted). The full level also runs
Grimshaw's third-order initial field (`initial.order` 3), whose H_inc must be within 2% of H at
dx = 0.4 m, measures the spread with the time-step sequence (snapshots every 0.2 s and 0.25 s
beside the case's 0.5 s: the steps stop on the output times) and runs Koshizuka's weight beside
(noted, not checked).
"""
import glob
import math
import os

import numpy as np

TITLE = "solitary wave: run-up on a vertical wall against third-order theory"
G, H = 9.81, 2.0
GAUGE = "incident"        # the case's height gauge, 5 depths before the wall
GAUGE_NEAR = "x135"       # and the one 2.5 depths before it (noted)
SETS = {"sheu_quartic": [], "koshizuka": ["kernel.type=koshizuka", "mps.re=2.1",
                                        "mps.re_grad=2.1"]}
RUNUP_BOUND = {0.8: 0.10, 0.4: 0.05}   # |R/d - third order at H_inc| / third order, per dx
INCIDENT_BOUND = 0.02                  # |H_inc - H| / H with the third-order field at dx = 0.4
# (weight, dx, initial field's order, snapshot interval [s], what is checked: "runup" (R/d at
# H_inc within RUNUP_BOUND[dx]), "incident" (H_inc within INCIDENT_BOUND of H) or None (noted))
RUNS = {"full": [("sheu_quartic", 0.8, 1, 0.5, "runup"), ("sheu_quartic", 0.4, 1, 0.5, "runup"),
                 ("sheu_quartic", 0.8, 3, 0.5, None), ("sheu_quartic", 0.4, 3, 0.5, "incident"),
                 ("sheu_quartic", 0.8, 1, 0.2, None), ("sheu_quartic", 0.8, 1, 0.25, None),
                 ("koshizuka", 0.8, 1, 0.5, None), ("koshizuka", 0.4, 1, 0.5, None)],
        "ci": [("sheu_quartic", 0.8, 1, 0.5, "runup")]}
RESOLUTION = {"full": "dx = 0.8 m (the paper's, 2,500 fluid particles) and 0.4 m (10,000), the "
                      "first- and third-order initial fields, both MPS weights",
              "ci": "dx = 0.8 m (the paper's spacing, 2,500 fluid particles), the case's quartic "
                    "weight and first-order field"}


def surface(snap):
    """The fluid's time, and its free surface as (column centres, top + dx/2) of a snapshot."""
    import h5py
    with h5py.File(snap, "r") as f:
        t, dx = float(f.attrs["time"]), float(f.attrs["dx"])
        pos, typ = f["pos"][:], f["type"][:]
    p = pos[typ == 0]
    col = np.floor(p[:, 0] / dx).astype(int)
    top = np.full(col.max() + 1, np.nan)
    for k in np.unique(col):
        top[k] = p[col == k, 1].max() + 0.5 * dx
    x = (np.arange(len(top)) + 0.5) * dx
    return t, x, top, p


def crest_fit(t, eta):
    """The crest height of a solitary wave's passage in a gauge record eta(t) (above the still
    depth): the least-squares fit of A sech^2((t - t0)/tau) to the samples at or above a quarter
    of the record's highest (the crest and its flanks), which is what a solitary wave gives a
    fixed gauge. The gauge reads the top particle, so single particles that rise for a moment
    (up to dx/4 at dx = 0.8 m) make its highest reading overstate the crest; the fit takes the
    whole passage. A is linear given (t0, tau): a grid over those two (0.01 s), refined once.
    Returns (A, t0, tau)."""
    sel = eta >= 0.25 * np.nanmax(eta)
    ts, es = t[sel], eta[sel]

    def best(t0s, taus):
        T0, TAU = np.meshgrid(t0s, taus, indexing="ij")
        f = 1.0 / np.cosh((ts[None, None, :] - T0[..., None]) / TAU[..., None]) ** 2
        A = np.sum(f * es, axis=-1) / np.sum(f * f, axis=-1)
        cost = np.sum((A[..., None] * f - es) ** 2, axis=-1)
        i, j = np.unravel_index(int(np.argmin(cost)), cost.shape)
        return float(A[i, j]), float(t0s[i]), float(taus[j])

    A, t0, tau = best(np.arange(ts[0], ts[-1] + 1e-9, 0.01), np.arange(0.2, 6.0, 0.01))
    return best(np.arange(t0 - 0.01, t0 + 0.01, 0.0005), np.arange(tau - 0.01, tau + 0.01,
                                                                   0.0005))


def third_order(ref, eps):
    return float(np.interp(eps, ref["eps"], ref["R_over_d_3rd_SuMirie"]))


def run(ctx):
    ref = ctx.reference_columns("solitary_wave_runup_vertical_wall.csv")
    fig = ctx.figure("runup", figsize=(6.5, 4.2))
    ax = fig.add_subplot(111)
    figg = ctx.figure("incident_gauge", figsize=(6.5, 4.2))
    axg = figg.add_subplot(111)
    fig2 = ctx.figure("free_surface", figsize=(7.5, 2.2 * len(RUNS[ctx.level]) + 0.6))
    summary = []
    for k, (weight, dx, order, every, checked) in enumerate(RUNS[ctx.level]):
        sets = ["dx=%g" % dx, "output.every=%g" % every] + SETS[weight]
        if order != 1:
            sets.append("initial.order=%d" % order)
        events, out = ctx.sphd_run("cases/solitary_wave.json", sets,
                                   job="solitary_wave_%s_%g_order%d_every%g"
                                   % (weight, dx, order, every))
        assert events[-1].get("state") == "done", events[-1]
        diag = [e for e in events if e["type"] == "diag"]
        t = np.array([e["t"] for e in diag])
        r = np.array([np.nan if e.get("runup") is None else e["runup"] for e in diag])
        g = np.array([e["gauges"][GAUGE] for e in diag])
        gn = np.array([e["gauges"][GAUGE_NEAR] for e in diag])
        d = r[0]  # the still depth the lattice holds (the wave's hump is far from the wall)
        expect_d = math.floor(10.0 / dx + 1e-6) * dx
        assert abs(d - expect_d) < 0.5 * dx, (d, expect_d)
        kmax = int(np.nanargmax(r))
        R = (r[kmax] - d) / d
        before = t <= t[kmax]
        Hi, tinc, tau = crest_fit(t[before], g[before] - d)
        graw = float(np.max(g[before]) - d)
        Hn = crest_fit(t[before], gn[before] - d)[0]
        ref_inc, ref_nom = third_order(ref, Hi / d), third_order(ref, H / d)
        rel_inc, rel_nom = (R - ref_inc) / ref_inc, (R - ref_nom) / ref_nom
        label = "%s, dx = %g m, order %d%s" % (weight, dx, order, "" if every == 0.5 else
                                               ", snapshots every %g s" % every)
        lost = diag[-1]["lost"]
        ctx.check("%s: no fluid particle lost" % label, lost, 0, lost == 0)
        how = ("largest run-up %.3f m above the still depth %.2f m at t = %.2f s; incident crest "
               "H_inc = %.3f m (gauge x = 110 m: sech^2 fit, crest at t = %.2f s, tau = %.2f s; "
               "highest reading %.3f m; the same fit at x = 135 m: %.3f m); third order R/d = %.4f at H_inc/d = %.4f (%.4f at the "
               "nominal H/d = %.4f: %+.1f%%)"
               % (r[kmax] - d, d, t[kmax], Hi, tinc, tau, graw, Hn, ref_inc, Hi / d, ref_nom,
                  H / d, 100 * rel_nom))
        if checked == "runup":
            ctx.check("%s: largest run-up R/d against third order at the incident crest "
                      "H_inc/d, relative difference" % label, round(rel_inc, 4),
                      RUNUP_BOUND[dx], abs(rel_inc) <= RUNUP_BOUND[dx], how)
        inc_err = (Hi - H) / H
        if checked == "incident":
            ctx.check("%s: incident crest H_inc against the nominal H = %g m, relative "
                      "difference" % (label, H), round(inc_err, 4), INCIDENT_BOUND,
                      abs(inc_err) <= INCIDENT_BOUND, how)
        if checked != "runup":
            print("  note %s: R/d %.4f, %+.1f%% against third order at H_inc, H_inc/H = %.4f "
                  "(%s)" % (label, R, 100 * rel_inc, Hi / H, how))
        summary.append("%s: H_inc/H = %.3f (at x = 135 m: %.3f); R/d = %.3f at t = %.2f s, %+.1f%% against the third "
                       "order at H_inc/d (%.4f), %+.1f%% at the nominal H/d (%.4f)" % (
                           label, Hi / H, Hn / H, R, t[kmax], 100 * rel_inc, ref_inc, 100 * rel_nom,
                           ref_nom))
        ax.plot(t * math.sqrt(G / d), (r - d) / d, "-", lw=0.9, label="sphd, " + label)
        axg.plot(t, (g - d) / H, "-", lw=0.9, color="C%d" % k,
                 label="%s: H_inc/H = %.3f" % (label, Hi / H))
        tt = np.linspace(tinc - 3 * tau, min(tinc + 3 * tau, t[kmax]), 200)
        axg.plot(tt, Hi / H / np.cosh((tt - tinc) / tau) ** 2, ":", lw=1.2, color="C%d" % k)
        # the free surface at the snapshot nearest the largest run-up
        snaps = sorted(glob.glob(os.path.join(out, "snap_*.h5")))
        ts = [round(i * every, 9) for i in range(len(snaps))]
        j = int(np.argmin(np.abs(np.array(ts) - t[kmax])))
        ts_j, x, top, p = surface(snaps[j])
        a = fig2.add_subplot(len(RUNS[ctx.level]), 1, k + 1)
        a.plot(p[:, 0], p[:, 1], ".", ms=0.8, color="0.6")
        a.plot(x, top, "-", lw=0.9, color="C0", label="free surface (top particle + dx/2)")
        a.axhline(d, color="k", lw=0.5, ls=":")
        a.axhline(d + ref_inc * d, color="C3", lw=0.8, ls="--",
                  label="third-order run-up at H_inc")
        a.set_xlim(100, 160)
        a.set_ylim(0, d + 2.5 * H)
        a.set_title("%s, t = %.2f s (largest run-up at %.2f s)" % (label, ts_j, t[kmax]),
                    fontsize=8)
        a.set_ylabel("y [m]")
        a.legend(loc="upper left", fontsize=6)
    for name in ("R_over_d_3rd_SuMirie", "R_over_d_linear"):
        v = float(np.interp(H / 10.0, ref["eps"], ref[name]))
        ax.axhline(v, color="k", lw=0.7, ls="--" if "3rd" in name else ":",
                   label="%s order, eps = 0.2" % ("third" if "3rd" in name else "linear"))
    ax.set_xlabel("t sqrt(g/d)")
    ax.set_ylabel("(run-up - d) / d at the right wall")
    ax.set_title("Solitary wave H/d = 0.2: run-up on the right wall")
    ax.legend(loc="upper left", fontsize=7)
    axg.axhline(1.0, color="k", lw=0.7, ls="--", label="nominal H")
    axg.axhspan(1 - INCIDENT_BOUND, 1 + INCIDENT_BOUND, color="0.9", zorder=0,
                label="H within %.0f%%" % (100 * INCIDENT_BOUND))
    axg.set_xlabel("t [s]")
    axg.set_ylabel("(gauge - d) / H")
    axg.set_title("incident wave at x = 110 m (dotted: the sech^2 fit giving H_inc)")
    axg.legend(loc="upper right", fontsize=6)
    fig2.axes[-1].set_xlabel("x [m]")
    ctx.note("Largest run-up against Su & Mirie's third order: " + "; ".join(summary) + ".")
    ctx.note("The incident crest H_inc is the height A of the least-squares fit of "
             "A sech^2((t - t0)/tau), the record a solitary wave leaves at a fixed gauge, to the "
             "case's height gauge at x = 110 m (the top fluid particle within dx of the line "
             "plus dx/2, sampled with every diag), over its readings above a quarter of its "
             "highest up to the largest run-up, before the reflection comes back. The gauge's "
             "highest reading is noted too: single surface particles rise and fall by up to a "
             "quarter of dx, so it overstates the crest. The gauge stands 5 depths before the "
             "wall, not the 2-3 the issue named: this wave is long (sech^2 half-width about "
             "2.6 d), and at 2-3 depths the wall's reflection of its front is back before the "
             "crest passes (a steady wave and its mirror image read 1.06-1.24 H there, 1.002 H "
             "at 5 depths); the same fit at x = 135 m is noted. The paper's first-order initial "
             "field (its crest velocity sqrt(gd) H/d is 10%% above a solitary wave's "
             "c H/(d + H)) adjusts in the first seconds into a wave higher than H = %g m, so "
             "issue 22 bounds the run-up against the third order at H_inc/d; the comparison "
             "at the nominal H/d is noted beside it. Grimshaw's third-order field "
"(`initial.order` 3) starts as a solitary wave of height H." % H)

#include "sph_envelope.h"

#include <math.h>
#include <string.h>

void sph_envelope_init(sph_envelope *e, double period)
{
    memset(e, 0, sizeof *e);
    e->period = period;
    e->win_lo = -INFINITY;
    e->win_hi = 0.25 * period;
}

void sph_envelope_add(sph_envelope *e, double t, double ekin)
{
    if (t > e->win_hi) { /* the window is over: its largest sample is a peak */
        if (e->have_best && e->npeaks < SPH_ENVELOPE_MAX_PEAKS) {
            e->tp[e->npeaks] = e->best_t;
            e->ep[e->npeaks] = e->best_e;
            e->npeaks++;
        }
        const double from = e->have_best ? e->best_t : e->win_hi;
        e->win_lo = from + 0.25 * e->period;
        e->win_hi = from + 0.75 * e->period;
        e->have_best = 0;
        while (t > e->win_hi) { /* a gap in the samples longer than a window */
            e->win_lo += 0.5 * e->period;
            e->win_hi += 0.5 * e->period;
        }
    }
    if (t >= e->win_lo && (!e->have_best || ekin > e->best_e)) {
        e->best_t = t;
        e->best_e = ekin;
        e->have_best = 1;
    }
}

/* Least-squares slope of y over x. */
static double slope(const double *x, const double *y, int n)
{
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (int i = 0; i < n; i++) {
        sx += x[i];
        sy += y[i];
        sxx += x[i] * x[i];
        sxy += x[i] * y[i];
    }
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

int sph_envelope_fit_peaks(const sph_envelope *e, double t_max, sph_envelope_fit *f)
{
    memset(f, 0, sizeof *f);
    double k[SPH_ENVELOPE_MAX_PEAKS], lnE[SPH_ENVELOPE_MAX_PEAKS];
    int n = 0;
    for (int i = 0; i < e->npeaks && e->tp[i] <= t_max; i++) {
        if (!(e->ep[i] > 0.0))
            break;
        k[n] = i;
        lnE[n] = log(e->ep[i]);
        n++;
    }
    if (n < 3)
        return -1;
    f->npeaks = n;
    f->decay_rate = -slope(e->tp, lnE, n);
    f->period = 2.0 * slope(k, e->tp, n);
    return 0;
}

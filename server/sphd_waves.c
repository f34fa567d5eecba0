/*
 * sphd_waves: wave analysis of a flume's height gauges (sphd_waves.h).
 */
#include "sphd_waves.h"
#include "sphd_reflect.h"

#include "sph_events.h"
#include "sph_sim.h"

#include <math.h>
#include <stdlib.h>

/* The mean of eta over t >= t0 into *mean; the samples there (fewer than 3: nothing to take). */
static long window_mean(const double *t, const double *eta, long stride, long n, double t0,
                        double *mean)
{
    double sum = 0.0;
    long m = 0;
    for (long i = 0; i < n; i++)
        if (t[i] >= t0) {
            sum += eta[i * stride];
            m++;
        }
    *mean = m > 0 ? sum / (double)m : NAN;
    return m;
}

/* The zero-up-crossing waves of eta over t >= t0 about mean: each from one up-crossing (linearly
 * interpolated) to the next, its height the series' range between them, into h[count] (h NULL:
 * not kept); their sum into *hsum and the first and last crossings' times. Returns the count. */
static int zero_up_walk(const double *t, const double *eta, long stride, long n, double t0,
                        double mean, double *h, double *hsum, double *first, double *last)
{
    int count = 0;
    double lo = INFINITY, hi = -INFINITY;
    *hsum = 0.0;
    *first = *last = NAN;
    for (long i = 1; i < n; i++) {
        if (t[i - 1] < t0)
            continue;
        const double e0 = eta[(i - 1) * stride], a = e0 - mean, b = eta[i * stride] - mean;
        if (isfinite(*first)) {
            lo = fmin(lo, e0);
            hi = fmax(hi, e0);
        }
        if (a < 0.0 && b >= 0.0) {
            const double tc = t[i - 1] + (t[i] - t[i - 1]) * (-a) / (b - a);
            if (isfinite(*first)) {
                *hsum += hi - lo;
                if (h)
                    h[count] = hi - lo;
                count++;
                *last = tc;
            } else {
                *first = tc;
            }
            lo = INFINITY;
            hi = -INFINITY;
        }
    }
    return count;
}

int sphd_waves_zero_up(const double *t, const double *eta, long stride, long n, double t0,
                       double *height, double *period)
{
    *height = NAN;
    *period = NAN;
    double mean, hsum, first, last;
    if (window_mean(t, eta, stride, n, t0, &mean) < 3)
        return 0;
    const int count = zero_up_walk(t, eta, stride, n, t0, mean, NULL, &hsum, &first, &last);
    if (count == 0)
        return 0;
    *height = hsum / count;
    *period = (last - first) / count;
    return count;
}

int sphd_waves_crest(const double *t, const double *eta, long stride, long n, double t_still,
                     double t0, double t1, double *height, double *time, double *level)
{
    *height = *time = *level = NAN;
    double lv = 0.0;
    long m = 0, top = -1;
    for (long i = 0; i < n; i++) {
        if (i == 0 || t[i] <= t_still) {
            lv += eta[i * stride];
            m++;
        }
        if (t[i] >= t0 && t[i] <= t1 && (top < 0 || eta[i * stride] > eta[top * stride]))
            top = i;
    }
    lv /= (double)m;
    *level = lv;
    if (top < 0)
        return 0;
    double tc = t[top], ec = eta[top * stride];
    if (top > 0 && top < n - 1) { /* the parabola through the top sample and its neighbours */
        const double ta = t[top - 1], tb = t[top + 1];
        const double ea = eta[(top - 1) * stride], eb = eta[(top + 1) * stride];
        const double d1 = (ec - ea) / (tc - ta), d2 = (eb - ec) / (tb - tc);
        const double curv = (d2 - d1) / (tb - ta); /* half the second derivative */
        if (curv < 0.0) {
            const double ts = 0.5 * (ta + tc) - d1 / (2.0 * curv);
            if (ts >= ta && ts <= tb) {
                ec = ea + d1 * (ts - ta) + curv * (ts - ta) * (ts - tc);
                tc = ts;
            }
        }
    }
    *height = ec - lv;
    *time = tc;
    return 1;
}

static int cmp_desc(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x < y) - (x > y);
}

int sphd_waves_sea(const double *t, const double *eta, long stride, long n, double t0, double *hm0,
                   double *h13)
{
    *hm0 = *h13 = NAN;
    double mean, var = 0.0, hsum, first, last;
    const long m = window_mean(t, eta, stride, n, t0, &mean);
    if (m < 3)
        return 0;
    for (long i = 0; i < n; i++)
        if (t[i] >= t0)
            var += (eta[i * stride] - mean) * (eta[i * stride] - mean);
    *hm0 = 4.0 * sqrt(var / (double)m);
    double *h = malloc((size_t)m * sizeof *h); /* fewer waves than samples */
    if (!h)
        return 0;
    const int count = zero_up_walk(t, eta, stride, n, t0, mean, h, &hsum, &first, &last);
    if (count > 0) {
        qsort(h, (size_t)count, sizeof *h, cmp_desc);
        const int third = count / 3 > 0 ? count / 3 : 1;
        double sum = 0.0;
        for (int i = 0; i < third; i++)
            sum += h[i];
        *h13 = sum / third;
    }
    free(h);
    return count;
}

double sphd_waves_window(const sph_config *c, int k)
{
    sph_wave_design w;
    const sph_waves_type type = c->wavemaker.waves;
    if ((type != SPH_WAVES_REGULAR && type != SPH_WAVES_IRREGULAR) || sph_sim_wave_design(c, &w) ||
        k < 0 || k >= c->ngauges)
        return NAN;
    /* the ramp's end reaches the gauge at ramp T + distance / cg; one period more lets the
     * train's dispersed front go by (an irregular sea: the peak's period and group velocity) */
    const double period = type == SPH_WAVES_IRREGULAR ? c->wavemaker.tp : c->wavemaker.period;
    return (c->wavemaker.ramp + 1.0) * period + fabs(c->gauges[k].x - c->wavemaker.x) / w.cg;
}

json_t *sphd_waves_json(const sph_config *c, const double *t, const double *g, long n)
{
    const int irregular = c->wavemaker.waves == SPH_WAVES_IRREGULAR;
    if (c->wavemaker.type == SPH_WAVEMAKER_NONE ||
        (c->wavemaker.waves != SPH_WAVES_REGULAR && !irregular) || c->ngauges == 0 || n < 1)
        return NULL;
    const int ng = c->ngauges;
    json_t *out = json_object();
    if (!out)
        return NULL;
    for (int k = 0; k < ng; k++) {
        const double t0 = sphd_waves_window(c, k);
        double H, T;
        const int count = sphd_waves_zero_up(t, g + k, ng, n, t0, &H, &T);
        json_t *o =
            json_pack("{s:o, s:o, s:i, s:o}", "height", sph_json_real_or_null(H), "period",
                      sph_json_real_or_null(T), "count", count, "from", sph_json_real_or_null(t0));
        if (irregular && o) {
            double hm0, h13;
            sphd_waves_sea(t, g + k, ng, n, t0, &hm0, &h13);
            json_object_set_new(o, "hm0", sph_json_real_or_null(hm0));
            json_object_set_new(o, "h13", sph_json_real_or_null(h13));
        }
        json_object_set_new(out, c->gauges[k].name, o);
    }
    return out;
}

json_t *sphd_waves_solitary_json(const sph_config *c, const double *t, const double *g, long n)
{
    sph_wave_design w;
    if (c->wavemaker.type == SPH_WAVEMAKER_NONE || c->wavemaker.waves != SPH_WAVES_SOLITARY ||
        c->ngauges == 0 || n < 1 || sph_sim_wave_design(c, &w))
        return NULL;
    const int ng = c->ngauges;
    json_t *gauges = json_object();
    double sx = 0.0, st = 0.0, sxt = 0.0, stt = 0.0;
    int found = 0;
    for (int k = 0; k < ng; k++) {
        /* the wave's front (theta = -theta0) leaves the paddle at t = 0 and moves at c, its
         * crest theta0 / kappa behind it: the window is the crest's time +- 2 / (kappa c), where
         * the theory's wave is above sech^2(2) = 7% of its height */
        const double dx = fabs(c->gauges[k].x - c->wavemaker.x);
        const double crest = (dx + w.lag) / w.celerity;
        const int runup = !isnan(c->gauges[k].to); /* from the front's arrival to the end */
        const double t0 = runup ? dx / w.celerity : crest - 2.0 / (w.kappa * w.celerity);
        const double t1 = runup ? t[n - 1] : crest + 2.0 / (w.kappa * w.celerity);
        double H, tc, level;
        const int got = sphd_waves_crest(t, g + k, ng, n, dx / w.celerity, t0, t1, &H, &tc, &level);
        json_object_set_new(gauges, c->gauges[k].name,
                            json_pack("{s:o, s:o, s:o, s:o, s:o}", "height",
                                      sph_json_real_or_null(H), "time", sph_json_real_or_null(tc),
                                      "level", sph_json_real_or_null(level), "from",
                                      sph_json_real_or_null(t0), "to", sph_json_real_or_null(t1)));
        if (got && !runup && t1 <= t[n - 1]) {
            const double x = c->gauges[k].x;
            sx += x;
            st += tc;
            sxt += x * tc;
            stt += tc * tc;
            found++;
        }
    }
    /* the crest's speed: the least-squares slope of the gauges' x against their crests' times */
    const double den = found * stt - st * st;
    const double cel = found >= 2 && den > 0.0 ? fabs((found * sxt - sx * st) / den) : NAN;
    return json_pack("{s:o, s:o, s:o, s:o}", "celerity", sph_json_real_or_null(cel), "theory",
                     sph_json_real_or_null(w.celerity), "stroke", sph_json_real_or_null(w.stroke),
                     "gauges", gauges);
}

json_t *sphd_waves_reflection_json(const sph_config *c, const sph_output_config *o, const double *t,
                                   const double *g, long n)
{
    sph_wave_design w;
    if (c->wavemaker.type == SPH_WAVEMAKER_NONE || o->nreflect < 2 || n < 1 ||
        sph_sim_wave_design(c, &w))
        return NULL;
    /* the case's gauges, from the latest of their windows to the run's end */
    const int m = o->nreflect;
    long cols[SPH_CONFIG_MAX_GAUGES];
    double x[SPH_CONFIG_MAX_GAUGES], t0 = -INFINITY;
    json_t *names = json_array();
    for (int j = 0; j < m; j++) {
        const int k = o->reflect[j];
        cols[j] = k;
        x[j] = c->gauges[k].x;
        t0 = fmax(t0, sphd_waves_window(c, k));
        json_array_append_new(names, json_string(c->gauges[k].name));
    }
    sphd_reflect_out r;
    const char *why = NULL;
    if (sphd_reflect(t, g, c->ngauges, cols, x, m, n, t0, t[n - 1], w.omega, w.k, &r))
        why = isnan(r.cond) ? "the run ends less than a period after the window opens"
                            : "the gauges are too near a multiple of half a wavelength apart";
    json_t *out = json_pack(
        "{s:o, s:o, s:o, s:o, s:o, s:o, s:o}", "coefficient", sph_json_real_or_null(r.kr),
        "incident_height", sph_json_real_or_null(r.hi), "reflected_height",
        sph_json_real_or_null(r.hr), "conditioning", sph_json_real_or_null(r.cond), "from",
        sph_json_real_or_null(t0), "to", sph_json_real_or_null(t[n - 1]), "gauges", names);
    if (out && why)
        json_object_set_new(out, "why", json_string(why));
    return out;
}

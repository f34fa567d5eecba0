/*
 * sphd_waves: wave analysis of a flume's height gauges (PROTOCOL.md section 1.8): the
 * zero-up-crossing wave height and period of each gauge's series over the window after the
 * wavemaker's ramp, in the result event and result.json as "waves"; a solitary wave's crest at
 * each gauge and its celerity as "solitary".
 */
#ifndef SPHD_WAVES_H
#define SPHD_WAVES_H

#include "sph_case.h"
#include "sph_config.h"

#include <jansson.h>

/* Zero-up-crossing analysis of eta(t) (n samples, t increasing, sample i at eta[i * stride]:
 * one gauge's column of a row-major table) over t >= t0: the level is the window's mean; each
 * wave runs from one up-crossing (linearly interpolated) to the next, its height the series'
 * range between them. Writes the mean height [m] and period [s] of the waves and returns their
 * count (0: none, height and period NaN). */
int sphd_waves_zero_up(const double *t, const double *eta, long stride, long n, double t0,
                       double *height, double *period);

/* An irregular sea's statistics of eta(t) (as sphd_waves_zero_up's arguments) over t >= t0: the
 * spectral significant height Hm0 = 4 sqrt(m0), m0 the variance about the window's mean, and
 * H1/3, the mean of the highest third of the zero-up-crossing waves. Writes both [m] (NaN
 * without samples or waves) and returns the count of waves. */
int sphd_waves_sea(const double *t, const double *eta, long stride, long n, double t0, double *hm0,
                   double *h13);

/* A solitary wave's crest in eta(t) (n samples, t increasing, sample i at eta[i * stride]): the
 * highest sample within [t0, t1] and the parabola through it and its neighbours, its height above
 * the still level (the mean of the samples up to t_still, the first one at least). Writes the
 * height [m], the crest's time [s] and the level [m]; returns 1, or 0 when no sample lies in the
 * window (height and time NaN). */
int sphd_waves_crest(const double *t, const double *eta, long stride, long n, double t_still,
                     double t0, double t1, double *height, double *time, double *level);

/* The window of gauge k of c: it opens one period after the end of the ramp, moving at linear
 * theory's group velocity cg, has reached the gauge, so that the waves in it are the developed
 * train, not its growing front: (ramp + 1) T + |x_gauge - x_paddle| / cg [s] (an irregular sea:
 * the peak's T and cg). NaN without regular or irregular waves. */
double sphd_waves_window(const sph_config *c, int k);

/* {"GAUGE": {"height", "period", "count", "from"}, ...} for c's gauges from the series t[n]
 * and g[n][ngauges] (row-major), an irregular sea's with "hm0" and "h13" (sphd_waves_sea)
 * besides, or NULL without regular or irregular waves or without gauges (new reference). */
json_t *sphd_waves_json(const sph_config *c, const double *t, const double *g, long n);

/* A solitary wave's passage at c's gauges (PROTOCOL.md section 1.8): {"celerity", "theory",
 * "stroke", "gauges": {"GAUGE": {"height", "time", "level", "from", "to"}}}, each gauge's crest
 * (sphd_waves_crest) within [from, to], the theory's crest time +- 2 / (kappa c) (the crest
 * (x - x_paddle + 3.8 / kappa) / c), the still level the mean before the theory's front reaches
 * the gauge ((x - x_paddle) / c); a run-up gauge's (`to`) the highest reading from that arrival
 * to the run's end, the run-up above the still level; the celerity the least-squares slope of
 * the line gauges' x against their crests' times (null with fewer than 2 whole windows), "theory"
 * sqrt(g (d + H)). NULL without a solitary wave or gauges (new reference). */
json_t *sphd_waves_solitary_json(const sph_config *c, const double *t, const double *g, long n);

/* The reflection of the flume's waves (sphd_reflect.h) from the gauges of the case's
 * diagnostics.reflection (o), over the latest of their windows to the run's end: {"coefficient",
 * "incident_height", "reflected_height", "conditioning", "from", "to", "gauges"}, the numbers
 * null and "why" added when the waves cannot be split; NULL without a wavemaker or those gauges
 * (new reference). */
json_t *sphd_waves_reflection_json(const sph_config *c, const sph_output_config *o, const double *t,
                                   const double *g, long n);

#endif

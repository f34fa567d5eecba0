/*
 * sphd_waves: wave analysis of a flume's height gauges (PROTOCOL.md section 1.8): the
 * zero-up-crossing wave height and period of each gauge's series over the window after the
 * wavemaker's ramp, in the result event and result.json as "waves".
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

/* The window of gauge k of c: it opens one period after the end of the ramp, moving at linear
 * theory's group velocity cg, has reached the gauge, so that the waves in it are the developed
 * train, not its growing front: (ramp + 1) T + |x_gauge - x_paddle| / cg [s]. NaN without a
 * wavemaker. */
double sphd_waves_window(const sph_config *c, int k);

/* {"GAUGE": {"height", "period", "count", "from"}, ...} for c's gauges from the series t[n]
 * and g[n][ngauges] (row-major), or NULL without a wavemaker or gauges (new reference). */
json_t *sphd_waves_json(const sph_config *c, const double *t, const double *g, long n);

/* The reflection of the flume's waves (sphd_reflect.h) from the gauges of the case's
 * diagnostics.reflection (o), over the latest of their windows to the run's end: {"coefficient",
 * "incident_height", "reflected_height", "conditioning", "from", "to", "gauges"}, the numbers
 * null and "why" added when the waves cannot be split; NULL without a wavemaker or those gauges
 * (new reference). */
json_t *sphd_waves_reflection_json(const sph_config *c, const sph_output_config *o, const double *t,
                                   const double *g, long n);

#endif

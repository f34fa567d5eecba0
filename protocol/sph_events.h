/*
 * sph_events: the JSON objects a job emits (PROTOCOL.md, "Events"). The same objects go to the
 * stream socket and to stdout in `sphd --run`.
 */
#ifndef SPH_EVENTS_H
#define SPH_EVENTS_H

#include "sph_case.h"
#include "sph_study.h"

#include <jansson.h>

/* {"job": job, "seq": seq, "type": type}: new reference, NULL on allocation failure. */
json_t *sph_event_new(const char *job, long seq, const char *type);

/* A number, or null when it is not finite (JSON has no NaN). New reference. */
json_t *sph_json_real_or_null(double x);

/* The result object of a kernel study (the body of its `result` event). New reference. */
json_t *sph_study_result_json(const sph_study_config *cfg, const sph_study_result *res);

#endif

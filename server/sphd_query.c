/*
 * Particle queries (`query` with "fields"): the fields of a job's executor, and the whole reply
 * encoded, by the thread that may read that executor: the job's worker while it runs, the files
 * thread while it is paused. The socket loop only sends the text it gets (a million particles
 * are tens of megabytes of JSON: never built on the loop, which would hold up every client).
 */
#include "sphd_daemon.h"

#include <limits.h>
#include <stdlib.h>

#define SPHD_MAX_FIELDS 8

json_t *sphd_particles(sphd_exec *x, const sph_case *c, json_t *fields, long max, sphd_err *e)
{
    const char *names[SPHD_MAX_FIELDS];
    const size_t n = json_array_size(fields);
    if (!sph_case_is_sim(c)) {
        sphd_err_set(e, SPHD_E_BAD_REQUEST, "/args/fields", "%s jobs have no particle fields",
                     sph_method_name(c->method));
        return NULL;
    }
    if (n < 1 || n > SPHD_MAX_FIELDS) {
        sphd_err_set(e, SPHD_E_BAD_REQUEST, "/args/fields", "'fields' names 1 to %d fields",
                     SPHD_MAX_FIELDS);
        return NULL;
    }
    for (size_t i = 0; i < n; i++)
        names[i] = json_string_value(json_array_get(fields, i));
    sph_error err;
    sph_error_clear(&err);
    json_t *r = sphd_exec_particles(x, names, (int)n, max > 0 ? max : LONG_MAX, &err);
    if (!r)
        sphd_err_set(e, err.code == SPH_ERR_INVALID ? SPHD_E_BAD_REQUEST : SPHD_E_INTERNAL,
                     "/args/fields", "%s", err.message);
    return r;
}

char *sphd_particles_reply(sphd_exec *x, const sph_case *c, json_t *fields, long max,
                           json_t *status, json_t *id)
{
    sphd_err e;
    json_t *parts = status ? sphd_particles(x, c, fields, max, &e) : NULL;
    if (!status)
        sphd_err_set(&e, SPHD_E_INTERNAL, NULL, "out of memory");
    json_t *reply;
    if (parts) {
        json_object_set_new(status, "particles", parts);
        reply = sphd_reply_new(id, status, NULL);
    } else {
        reply = sphd_reply_new(id, NULL, &e);
        json_decref(status);
    }
    json_decref(id);
    char *text = reply ? json_dumps(reply, JSON_COMPACT | JSON_REAL_PRECISION(12)) : NULL;
    json_decref(reply);
    return text;
}

#include "sphd_exec.h"

#include "sph_events.h"
#include "sph_study.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct sphd_exec {
    sph_case c;
    char *outdir;
    int finished;
};

sphd_exec *sphd_exec_new(const sph_case *c, const char *outdir, sph_error *err)
{
    sphd_exec *x = calloc(1, sizeof *x);
    if (!x) {
        sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory");
        return NULL;
    }
    x->c = *c;
    if (outdir && !(x->outdir = strdup(outdir))) {
        free(x);
        sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory");
        return NULL;
    }
    switch (c->method) {
    case SPH_METHOD_KERNEL_STUDY:
        if (sph_study_validate(&c->study, err)) {
            sphd_exec_free(x);
            return NULL;
        }
        break;
    default:
        sph_error_set(err, SPH_ERR_INVALID, "/method", "method '%s' is not available",
                      sph_method_name(c->method));
        sphd_exec_free(x);
        return NULL;
    }
    return x;
}

static sphd_exec_status advance_study(sphd_exec *x, sphd_emit_fn emit, void *ud, sph_error *err)
{
    sph_study_result *res = calloc(1, sizeof *res);
    if (!res) {
        sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory for the study's results");
        return SPHD_EXEC_FAILED;
    }
    if (sph_study_run(&x->c.study, res, err)) {
        free(res);
        return SPHD_EXEC_FAILED;
    }
    emit(ud, "result", sph_study_result_json(&x->c.study, res));
    free(res);
    x->finished = 1;
    return SPHD_EXEC_DONE;
}

sphd_exec_status sphd_exec_advance(sphd_exec *x, long max_steps, double until, sphd_emit_fn emit,
                                   void *ud, sph_error *err)
{
    (void)max_steps;
    (void)until;
    if (x->finished)
        return SPHD_EXEC_DONE;
    switch (x->c.method) {
    case SPH_METHOD_KERNEL_STUDY:
        return advance_study(x, emit, ud, err);
    default:
        sph_error_set(err, SPH_ERR_INTERNAL, "", "method not implemented");
        return SPHD_EXEC_FAILED;
    }
}

json_t *sphd_exec_progress(const sphd_exec *x)
{
    return json_pack("{s:I, s:b}", "step", (json_int_t)0, "finished", x->finished);
}

void sphd_exec_free(sphd_exec *x)
{
    if (!x)
        return;
    free(x->outdir);
    free(x);
}

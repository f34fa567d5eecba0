#include "sph_events.h"

#include <math.h>

json_t *sph_event_new(const char *job, long seq, const char *type)
{
    return json_pack("{s:s, s:I, s:s}", "job", job, "seq", (json_int_t)seq, "type", type);
}

json_t *sph_json_real_or_null(double x)
{
    return isfinite(x) ? json_real(x) : json_null();
}

static json_t *summary_json(const sph_error_summary *s)
{
    return json_pack("{s:o, s:o, s:o}", "max", sph_json_real_or_null(s->max), "rms",
                     sph_json_real_or_null(s->rms), "at", sph_json_real_or_null(s->at));
}

json_t *sph_study_result_json(const sph_study_config *cfg, const sph_study_result *res)
{
    json_t *kernels = json_array();
    for (int i = 0; i < res->nkernels; i++) {
        const sph_study_kernel_result *k = &res->kernels[i];
        json_t *fns = json_object();
        for (int f = 0; f < cfg->nfunctions; f++)
            json_object_set_new(fns, sph_function_name(cfg->functions[f]),
                                json_pack("{s:o, s:o}", "f", summary_json(&k->f[f]), "dfdx",
                                          summary_json(&k->dfdx[f])));
        json_t *kj = json_pack("{s:s, s:f, s:f, s:o, s:o, s:I, s:o}", "type",
                               sph_kernel_type_name(k->spec.type), "h", k->h, "support", k->support,
                               "normalisation", sph_json_real_or_null(k->normalisation),
                               "second_moment", sph_json_real_or_null(k->second_moment), "interior",
                               (json_int_t)k->interior, "functions", fns);
        if (k->spec.type == SPH_KERNEL_DOUBLE_COSINE)
            json_object_set_new(kj, "kappa", json_real(k->spec.kappa));
        if (k->spec.type == SPH_KERNEL_GAUSSIAN)
            json_object_set_new(kj, "radius", json_real(k->spec.radius));
        json_array_append_new(kernels, kj);
    }
    return json_pack("{s:s, s:I, s:f, s:f, s:f, s:o}", "method", "kernel_study", "particles",
                     (json_int_t)cfg->particles, "dx", res->dx, "h_over_dx", cfg->h_over_dx, "at",
                     cfg->at, "kernels", kernels);
}

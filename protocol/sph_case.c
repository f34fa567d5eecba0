#include "sph_case.h"
#include "sph_json.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

static const char *const method_names[] = {[SPH_METHOD_KERNEL_STUDY] = "kernel_study",
                                           [SPH_METHOD_WCSPH] = "wcsph",
                                           [SPH_METHOD_MPS] = "mps"};

const char *sph_method_name(sph_method m)
{
    if ((int)m < 0 || (size_t)m >= sizeof method_names / sizeof method_names[0])
        return "unknown";
    return method_names[m];
}

int sph_case_load(const char *file, json_t **root, sph_error *err)
{
    *root = NULL;
    FILE *f = fopen(file, "rb");
    if (!f)
        return sph_error_set(err, SPH_ERR_IO, "", "cannot open case file '%s': %s", file,
                             strerror(errno));
    json_error_t jerr;
    json_t *j = json_loadf(f, JSON_REJECT_DUPLICATES, &jerr);
    fclose(f);
    if (!j)
        return sph_error_set(err, SPH_ERR_INVALID, "", "%s:%d:%d: not valid JSON: %s", file,
                             jerr.line, jerr.column, jerr.text);
    if (!json_is_object(j)) {
        json_decref(j);
        return sph_error_set(err, SPH_ERR_INVALID, "", "%s: a case must be a JSON object", file);
    }
    *root = j;
    return 0;
}

/* A kernel object {"type": ..., "kappa": ..., "radius": ...} at path base. */
static int parse_kernel(const json_t *obj, const char *base, sph_kernel_spec *spec, sph_error *err)
{
    static const char *const keys[] = {"type", "kappa", "radius", NULL};
    if (!json_is_object(obj))
        return sph_error_set(err, SPH_ERR_INVALID, base,
                             "a kernel must be an object like {\"type\": \"wendland_c2\"}, not %s",
                             sph_json_type_name(obj));
    if (sph_json_check_keys(obj, base, keys, err))
        return SPH_ERR_INVALID;
    const char *type = NULL;
    if (sph_json_string(obj, base, "type", 1, &type, err))
        return SPH_ERR_INVALID;
    const int t = sph_kernel_type_from_name(type);
    if (t < 0) {
        char path[SPH_ERROR_PATH_MAX];
        snprintf(path, sizeof path, "%s/type", base);
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "unknown kernel type '%s' (known: cubic_spline, gaussian, "
                             "double_cosine, wendland_c2, renormalized_gaussian, koshizuka, "
                             "sheu_quartic)",
                             type);
    }
    *spec = sph_kernel_spec_default((sph_kernel_type)t);
    if (json_object_get(obj, "kappa") && t != SPH_KERNEL_DOUBLE_COSINE) {
        char path[SPH_ERROR_PATH_MAX];
        snprintf(path, sizeof path, "%s/kappa", base);
        return sph_error_set(err, SPH_ERR_INVALID, path, "'kappa' applies to double_cosine only");
    }
    if (json_object_get(obj, "radius") && t != SPH_KERNEL_GAUSSIAN) {
        char path[SPH_ERROR_PATH_MAX];
        snprintf(path, sizeof path, "%s/radius", base);
        return sph_error_set(err, SPH_ERR_INVALID, path, "'radius' applies to gaussian only");
    }
    if (sph_json_number(obj, base, "kappa", 0, SPH_KERNEL_KAPPA_MIN, SPH_KERNEL_KAPPA_MAX,
                        &spec->kappa, err) ||
        sph_json_number(obj, base, "radius", 0, SPH_KERNEL_GAUSS_RADIUS_MIN,
                        SPH_KERNEL_GAUSS_RADIUS_MAX, &spec->radius, err))
        return SPH_ERR_INVALID;
    return 0;
}

static int parse_study(const json_t *root, sph_study_config *c, sph_error *err)
{
    static const char *const keys[] = {"name",      "description", "method",    "dim",
                                       "domain",    "particles",   "h_over_dx", "kernels",
                                       "functions", "at",          NULL};
    if (sph_json_check_keys(root, "", keys, err))
        return SPH_ERR_INVALID;
    memset(c, 0, sizeof *c);
    long dim = 1;
    if (sph_json_integer(root, "", "dim", 0, 1, 1, &dim, err))
        return SPH_ERR_INVALID;

    json_t *domain;
    static const char *const dkeys[] = {"min", "max", NULL};
    if (sph_json_get(root, "", "domain", 1, &domain, err))
        return SPH_ERR_INVALID;
    if (!json_is_object(domain))
        return sph_error_set(err, SPH_ERR_INVALID, "/domain",
                             "'domain' must be an object {\"min\": [a], \"max\": [b]}");
    if (sph_json_check_keys(domain, "/domain", dkeys, err) ||
        sph_json_vector(domain, "/domain", "min", 1, 1, &c->xmin, err) ||
        sph_json_vector(domain, "/domain", "max", 1, 1, &c->xmax, err))
        return SPH_ERR_INVALID;
    if (!(c->xmax > c->xmin))
        return sph_error_set(err, SPH_ERR_INVALID, "/domain/max",
                             "domain max (%g) must be greater than min (%g)", c->xmax, c->xmin);

    if (sph_json_integer(root, "", "particles", 1, SPH_STUDY_MIN_PARTICLES, SPH_STUDY_MAX_PARTICLES,
                         &c->particles, err))
        return SPH_ERR_INVALID;
    c->h_over_dx = 1.2;
    if (sph_json_number(root, "", "h_over_dx", 0, 1e-3, SPH_STUDY_MAX_H_OVER_DX, &c->h_over_dx,
                        err))
        return SPH_ERR_INVALID;

    json_t *kernels;
    if (sph_json_get(root, "", "kernels", 1, &kernels, err))
        return SPH_ERR_INVALID;
    if (!json_is_array(kernels) || json_array_size(kernels) < 1 ||
        json_array_size(kernels) > SPH_STUDY_MAX_KERNELS)
        return sph_error_set(err, SPH_ERR_INVALID, "/kernels",
                             "'kernels' must be an array of 1 to %d kernel objects",
                             SPH_STUDY_MAX_KERNELS);
    size_t i;
    json_t *v;
    json_array_foreach(kernels, i, v)
    {
        char base[64];
        snprintf(base, sizeof base, "/kernels/%zu", i);
        if (parse_kernel(v, base, &c->kernels[i], err))
            return SPH_ERR_INVALID;
        if (c->kernels[i].type == SPH_KERNEL_KOSHIZUKA)
            return sph_error_set(err, SPH_ERR_INVALID, base,
                                 "koshizuka is singular at r = 0 and not normalisable in 1D: a "
                                 "kernel study needs a normalised kernel");
    }
    c->nkernels = (int)json_array_size(kernels);

    json_t *functions;
    if (sph_json_get(root, "", "functions", 0, &functions, err))
        return SPH_ERR_INVALID;
    if (!functions) {
        c->functions[0] = SPH_FN_EXP;
        c->functions[1] = SPH_FN_SIN;
        c->nfunctions = 2;
    } else {
        if (!json_is_array(functions) || json_array_size(functions) < 1 ||
            json_array_size(functions) > SPH_FN_COUNT)
            return sph_error_set(err, SPH_ERR_INVALID, "/functions",
                                 "'functions' must be an array of 1 to %d names from exp, sin, "
                                 "cos, poly2",
                                 SPH_FN_COUNT);
        json_array_foreach(functions, i, v)
        {
            char path[64];
            snprintf(path, sizeof path, "/functions/%zu", i);
            const int fn = json_is_string(v) ? sph_function_from_name(json_string_value(v)) : -1;
            if (fn < 0)
                return sph_error_set(err, SPH_ERR_INVALID, path,
                                     "unknown function (known: exp, sin, cos, poly2)");
            for (size_t j = 0; j < i; j++)
                if ((int)c->functions[j] == fn)
                    return sph_error_set(err, SPH_ERR_INVALID, path, "function '%s' listed twice",
                                         json_string_value(v));
            c->functions[i] = (sph_function)fn;
        }
        c->nfunctions = (int)json_array_size(functions);
    }

    c->at = 0.5 * (c->xmin + c->xmax);
    if (sph_json_number(root, "", "at", 0, c->xmin, c->xmax, &c->at, err))
        return SPH_ERR_INVALID;
    return sph_study_validate(c, err);
}

int sph_case_from_json(const json_t *root, sph_case *out, sph_error *err)
{
    memset(out, 0, sizeof *out);
    if (!json_is_object(root))
        return sph_error_set(err, SPH_ERR_INVALID, "", "a case must be a JSON object");
    const char *name = "case", *method = NULL;
    if (sph_json_string(root, "", "name", 0, &name, err) ||
        sph_json_string(root, "", "method", 1, &method, err))
        return SPH_ERR_INVALID;
    if (strlen(name) == 0 || strlen(name) >= SPH_CASE_NAME_MAX)
        return sph_error_set(err, SPH_ERR_INVALID, "/name", "'name' must have 1 to %d characters",
                             SPH_CASE_NAME_MAX - 1);
    snprintf(out->name, sizeof out->name, "%s", name);
    if (strcmp(method, "kernel_study") == 0) {
        out->method = SPH_METHOD_KERNEL_STUDY;
        return parse_study(root, &out->study, err);
    }
    if (strcmp(method, "wcsph") == 0 || strcmp(method, "mps") == 0)
        return sph_error_set(err, SPH_ERR_INVALID, "/method",
                             "method '%s' is not available in this version of sphd yet", method);
    return sph_error_set(err, SPH_ERR_INVALID, "/method",
                         "unknown method '%s' (known: kernel_study, wcsph, mps)", method);
}

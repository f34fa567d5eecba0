#include "sph_case.h"
#include "sph_geometry.h"
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
static int parse_kernel_keys(const json_t *obj, const char *base, const char *const *keys,
                             sph_kernel_spec *spec, sph_error *err)
{
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

static int parse_kernel(const json_t *obj, const char *base, sph_kernel_spec *spec, sph_error *err)
{
    static const char *const keys[] = {"type", "kappa", "radius", NULL};
    return parse_kernel_keys(obj, base, keys, spec, err);
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

/* An object member at base/key (required or optional); *out NULL when absent. */
static int get_object(const json_t *obj, const char *base, const char *key, int required,
                      json_t **out, char *path, size_t pathsize, sph_error *err)
{
    if (sph_json_get(obj, base, key, required, out, err))
        return SPH_ERR_INVALID;
    int n = snprintf(path, pathsize, "%s/%s", base, key);
    if (n < 0 || (size_t)n >= pathsize)
        return sph_error_set(err, SPH_ERR_INVALID, base, "the path of '%s' is too long", key);
    if (*out && !json_is_object(*out))
        return sph_error_set(err, SPH_ERR_INVALID, path, "'%s' must be an object, not %s", key,
                             sph_json_type_name(*out));
    return 0;
}

/* {"min": [x, y], "max": [x, y]} with max > min. */
static int parse_box(const json_t *obj, const char *base, sph_box *b, sph_error *err)
{
    static const char *const keys[] = {"min", "max", NULL};
    if (!json_is_object(obj))
        return sph_error_set(err, SPH_ERR_INVALID, base,
                             "a box must be an object {\"min\": [x, y], \"max\": [x, y]}");
    memset(b, 0, sizeof *b);
    if (sph_json_check_keys(obj, base, keys, err) ||
        sph_json_vector(obj, base, "min", 1, 2, b->min, err) ||
        sph_json_vector(obj, base, "max", 1, 2, b->max, err))
        return SPH_ERR_INVALID;
    for (int d = 0; d < 2; d++)
        if (!(b->max[d] > b->min[d])) {
            char path[SPH_ERROR_PATH_MAX];
            snprintf(path, sizeof path, "%s/max/%d", base, d);
            return sph_error_set(err, SPH_ERR_INVALID, path,
                                 "max (%g) must be greater than min (%g)", b->max[d], b->min[d]);
        }
    return 0;
}

static int parse_physics(const json_t *root, sph_config *c, sph_error *err)
{
    static const char *const keys[] = {"rho0",       "gravity",   "eos", "viscosity",
                                       "turbulence", "delta_sph", NULL};
    static const char *const eos_keys[] = {"type", "c0", NULL};
    static const char *const visc_keys[] = {"type", "alpha", "nu", NULL};
    char path[SPH_ERROR_PATH_MAX], sub[SPH_ERROR_PATH_MAX];
    json_t *ph, *o;
    if (get_object(root, "", "physics", 1, &ph, path, sizeof path, err) ||
        sph_json_check_keys(ph, path, keys, err) ||
        sph_json_number(ph, path, "rho0", 0, 1e-3, 1e6, &c->rho0, err) ||
        sph_json_vector(ph, path, "gravity", 0, 2, c->gravity, err) ||
        sph_json_number(ph, path, "delta_sph", 0, 0.0, 1.0, &c->delta_sph, err))
        return SPH_ERR_INVALID;
    for (int d = 0; d < 2; d++)
        if (fabs(c->gravity[d]) > 1e3)
            return sph_error_set(err, SPH_ERR_INVALID, "/physics/gravity",
                                 "gravity components must be within +-1000 m/s^2");

    const char *type = NULL;
    if (get_object(ph, path, "eos", 1, &o, sub, sizeof sub, err) ||
        sph_json_check_keys(o, sub, eos_keys, err) ||
        sph_json_string(o, sub, "type", 1, &type, err) ||
        sph_json_number(o, sub, "c0", 1, 1e-3, 1e5, &c->c0, err))
        return SPH_ERR_INVALID;
    if (strcmp(type, "linear") == 0)
        c->eos = SPH_EOS_LINEAR;
    else if (strcmp(type, "tait") == 0)
        c->eos = SPH_EOS_TAIT;
    else
        return sph_error_set(err, SPH_ERR_INVALID, "/physics/eos/type",
                             "unknown eos '%s' (known: linear, tait)", type);

    if (get_object(ph, path, "viscosity", 0, &o, sub, sizeof sub, err))
        return SPH_ERR_INVALID;
    if (o) {
        if (sph_json_check_keys(o, sub, visc_keys, err) ||
            sph_json_string(o, sub, "type", 1, &type, err))
            return SPH_ERR_INVALID;
        if (strcmp(type, "artificial") == 0) {
            c->visc = SPH_VISC_ARTIFICIAL;
            if (json_object_get(o, "nu"))
                return sph_error_set(err, SPH_ERR_INVALID, "/physics/viscosity/nu",
                                     "'nu' applies to laminar viscosity only");
            if (sph_json_number(o, sub, "alpha", 0, 0.0, 10.0, &c->alpha, err))
                return SPH_ERR_INVALID;
        } else if (strcmp(type, "laminar") == 0) {
            c->visc = SPH_VISC_LAMINAR;
            if (json_object_get(o, "alpha"))
                return sph_error_set(err, SPH_ERR_INVALID, "/physics/viscosity/alpha",
                                     "'alpha' applies to artificial viscosity only");
            if (sph_json_number(o, sub, "nu", 1, 0.0, 1e3, &c->nu, err))
                return SPH_ERR_INVALID;
        } else {
            return sph_error_set(err, SPH_ERR_INVALID, "/physics/viscosity/type",
                                 "unknown viscosity '%s' (known: artificial, laminar)", type);
        }
    }
    const char *turb = "none";
    if (sph_json_string(ph, path, "turbulence", 0, &turb, err))
        return SPH_ERR_INVALID;
    if (strcmp(turb, "none") == 0)
        c->turb = SPH_TURB_NONE;
    else if (strcmp(turb, "sps") == 0)
        c->turb = SPH_TURB_SPS;
    else
        return sph_error_set(err, SPH_ERR_INVALID, "/physics/turbulence",
                             "unknown turbulence model '%s' (known: none, sps)", turb);
    return 0;
}

/* Names in an array of strings, each from `known` (NULL-terminated); returns a bit per name. */
static int parse_names(const json_t *obj, const char *base, const char *key,
                       const char *const *known, unsigned *mask, sph_error *err)
{
    json_t *a;
    if (sph_json_get(obj, base, key, 0, &a, err))
        return SPH_ERR_INVALID;
    if (!a)
        return 0;
    char path[SPH_ERROR_PATH_MAX];
    snprintf(path, sizeof path, "%s/%s", base, key);
    if (!json_is_array(a))
        return sph_error_set(err, SPH_ERR_INVALID, path, "'%s' must be an array of names", key);
    *mask = 0;
    size_t i;
    json_t *v;
    json_array_foreach(a, i, v)
    {
        int k = -1;
        for (int j = 0; json_is_string(v) && known[j]; j++)
            if (strcmp(json_string_value(v), known[j]) == 0)
                k = j;
        if (k < 0) {
            char ipath[SPH_ERROR_PATH_MAX + 32];
            snprintf(ipath, sizeof ipath, "%s/%zu", path, i);
            return sph_error_set(err, SPH_ERR_INVALID, ipath,
                                 "unknown name in '%s' (known: %s%s%s%s%s)", key, known[0],
                                 known[1] ? ", " : "", known[1] ? known[1] : "",
                                 known[1] && known[2] ? ", ..." : "", "");
        }
        *mask |= 1u << k;
    }
    return 0;
}

static int parse_sim(const json_t *root, sph_config *c, sph_output_config *out, sph_error *err)
{
    static const char *const keys[] = {"name", "description", "method",      "dim",      "kernel",
                                       "dx",   "domain",      "fluid",       "boundary", "physics",
                                       "time", "output",      "diagnostics", NULL};
    static const char *const kernel_keys[] = {"type", "kappa", "radius", "h_over_dx", NULL};
    static const char *const boundary_keys[] = {"type", "layers", "tank", NULL};
    static const char *const time_keys[] = {"end", "cfl", "dt", NULL};
    static const char *const output_keys[] = {"every", "fields", "compress", NULL};
    static const char *const diag_keys[] = {"every", "probes", NULL};
    /* probe names: bit k of the mask is known[k]; the first two are SPH_PROBE_* */
    static const char *const probes[] = {"front_x", "height_left", "ekin", "epot", "vmax", NULL};
    /* bit k is known[k]: the SPH_FIELD_* of sph_case.h */
    static const char *const fields[] = {"pos", "vel", "rho", "p", "type", "id", "mass", NULL};
    char path[SPH_ERROR_PATH_MAX];
    json_t *o;

    if (sph_json_check_keys(root, "", keys, err))
        return SPH_ERR_INVALID;
    *c = sph_config_default();
    long dim = 2;
    if (sph_json_integer(root, "", "dim", 0, 1, 3, &dim, err))
        return SPH_ERR_INVALID;
    if (dim != 2)
        return sph_error_set(err, SPH_ERR_INVALID, "/dim",
                             "wcsph is available in 2D only in this version (dim = 2)");

    if (get_object(root, "", "kernel", 0, &o, path, sizeof path, err))
        return SPH_ERR_INVALID;
    if (o) {
        if (parse_kernel_keys(o, path, kernel_keys, &c->kernel, err) ||
            sph_json_number(o, path, "h_over_dx", 0, 0.5, 4.0, &c->h_over_dx, err))
            return SPH_ERR_INVALID;
        if (sph_kernel_is_mps(c->kernel.type))
            return sph_error_set(err, SPH_ERR_INVALID, "/kernel/type",
                                 "'%s' is an MPS weight function, not a WCSPH kernel",
                                 sph_kernel_type_name(c->kernel.type));
    }
    if (sph_json_number(root, "", "dx", 1, -INFINITY, 1e3, &c->dx, err))
        return SPH_ERR_INVALID;
    if (!(c->dx > 0.0))
        return sph_error_set(err, SPH_ERR_INVALID, "/dx", "'dx' must be positive, got %g", c->dx);

    json_t *dom;
    if (sph_json_get(root, "", "domain", 1, &dom, err) ||
        parse_box(dom, "/domain", &c->domain, err))
        return SPH_ERR_INVALID;

    json_t *fluid;
    if (sph_json_get(root, "", "fluid", 1, &fluid, err))
        return SPH_ERR_INVALID;
    if (!json_is_array(fluid) || json_array_size(fluid) < 1 ||
        json_array_size(fluid) > SPH_CONFIG_MAX_BOXES)
        return sph_error_set(err, SPH_ERR_INVALID, "/fluid",
                             "'fluid' must be an array of 1 to %d objects {\"box\": {...}}",
                             SPH_CONFIG_MAX_BOXES);
    size_t i;
    json_t *v;
    json_array_foreach(fluid, i, v)
    {
        static const char *const fkeys[] = {"box", NULL};
        char base[64], bpath[80];
        snprintf(base, sizeof base, "/fluid/%zu", i);
        snprintf(bpath, sizeof bpath, "%s/box", base);
        json_t *box;
        if (!json_is_object(v))
            return sph_error_set(err, SPH_ERR_INVALID, base,
                                 "a fluid block must be an object {\"box\": {...}}");
        if (sph_json_check_keys(v, base, fkeys, err) ||
            sph_json_get(v, base, "box", 1, &box, err) || parse_box(box, bpath, &c->fluid[i], err))
            return SPH_ERR_INVALID;
        for (int d = 0; d < 2; d++) {
            if (c->fluid[i].min[d] < c->domain.min[d]) {
                snprintf(path, sizeof path, "%s/min/%d", bpath, d);
                return sph_error_set(err, SPH_ERR_INVALID, path, "the fluid is outside the domain");
            }
            if (c->fluid[i].max[d] > c->domain.max[d]) {
                snprintf(path, sizeof path, "%s/max/%d", bpath, d);
                return sph_error_set(err, SPH_ERR_INVALID, path, "the fluid is outside the domain");
            }
        }
        if (sph_geometry_box_count(&c->fluid[i], 2, c->dx) == 0)
            return sph_error_set(err, SPH_ERR_INVALID, bpath,
                                 "the box holds no particles at dx = %g m (it is thinner than dx)",
                                 c->dx);
    }
    c->nfluid = (int)json_array_size(fluid);

    c->boundary = SPH_BOUNDARY_NONE;
    if (get_object(root, "", "boundary", 0, &o, path, sizeof path, err))
        return SPH_ERR_INVALID;
    if (o) {
        const char *type = NULL;
        long layers = 3;
        if (sph_json_check_keys(o, path, boundary_keys, err) ||
            sph_json_string(o, path, "type", 1, &type, err) ||
            sph_json_integer(o, path, "layers", 0, 1, 8, &layers, err))
            return SPH_ERR_INVALID;
        if (strcmp(type, "dynamic") == 0)
            c->boundary = SPH_BOUNDARY_DYNAMIC;
        else if (strcmp(type, "none") != 0)
            return sph_error_set(err, SPH_ERR_INVALID, "/boundary/type",
                                 "unknown boundary '%s' (known: dynamic, none)", type);
        c->layers = (int)layers;
        json_t *tank;
        if (sph_json_get(o, path, "tank", 0, &tank, err) ||
            (tank && parse_box(tank, "/boundary/tank", &c->tank, err)))
            return SPH_ERR_INVALID;
        c->has_tank = tank != NULL;
    }

    if (parse_physics(root, c, err))
        return SPH_ERR_INVALID;

    if (get_object(root, "", "time", 1, &o, path, sizeof path, err) ||
        sph_json_check_keys(o, path, time_keys, err) ||
        sph_json_number(o, path, "end", 1, 1e-9, 1e6, &c->t_end, err) ||
        sph_json_number(o, path, "cfl", 0, 1e-3, 1.0, &c->cfl, err) ||
        sph_json_number(o, path, "dt", 0, 1e-12, 1.0, &c->dt_fixed, err))
        return SPH_ERR_INVALID;

    unsigned mask = 0;
    if (get_object(root, "", "output", 0, &o, path, sizeof path, err))
        return SPH_ERR_INVALID;
    out->every = 0.0;
    out->fields = SPH_FIELD_POS | SPH_FIELD_VEL | SPH_FIELD_RHO | SPH_FIELD_P | SPH_FIELD_TYPE;
    out->compress = 0;
    if (o) {
        long compress = 0;
        if (sph_json_check_keys(o, path, output_keys, err) ||
            sph_json_number(o, path, "every", 1, 1e-9, 1e6, &out->every, err) ||
            parse_names(o, path, "fields", fields, &out->fields, err) ||
            sph_json_integer(o, path, "compress", 0, 0, 9, &compress, err))
            return SPH_ERR_INVALID;
        out->fields |= SPH_FIELD_POS;
        out->compress = (int)compress;
    }
    if (get_object(root, "", "diagnostics", 0, &o, path, sizeof path, err))
        return SPH_ERR_INVALID;
    if (o) {
        mask = SPH_PROBE_FRONT_X | SPH_PROBE_HEIGHT_LEFT;
        if (sph_json_check_keys(o, path, diag_keys, err) ||
            sph_json_integer(o, path, "every", 0, 1, 1000000000L, &c->diag_every, err) ||
            parse_names(o, path, "probes", probes, &mask, err))
            return SPH_ERR_INVALID;
        c->probes = mask & (SPH_PROBE_FRONT_X | SPH_PROBE_HEIGHT_LEFT);
    }
    return 0;
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
    if (strcmp(method, "wcsph") == 0) {
        out->method = SPH_METHOD_WCSPH;
        return parse_sim(root, &out->sim, &out->output, err);
    }
    if (strcmp(method, "mps") == 0)
        return sph_error_set(err, SPH_ERR_INVALID, "/method",
                             "method '%s' is not available in this version of sphd yet", method);
    return sph_error_set(err, SPH_ERR_INVALID, "/method",
                         "unknown method '%s' (known: kernel_study, wcsph, mps)", method);
}

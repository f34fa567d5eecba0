#include "sph_case.h"
#include "sph_case_table.h"
#include "sph_fileio.h"
#include "sph_fill.h"
#include "sph_inputs.h"
#include "sph_mesh_io.h"
#include "sph_sim.h"
#include "sph_wavemaker.h"
#include "sph_json.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const method_names[] = {[SPH_METHOD_KERNEL_STUDY] = "kernel_study",
                                           [SPH_METHOD_WCSPH] = "wcsph",
                                           [SPH_METHOD_MPS] = "mps"};

int sph_case_is_sim(const sph_case *c)
{
    return c->method != SPH_METHOD_KERNEL_STUDY;
}

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

/* The parent path of a JSON pointer ("/a/b" -> "/a", "/a" -> ""), into buf. */
static const char *parent_of(const char *path, char *buf, size_t n)
{
    const char *slash = strrchr(path, '/');
    const size_t len = slash ? (size_t)(slash - path) : 0;
    snprintf(buf, n, "%.*s", (int)len, path);
    return buf;
}

static const char *key_of(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

/* The value at a JSON pointer of the table (plain keys, no escapes; array elements by index),
 * or NULL. */
static const json_t *lookup(const json_t *root, const char *path)
{
    const json_t *v = root;
    char key[64];
    while (v && *path == '/') {
        const char *end = strchr(path + 1, '/');
        const size_t len = end ? (size_t)(end - path - 1) : strlen(path + 1);
        if (len >= sizeof key)
            return NULL;
        memcpy(key, path + 1, len);
        key[len] = '\0';
        if (json_is_array(v) && len > 0 && strspn(key, "0123456789") == len)
            v = json_array_get(v, strtoul(key, NULL, 10));
        else if (json_is_object(v))
            v = json_object_get(v, key);
        else
            return NULL;
        path += len + 1;
    }
    return v;
}

/* Whether a path of the table (an element row's has a "*" segment) names the concrete path. */
static int path_matches(const char *pattern, const char *path)
{
    while (*pattern && *path) {
        if (pattern[0] == '*' && (pattern[1] == '/' || pattern[1] == '\0')) {
            const size_t digits = strspn(path, "0123456789");
            if (digits == 0 || (path[digits] != '/' && path[digits] != '\0'))
                return 0;
            pattern++;
            path += digits;
            continue;
        }
        if (*pattern++ != *path++)
            return 0;
    }
    return *pattern == *path;
}

static const sph_case_field *row_of(const char *path)
{
    for (const sph_case_field *f = sph_case_fields; f->path; f++)
        if (path_matches(f->path, path))
            return f;
    return NULL;
}

/* An element row's path with its "*" replaced by index i, into buf. */
static const char *element_path(const char *pattern, size_t i, char *buf, size_t n)
{
    const char *star = strstr(pattern, "/*");
    if (!star) {
        snprintf(buf, n, "%s", pattern);
        return buf;
    }
    snprintf(buf, n, "%.*s/%zu%s", (int)(star - pattern), pattern, i, star + 2);
    return buf;
}

static void *dest(const sph_case_field *f, sph_config *c, sph_output_config *o)
{
    return (f->dst == SPH_CF_OUT ? (char *)o : (char *)c) + f->off;
}

/* The name an enum row holds in this case at path: given, or its default. */
static const char *enum_name(const json_t *root, const sph_case_field *f, const char *path)
{
    const json_t *v = lookup(root, path);
    if (json_is_string(v))
        return json_string_value(v);
    return f->has_def ? f->names[(int)f->def] : "";
}

/* Whether a row's `when` holds ("/path=a|b"); *what gets "type of /path is a or b". */
static int when_holds(const json_t *root, const sph_case_field *f, char *what, size_t n)
{
    if (!f->when)
        return 1;
    const char *eq = strchr(f->when, '=');
    char path[SPH_ERROR_PATH_MAX];
    snprintf(path, sizeof path, "%.*s", (int)(eq - f->when), f->when);
    const sph_case_field *ref = row_of(path);
    char num[32];
    const char *name = "";
    if (ref && ref->type == SPH_CF_INTEGER) { /* an integer row: its value, given or default */
        const json_t *v = lookup(root, path);
        snprintf(num, sizeof num, "%lld",
                 json_is_integer(v) ? (long long)json_integer_value(v) : (long long)ref->def);
        name = num;
    } else if (ref) {
        name = enum_name(root, ref, path);
    }
    snprintf(what, n, "'%s' applies only when %s is %s", key_of(f->path), path + 1, eq + 1);
    for (char *p = what; *p; p++)
        if (*p == '|')
            *p = '/';
    for (const char *a = eq + 1; *a;) {
        const char *bar = strchr(a, '|');
        const size_t len = bar ? (size_t)(bar - a) : strlen(a);
        if (strlen(name) == len && strncmp(a, name, len) == 0)
            return 1;
        a += len + (bar ? 1 : 0);
    }
    return 0;
}

/* Fields of the object at path that this method does not know. */
static int check_object_keys(const json_t *obj, const char *path, sph_method m, sph_error *err)
{
    const char *key;
    json_t *v;
    char parent[SPH_ERROR_PATH_MAX], fpath[SPH_ERROR_PATH_MAX];
    json_object_foreach((json_t *)obj, key, v)
    {
        snprintf(fpath, sizeof fpath, "%s/%s", path, key);
        const sph_case_field *f = row_of(fpath);
        if (f && (f->methods & SPH_CF_M(m)))
            continue;
        if (f) {
            char list[96] = "";
            for (int k = 0; k < SPH_METHOD_COUNT; k++)
                if (f->methods & SPH_CF_M(k))
                    snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s",
                             list[0] ? ", " : "", sph_method_name((sph_method)k));
            return sph_error_set(err, SPH_ERR_INVALID, fpath, "'%s' applies to method %s, not %s",
                                 key, list, sph_method_name(m));
        }
        char allowed[240] = "";
        for (const sph_case_field *g = sph_case_fields; g->path; g++)
            if ((g->methods & SPH_CF_M(m)) &&
                path_matches(parent_of(g->path, parent, sizeof parent), path) &&
                strlen(allowed) + strlen(key_of(g->path)) + 8 < sizeof allowed)
                snprintf(allowed + strlen(allowed), sizeof allowed - strlen(allowed), "%s%s",
                         allowed[0] ? ", " : "", key_of(g->path));
        return sph_error_set(err, SPH_ERR_INVALID, fpath, "unknown field '%s' (allowed: %s)", key,
                             allowed);
    }
    return 0;
}

/* The names of a NULL-terminated list, comma-separated into buf (cut short when it is full). */
static void names_list(const char *const *names, char *buf, size_t size)
{
    buf[0] = '\0';
    for (int j = 0; names[j] && strlen(buf) < size - 40; j++)
        snprintf(buf + strlen(buf), size - strlen(buf), "%s%s", j ? ", " : "", names[j]);
}

/* An array of names into a mask. */
static int parse_names(const json_t *a, const sph_case_field *f, unsigned *mask, sph_error *err)
{
    if (!json_is_array(a))
        return sph_error_set(err, SPH_ERR_INVALID, f->path, "'%s' must be an array of names",
                             key_of(f->path));
    *mask = 0;
    size_t i;
    json_t *v;
    json_array_foreach(a, i, v)
    {
        int k = -1;
        for (int j = 0; json_is_string(v) && f->names[j]; j++)
            if (strcmp(json_string_value(v), f->names[j]) == 0)
                k = j;
        if (k < 0) {
            char ipath[SPH_ERROR_PATH_MAX + 32], list[200];
            names_list(f->names, list, sizeof list);
            snprintf(ipath, sizeof ipath, "%s/%zu", f->path, i);
            return sph_error_set(err, SPH_ERR_INVALID, ipath, "unknown name in '%s' (known: %s)",
                                 key_of(f->path), list);
        }
        *mask |= f->values ? (unsigned)f->values[k] : 1u << k;
    }
    return 0;
}

int sph_case_parse_box(const json_t *obj, const char *base, int dim, sph_box *b, sph_error *err)
{
    static const char *const keys[] = {"min", "max", NULL};
    if (!json_is_object(obj))
        return sph_error_set(err, SPH_ERR_INVALID, base,
                             "a box must be an object {\"min\": [x, y], \"max\": [x, y]}");
    memset(b, 0, sizeof *b);
    if (sph_json_check_keys(obj, base, keys, err) ||
        sph_json_vector(obj, base, "min", 1, dim, b->min, err) ||
        sph_json_vector(obj, base, "max", 1, dim, b->max, err))
        return SPH_ERR_INVALID;
    for (int d = 0; d < dim; d++)
        if (!(b->max[d] > b->min[d])) {
            char path[SPH_ERROR_PATH_MAX];
            snprintf(path, sizeof path, "%s/max/%d", base, d);
            return sph_error_set(err, SPH_ERR_INVALID, path,
                                 "max (%g) must be greater than min (%g)", b->max[d], b->min[d]);
        }
    return 0;
}

static int parse_array(const json_t *root, const sph_case_field *f, const json_t *v, sph_method m,
                       sph_config *c, sph_output_config *o, sph_error *err);

/* One row, present (v) or not, whose parent object is present or not. */
static int parse_row(const json_t *root, const sph_case_field *f, const json_t *v,
                     int parent_present, sph_method m, sph_config *c, sph_output_config *o,
                     sph_error *err)
{
    char what[SPH_ERROR_PATH_MAX + 64], parent[SPH_ERROR_PATH_MAX];
    if (!when_holds(root, f, what, sizeof what)) {
        if (v)
            return sph_error_set(err, SPH_ERR_INVALID, f->path, "%s", what);
        return 0;
    }
    void *dst = dest(f, c, o);
    if (!v) {
        if ((f->required & SPH_CF_M(m)) && parent_present)
            return sph_error_set(err, SPH_ERR_INVALID, f->path, "missing required field '%s'",
                                 key_of(f->path));
        if (f->type == SPH_CF_NAMES)
            *(unsigned *)dst = f->def_mask;
        else if (f->has_def && f->type == SPH_CF_NUMBER)
            *(double *)dst = f->def;
        else if (f->has_def && f->type == SPH_CF_INTEGER && f->size == sizeof(long))
            *(long *)dst = (long)f->def;
        else if (f->has_def && (f->type == SPH_CF_INTEGER || f->type == SPH_CF_ENUM))
            *(int *)dst = f->values ? f->values[(int)f->def] : (int)f->def;
        return 0;
    }
    const json_t *obj = lookup(root, parent_of(f->path, parent, sizeof parent));
    const char *key = key_of(f->path);
    double num;
    long lval;
    const char *str;
    switch (f->type) {
    case SPH_CF_OBJECT:
        if (!json_is_object(v))
            return sph_error_set(err, SPH_ERR_INVALID, f->path, "'%s' must be an object, not %s",
                                 key, sph_json_type_name(v));
        return check_object_keys(v, f->path, m, err);
    case SPH_CF_TEXT:
        return sph_json_string(obj, parent, key, 0, &str, err);
    case SPH_CF_NUMBER:
        /* the type here, the range below: one message that says which ends are open */
        if (sph_json_number(obj, parent, key, 1, -INFINITY, INFINITY, &num, err))
            return SPH_ERR_INVALID;
        if (!((f->lo_open ? num > f->lo : num >= f->lo) &&
              (f->hi_open ? num < f->hi : num <= f->hi)))
            return sph_error_set(err, SPH_ERR_INVALID, f->path,
                                 "'%s' must be in %c%g, %g%c, got %g", key, f->lo_open ? '(' : '[',
                                 f->lo, f->hi, f->hi_open ? ')' : ']', num);
        *(double *)dst = num;
        return 0;
    case SPH_CF_INTEGER:
        if (sph_json_integer(obj, parent, key, 1, (long)f->lo, (long)f->hi, &lval, err))
            return SPH_ERR_INVALID;
        if (f->size == sizeof(long))
            *(long *)dst = lval;
        else
            *(int *)dst = (int)lval;
        return 0;
    case SPH_CF_ENUM:
        if (sph_json_string(obj, parent, key, 1, &str, err))
            return SPH_ERR_INVALID;
        for (int k = 0; f->names[k]; k++)
            if (strcmp(str, f->names[k]) == 0) {
                *(int *)dst = f->values ? f->values[k] : k;
                return 0;
            }
        {
            char list[200];
            names_list(f->names, list, sizeof list);
            return sph_error_set(err, SPH_ERR_INVALID, f->path, "unknown %s '%s' (known: %s)", key,
                                 str, list);
        }
    case SPH_CF_VECTOR: {
        double *vec = dst;
        if (sph_json_vector(obj, parent, key, 1, c->dim, vec, err))
            return SPH_ERR_INVALID;
        for (int d = 0; d < c->dim; d++)
            if (!(vec[d] >= f->lo && vec[d] <= f->hi))
                return sph_error_set(err, SPH_ERR_INVALID, f->path,
                                     "'%s' components must be in [%g, %g]", key, f->lo, f->hi);
        return 0;
    }
    case SPH_CF_BOX:
        return sph_case_parse_box(v, f->path, c->dim, dst, err);
    case SPH_CF_NAMES:
        return parse_names(v, f, dst, err);
    case SPH_CF_CUSTOM:
        return f->parse(v, f->path, c, o, err);
    case SPH_CF_STRING:
        if (sph_json_string(obj, parent, key, 1, &str, err))
            return SPH_ERR_INVALID;
        if (strlen(str) < 1 || strlen(str) >= f->size)
            return sph_error_set(err, SPH_ERR_INVALID, f->path,
                                 "'%s' must have 1 to %zu characters", key, f->size - 1);
        snprintf(dst, f->size, "%s", str);
        return 0;
    case SPH_CF_ARRAY:
        return parse_array(root, f, v, m, c, o, err);
    }
    return 0;
}

/* An array row: lo..hi objects, each element's rows read with its index in their paths. */
static int parse_array(const json_t *root, const sph_case_field *f, const json_t *v, sph_method m,
                       sph_config *c, sph_output_config *o, sph_error *err)
{
    const char *key = key_of(f->path);
    if (!json_is_array(v) || json_array_size(v) < (size_t)f->lo ||
        json_array_size(v) > (size_t)f->hi)
        return sph_error_set(err, SPH_ERR_INVALID, f->path,
                             "'%s' must be an array of %g to %g objects", key, f->lo, f->hi);
    char pattern[SPH_ERROR_PATH_MAX], base[SPH_ERROR_PATH_MAX], path[SPH_ERROR_PATH_MAX];
    char when[SPH_ERROR_PATH_MAX + 64];
    snprintf(pattern, sizeof pattern, "%s/*/", f->path);
    for (size_t i = 0; i < json_array_size(v); i++) {
        const json_t *e = json_array_get(v, i);
        snprintf(base, sizeof base, "%s/%zu", f->path, i);
        if (!json_is_object(e))
            return sph_error_set(err, SPH_ERR_INVALID, base, "an element of '%s' must be an object",
                                 key);
        if (check_object_keys(e, base, m, err))
            return SPH_ERR_INVALID;
        for (const sph_case_field *g = sph_case_fields; g->path; g++) {
            if (!(g->methods & SPH_CF_M(m)) || strncmp(g->path, pattern, strlen(pattern)) != 0)
                continue;
            sph_case_field row = *g; /* the element's own copy: its path, condition, place */
            row.path = element_path(g->path, i, path, sizeof path);
            if (g->when)
                row.when = element_path(g->when, i, when, sizeof when);
            row.dst = f->dst;
            row.off = f->off + i * f->stride + g->off;
            if (parse_row(root, &row, lookup(root, row.path), 1, m, c, o, err))
                return SPH_ERR_INVALID;
        }
    }
    *(int *)((f->dst == SPH_CF_OUT ? (char *)o : (char *)c) + f->count_off) =
        (int)json_array_size(v);
    return 0;
}

int sph_case_parse_sim(const json_t *root, sph_method m, sph_config *c, sph_output_config *o,
                       sph_error *err)
{
    *c = sph_config_default();
    c->method = m;
    memset(o, 0, sizeof *o);
    if (check_object_keys(root, "", m, err))
        return SPH_ERR_INVALID;
    char parent[SPH_ERROR_PATH_MAX];
    for (const sph_case_field *f = sph_case_fields; f->path; f++) {
        if (!(f->methods & SPH_CF_M(m)) || strstr(f->path, "/*"))
            continue; /* element rows are read by their array's row */
        const json_t *up = lookup(root, parent_of(f->path, parent, sizeof parent));
        if (parse_row(root, f, lookup(root, f->path), up != NULL, m, c, o, err))
            return SPH_ERR_INVALID;
        if (strcmp(f->path, "/dim") == 0 && c->dim != 2 && m != SPH_METHOD_WCSPH)
            return sph_error_set(err, SPH_ERR_INVALID, "/dim",
                                 "%s is available in 2D only in this version (dim = 2; 3D cases "
                                 "take \"method\": \"wcsph\")",
                                 sph_method_name(m));
    }
    o->fields |= SPH_FIELD_POS;
    return sph_sim_check(c, err);
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
    for (int m = 0; m < SPH_METHOD_COUNT; m++)
        if (m != SPH_METHOD_KERNEL_STUDY && strcmp(method, sph_method_name((sph_method)m)) == 0) {
            if (!sph_sim_has_method((sph_method)m))
                return sph_error_set(err, SPH_ERR_INVALID, "/method",
                                     "method '%s' is not available in this version of sphd yet",
                                     method);
            out->method = (sph_method)m;
            const int rc = sph_case_parse_sim(root, out->method, &out->sim, &out->output, err);
            /* the polygons the geometry list made are the case's to free */
            for (int k = 0; k < out->sim.ngeometry; k++)
                if (out->sim.geometry[k].kind == SPH_GEOM_POLYGON)
                    out->meshes[k] = (sph_mesh *)out->sim.geometry[k].mesh;
            if (rc)
                sph_case_clear(out);
            return rc;
        }
    return sph_error_set(err, SPH_ERR_INVALID, "/method",
                         "unknown method '%s' (known: kernel_study, wcsph, mps)", method);
}

json_t *sph_case_field_names(const char *path)
{
    for (const sph_case_field *f = sph_case_fields; f->path; f++)
        if (f->names && strcmp(f->path, path) == 0) {
            json_t *a = json_array();
            for (int k = 0; a && f->names[k]; k++)
                json_array_append_new(a, json_string(f->names[k]));
            return a;
        }
    return NULL;
}

json_t *sph_case_fields_json(void)
{
    static const char *const types[] = {"object", "text",  "number", "integer", "enum",  "vector",
                                        "box",    "names", "custom", "array",   "string"};
    json_t *rows = json_array();
    for (const sph_case_field *f = sph_case_fields; rows && f->path; f++) {
        json_t *methods = json_array(), *required = json_array();
        for (int m = 0; m < SPH_METHOD_COUNT; m++) {
            if (!sph_sim_has_method((sph_method)m))
                continue; /* a method of a later version: its rows are not in force */
            if (f->methods & SPH_CF_M(m))
                json_array_append_new(methods, json_string(sph_method_name((sph_method)m)));
            if (f->required & SPH_CF_M(m))
                json_array_append_new(required, json_string(sph_method_name((sph_method)m)));
        }
        json_t *row = json_pack("{s:s, s:s, s:o, s:o, s:s?, s:s}", "path", f->path, "type",
                                types[f->type], "methods", methods, "required", required, "when",
                                f->when, "doc", f->doc ? f->doc : "");
        if (!row)
            continue;
        if (f->type == SPH_CF_NUMBER || f->type == SPH_CF_INTEGER || f->type == SPH_CF_VECTOR ||
            f->type == SPH_CF_ARRAY) {
            json_object_set_new(row, f->lo_open ? "exclusive_min" : "min", json_real(f->lo));
            json_object_set_new(row, f->hi_open ? "exclusive_max" : "max", json_real(f->hi));
        }
        json_t *names = NULL;
        if (f->names) {
            names = json_array();
            for (int k = 0; f->names[k]; k++)
                json_array_append_new(names, json_string(f->names[k]));
            json_object_set(row, "names", names);
        }
        if (f->type == SPH_CF_NAMES) {
            json_t *def = json_array();
            for (int k = 0; f->names[k]; k++)
                if ((f->values ? (unsigned)f->values[k] : 1u << k) & f->def_mask)
                    json_array_append_new(def, json_string(f->names[k]));
            json_object_set_new(row, "default", def);
        } else if (f->has_def && f->type == SPH_CF_ENUM) {
            json_object_set(row, "default", json_array_get(names, (size_t)f->def));
        } else if (f->has_def) {
            json_object_set_new(row, "default", json_real(f->def));
        }
        json_decref(names);
        json_array_append_new(rows, row);
    }
    return rows;
}

void sph_case_clear(sph_case *c)
{
    if (!c)
        return;
    sph_wave_series_free(c->series);
    free(c->series);
    c->series = NULL;
    c->sim.wavemaker.series = NULL;
    for (int k = 0; k < SPH_CONFIG_MAX_GEOMETRY; k++) {
        if (c->meshes[k]) {
            sph_mesh_free(c->meshes[k]);
            free(c->meshes[k]);
            c->meshes[k] = NULL;
        }
        c->sim.geometry[k].mesh = NULL;
    }
}

int sph_case_files(const json_t *root, sph_case_file *files, int max)
{
    int n = 0;
    const json_t *geo = json_is_object(root) ? json_object_get(root, "geometry") : NULL;
    for (size_t k = 0; json_is_array(geo) && k < json_array_size(geo); k++) {
        const json_t *f = json_object_get(json_array_get(geo, k), "mesh");
        if (!json_is_string(f))
            continue;
        if (n < max) {
            files[n].name = json_string_value(f);
            snprintf(files[n].path, sizeof files[n].path, "/geometry/%zu/mesh", k);
            snprintf(files[n].what, sizeof files[n].what, "geometry item %zu", k);
        }
        n++;
    }
    const json_t *w = json_is_object(root) ? json_object_get(root, "wavemaker") : NULL;
    const json_t *waves = json_is_object(w) ? json_object_get(w, "waves") : NULL;
    const json_t *type = json_is_object(waves) ? json_object_get(waves, "type") : NULL;
    const json_t *f = json_is_object(waves) ? json_object_get(waves, "file") : NULL;
    if (json_is_string(f) && json_is_string(type) &&
        strcmp(json_string_value(type), "series") == 0) {
        if (n < max) {
            files[n].name = json_string_value(f);
            snprintf(files[n].path, sizeof files[n].path, "/wavemaker/waves/file");
            snprintf(files[n].what, sizeof files[n].what, "the wavemaker's series");
        }
        n++;
    }
    return n;
}

void sph_wave_series_free(sph_wave_series *q)
{
    if (!q)
        return;
    free(q->t);
    free(q->x);
    *q = (sph_wave_series){0};
}

/* Appends a row to q (grown by doubling in *cap). 0, or -1 out of memory. */
static int series_push(sph_wave_series *q, long *cap, double t, double x)
{
    if (q->n == *cap) {
        const long nc = *cap ? 2 * *cap : 256;
        double *nt = realloc(q->t, (size_t)nc * sizeof *nt);
        if (nt)
            q->t = nt;
        double *nx = nt ? realloc(q->x, (size_t)nc * sizeof *nx) : NULL;
        if (!nx)
            return -1;
        q->x = nx;
        *cap = nc;
    }
    q->t[q->n] = t;
    q->x[q->n] = x;
    q->n++;
    return 0;
}

int sph_wave_series_parse(const char *text, size_t len, const char *name, sph_wave_series *q,
                          sph_error *err)
{
    const char *path = "/wavemaker/waves/file";
    *q = (sph_wave_series){0};
    long cap = 0, line = 0;
    int rc = 0;
    for (size_t i = 0; i < len && rc == 0;) {
        size_t e = i;
        while (e < len && text[e] != '\n')
            e++;
        line++;
        size_t b = i;
        if (line == 1 && len - b >= 3 && memcmp(text + b, "\xef\xbb\xbf", 3) == 0)
            b += 3; /* a UTF-8 byte order mark */
        while (b < e && (text[b] == ' ' || text[b] == '\t' || text[b] == '\r'))
            b++;
        if (b == e || text[b] == '#') { /* blank, or a comment of any length */
            i = e + 1;
            continue;
        }
        i = b;
        char buf[256];
        if (e - i > sizeof buf - 1) {
            rc = sph_error_set(err, SPH_ERR_INVALID, path,
                               "%s line %ld: longer than %zu characters: expected 'time, "
                               "displacement'",
                               name, line, sizeof buf - 1);
            break;
        }
        const size_t m = e - i;
        memcpy(buf, text + i, m);
        buf[m] = '\0';
        i = e + 1;
        char *p = buf;
        while (*p == ' ' || *p == '\t' || *p == '\r')
            p++;
        if (*p == '\0' || *p == '#')
            continue;
        for (char *c = p; *c; c++)
            if (*c == ',' || *c == ';' || *c == '\t' || *c == '\r')
                *c = ' ';
        char *end;
        errno = 0;
        const double t = strtod(p, &end);
        char *end2 = end;
        const double x = end != p ? strtod(end, &end2) : 0.0;
        while (*end2 == ' ')
            end2++;
        if (end == p || end2 == end || *end2 != '\0' || errno == ERANGE || !isfinite(t) ||
            !isfinite(x)) {
            if (q->n == 0 && line == 1 && !strchr("+-.0123456789", *p))
                continue; /* a header: it starts with no number */
            rc = sph_error_set(err, SPH_ERR_INVALID, path,
                               "%s line %ld: expected 'time, displacement' (two numbers, s and "
                               "m), found \"%.40s\"",
                               name, line, p);
        } else if (q->n >= SPH_WAVE_SERIES_MAX) {
            rc = sph_error_set(err, SPH_ERR_INVALID, path, "%s: more than %ld rows", name,
                               SPH_WAVE_SERIES_MAX);
        } else if (q->n > 0 && !(t > q->t[q->n - 1])) {
            rc = sph_error_set(err, SPH_ERR_INVALID, path,
                               "%s line %ld: the time %g s does not increase (after %g s)", name,
                               line, t, q->t[q->n - 1]);
        } else if (series_push(q, &cap, t, x)) {
            rc = sph_error_set(err, SPH_ERR_NOMEM, path, "out of memory");
        }
    }
    if (rc == 0 && q->n < 2)
        rc = sph_error_set(err, SPH_ERR_INVALID, path,
                           "%s: a series needs at least 2 rows of 'time, displacement'", name);
    if (rc)
        sph_wave_series_free(q);
    return rc;
}

/* Reads c's wavemaker's series (a series wavemaker: its file relative to dir) into c->series
 * and points the config at it. */
static int load_series(sph_case *c, const char *dir, sph_error *err)
{
    sph_wavemaker_spec *m = &c->sim.wavemaker;
    const char *path = "/wavemaker/waves/file";
    if (m->type == SPH_WAVEMAKER_NONE || m->waves != SPH_WAVES_SERIES || m->series)
        return 0;
    char why[256], file[4096];
    if (sph_input_name_check(m->file, why, sizeof why) != 0)
        return sph_error_set(err, SPH_ERR_INVALID, path, "%s", why);
    snprintf(file, sizeof file, "%s/%s", dir && *dir ? dir : ".", m->file);
    char *buf;
    size_t got;
    const int rd = sph_read_file(file, (size_t)SPH_INPUT_MAX_FILE, &buf, &got);
    if (rd == -3)
        return sph_error_set(err, SPH_ERR_NOMEM, path, "out of memory");
    if (rd == -2)
        return sph_error_set(err, SPH_ERR_INVALID, path, "%s is larger than %ld bytes", m->file,
                             (long)SPH_INPUT_MAX_FILE);
    if (rd)
        return sph_error_set(err, SPH_ERR_INVALID, path, "cannot read %s: %s", m->file,
                             errno ? strerror(errno) : "not a regular file, or it changed");
    sph_wave_series *q = calloc(1, sizeof *q);
    int rc = q ? sph_wave_series_parse(buf, got, m->file, q, err)
               : sph_error_set(err, SPH_ERR_NOMEM, path, "out of memory");
    free(buf);
    if (rc) {
        free(q);
        return rc;
    }
    c->series = q;
    m->series = q;
    return sph_wavemaker_check(&c->sim, err); /* the rows' own checks: jumps, the stroke */
}

int sph_case_load_files(sph_case *c, const char *dir, const sph_mesh_limits *lim, sph_error *err)
{
    if (load_series(c, dir, err))
        return SPH_ERR_INVALID;
    int loaded = 0;
    for (int k = 0; k < c->sim.ngeometry; k++) {
        sph_geometry_spec *g = &c->sim.geometry[k];
        if (g->kind != SPH_GEOM_MESH || g->mesh)
            continue;
        char path[64], file[4096];
        snprintf(path, sizeof path, "/geometry/%d/mesh", k);
        snprintf(file, sizeof file, "%s/%s", dir && *dir ? dir : ".", g->file);
        sph_mesh *m = calloc(1, sizeof *m);
        if (!m)
            return sph_error_set(err, SPH_ERR_NOMEM, path, "out of memory");
        const int rc = sph_mesh_read_file(file, g->file, lim, m, path, err);
        if (rc) {
            free(m);
            /* a file that is not there or cannot be read is the case's fault too */
            if (err && err->code == SPH_ERR_IO)
                err->code = SPH_ERR_INVALID;
            return SPH_ERR_INVALID;
        }
        c->meshes[k] = m;
        g->mesh = m;
        loaded = 1;
    }
    if (!loaded)
        return 0;
    /* the surfaces checked, placed and the lattice counted: every error of the geometry now,
     * at its path, before a job is made of it */
    sph_config probe = c->sim;
    return sph_fill_prepare(&probe, err);
}

int sph_case_mesh_note(const sph_case *c, int k, char *buf, size_t n, int *warn)
{
    if (k < 0 || k >= c->sim.ngeometry || c->sim.geometry[k].kind != SPH_GEOM_MESH ||
        !c->sim.geometry[k].mesh)
        return -1;
    const sph_mesh *m = c->sim.geometry[k].mesh;
    *warn = m->degenerate > 0;
    snprintf(buf, n,
             "geometry %d: mesh %s: %ld triangles, %ld vertices%s%ld degenerate triangles "
             "dropped",
             k, c->sim.geometry[k].file, m->nt, m->nv, m->degenerate ? "; " : ", ", m->degenerate);
    return 0;
}

/* ---- steering ---------------------------------------------------------------------------- */

/* The fields a running job takes between two steps (sph_sim_steer's), as dotted paths. */
static const char *const steerable[] = {"physics.viscosity.alpha",
                                        "physics.viscosity.nu",
                                        "physics.delta_sph",
                                        "physics.gravity",
                                        "time.cfl",
                                        "time.end",
                                        "triggers",
                                        "output.every",
                                        "diagnostics.every",
                                        "diagnostics.interval",
                                        NULL};

int sph_case_steerable(const char *path, sph_error *err)
{
    for (int k = 0; steerable[k]; k++) {
        const size_t n = strlen(steerable[k]);
        if (strcmp(path, steerable[k]) == 0 ||
            (strcmp(steerable[k], "physics.gravity") == 0 && strncmp(path, steerable[k], n) == 0 &&
             path[n] == '.' && path[n + 1] >= '0' && path[n + 1] <= '2' && !path[n + 2]))
            return 0;
    }
    if (strncmp(path, "output.", 7) == 0 || strcmp(path, "output") == 0 ||
        strncmp(path, "diagnostics.", 12) == 0 || strcmp(path, "diagnostics") == 0)
        return sph_error_set(err, SPH_ERR_INVALID, "",
                             "'%.200s' is not changed in a running job: of the outputs and "
                             "diagnostics only output.every, diagnostics.every and "
                             "diagnostics.interval are (the fields, the probes, gauges and "
                             "series of diag.h5 are fixed when it is made)",
                             path);
    return sph_error_set(err, SPH_ERR_INVALID, "",
                         "'%.200s' is not changed in a running job: it is part of the set-up (the "
                         "particles, the method, the models or the walls); submit a new job with "
                         "--set. The fields a running job takes: physics.viscosity.alpha, "
                         "physics.viscosity.nu, physics.delta_sph, physics.gravity, time.cfl, "
                         "time.end, triggers, output.every, diagnostics.every, "
                         "diagnostics.interval",
                         path);
}

#include "sph_json.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *sph_json_type_name(const json_t *v)
{
    switch (json_typeof(v)) {
    case JSON_OBJECT:
        return "an object";
    case JSON_ARRAY:
        return "an array";
    case JSON_STRING:
        return "a string";
    case JSON_INTEGER:
    case JSON_REAL:
        return "a number";
    case JSON_TRUE:
    case JSON_FALSE:
        return "a boolean";
    case JSON_NULL:
        return "null";
    }
    return "unknown";
}

static void join(char *dst, size_t n, const char *base, const char *key)
{
    snprintf(dst, n, "%s/%s", base ? base : "", key);
}

int sph_json_check_keys(const json_t *obj, const char *base, const char *const *allowed,
                        sph_error *err)
{
    const char *key;
    json_t *v;
    json_object_foreach((json_t *)obj, key, v)
    {
        int ok = 0;
        for (const char *const *a = allowed; *a; a++)
            if (strcmp(*a, key) == 0)
                ok = 1;
        if (!ok) {
            char path[SPH_ERROR_PATH_MAX];
            join(path, sizeof path, base, key);
            char list[200] = "";
            size_t used = 0;
            for (const char *const *a = allowed; *a && used < sizeof list - 40; a++)
                used += (size_t)snprintf(list + used, sizeof list - used, "%s%s",
                                         a == allowed ? "" : ", ", *a);
            return sph_error_set(err, SPH_ERR_INVALID, path, "unknown field '%s' (allowed: %s)",
                                 key, list);
        }
    }
    return 0;
}

int sph_json_get(const json_t *obj, const char *base, const char *key, int required, json_t **out,
                 sph_error *err)
{
    *out = json_object_get(obj, key);
    if (!*out && required) {
        char path[SPH_ERROR_PATH_MAX];
        join(path, sizeof path, base, key);
        return sph_error_set(err, SPH_ERR_INVALID, path, "missing required field '%s'", key);
    }
    return 0;
}

static int wrong_type(const char *base, const char *key, const char *want, const json_t *v,
                      sph_error *err)
{
    char path[SPH_ERROR_PATH_MAX];
    join(path, sizeof path, base, key);
    return sph_error_set(err, SPH_ERR_INVALID, path, "'%s' must be %s, not %s", key, want,
                         sph_json_type_name(v));
}

int sph_json_number(const json_t *obj, const char *base, const char *key, int required, double lo,
                    double hi, double *out, sph_error *err)
{
    json_t *v;
    if (sph_json_get(obj, base, key, required, &v, err))
        return SPH_ERR_INVALID;
    if (!v)
        return 0;
    if (!json_is_number(v))
        return wrong_type(base, key, "a number", v, err);
    const double x = json_number_value(v);
    if (!(x >= lo && x <= hi)) {
        char path[SPH_ERROR_PATH_MAX];
        join(path, sizeof path, base, key);
        return sph_error_set(err, SPH_ERR_INVALID, path, "'%s' must be in [%g, %g], got %g", key,
                             lo, hi, x);
    }
    *out = x;
    return 0;
}

int sph_json_integer(const json_t *obj, const char *base, const char *key, int required, long lo,
                     long hi, long *out, sph_error *err)
{
    json_t *v;
    if (sph_json_get(obj, base, key, required, &v, err))
        return SPH_ERR_INVALID;
    if (!v)
        return 0;
    double x;
    if (json_is_integer(v))
        x = (double)json_integer_value(v);
    else if (json_is_real(v) && json_real_value(v) == floor(json_real_value(v)))
        x = json_real_value(v);
    else
        return wrong_type(base, key, "an integer", v, err);
    if (!(x >= (double)lo && x <= (double)hi)) {
        char path[SPH_ERROR_PATH_MAX];
        join(path, sizeof path, base, key);
        return sph_error_set(err, SPH_ERR_INVALID, path, "'%s' must be in [%ld, %ld], got %.0f",
                             key, lo, hi, x);
    }
    *out = (long)x;
    return 0;
}

int sph_json_string(const json_t *obj, const char *base, const char *key, int required,
                    const char **out, sph_error *err)
{
    json_t *v;
    if (sph_json_get(obj, base, key, required, &v, err))
        return SPH_ERR_INVALID;
    if (!v)
        return 0;
    if (!json_is_string(v))
        return wrong_type(base, key, "a string", v, err);
    *out = json_string_value(v);
    return 0;
}

int sph_json_bool(const json_t *obj, const char *base, const char *key, int required, int *out,
                  sph_error *err)
{
    json_t *v;
    if (sph_json_get(obj, base, key, required, &v, err))
        return SPH_ERR_INVALID;
    if (!v)
        return 0;
    if (!json_is_boolean(v))
        return wrong_type(base, key, "true or false", v, err);
    *out = json_is_true(v);
    return 0;
}

int sph_json_vector(const json_t *obj, const char *base, const char *key, int required, int n,
                    double *out, sph_error *err)
{
    json_t *v;
    if (sph_json_get(obj, base, key, required, &v, err))
        return SPH_ERR_INVALID;
    if (!v)
        return 0;
    char path[SPH_ERROR_PATH_MAX];
    join(path, sizeof path, base, key);
    if (!json_is_array(v) || json_array_size(v) != (size_t)n)
        return sph_error_set(err, SPH_ERR_INVALID, path, "'%s' must be an array of %d numbers", key,
                             n);
    for (int i = 0; i < n; i++) {
        json_t *x = json_array_get(v, (size_t)i);
        if (!json_is_number(x) || !isfinite(json_number_value(x))) {
            char ipath[SPH_ERROR_PATH_MAX + 16];
            snprintf(ipath, sizeof ipath, "%s/%d", path, i);
            return sph_error_set(err, SPH_ERR_INVALID, ipath, "'%s[%d]' must be a number, not %s",
                                 key, i, sph_json_type_name(x));
        }
        out[i] = json_number_value(x);
    }
    return 0;
}

int sph_json_apply_set(json_t *root, const char *assignment, sph_error *err)
{
    const char *eq = strchr(assignment, '=');
    if (!eq || eq == assignment)
        return sph_error_set(err, SPH_ERR_INVALID, "",
                             "--set takes PATH=VALUE (e.g. dx=0.004), got '%s'", assignment);
    char path[256];
    const size_t plen = (size_t)(eq - assignment);
    if (plen >= sizeof path)
        return sph_error_set(err, SPH_ERR_INVALID, "", "--set path too long");
    memcpy(path, assignment, plen);
    path[plen] = '\0';

    json_error_t jerr;
    json_t *value = json_loads(eq + 1, JSON_DECODE_ANY, &jerr);
    if (!value)
        value = json_string(eq + 1);
    if (!value)
        return sph_error_set(err, SPH_ERR_INVALID, "", "--set value is not valid UTF-8");

    json_t *cur = root;
    char pointer[SPH_ERROR_PATH_MAX] = "";
    char *save = NULL;
    char *tok = strtok_r(path, ".", &save);
    while (tok) {
        char *next = strtok_r(NULL, ".", &save);
        size_t used = strlen(pointer);
        snprintf(pointer + used, sizeof pointer - used, "/%s", tok);
        if (json_is_object(cur)) {
            if (!next) {
                /* set_new takes value even when it fails (a key that is not UTF-8) */
                if (json_object_set_new(cur, tok, value) != 0)
                    return sph_error_set(err, SPH_ERR_INVALID, pointer,
                                         "--set: '%s' is not a valid key", tok);
                return 0;
            }
            json_t *child = json_object_get(cur, tok);
            if (!child) {
                child = json_object();
                if (json_object_set_new(cur, tok, child) != 0) {
                    json_decref(value);
                    return sph_error_set(err, SPH_ERR_INVALID, pointer,
                                         "--set: '%s' is not a valid key", tok);
                }
            }
            cur = child;
        } else if (json_is_array(cur)) {
            char *end;
            long idx = strtol(tok, &end, 10);
            if (*end || idx < 0 || (size_t)idx >= json_array_size(cur)) {
                json_decref(value);
                return sph_error_set(err, SPH_ERR_INVALID, pointer,
                                     "--set: '%s' is not an index of the array (size %zu)", tok,
                                     json_array_size(cur));
            }
            if (!next) {
                json_array_set_new(cur, (size_t)idx, value);
                return 0;
            }
            cur = json_array_get(cur, (size_t)idx);
        } else {
            json_decref(value);
            return sph_error_set(err, SPH_ERR_INVALID, pointer,
                                 "--set: cannot descend into %s at '%s'", sph_json_type_name(cur),
                                 pointer);
        }
        tok = next;
    }
    json_decref(value);
    return sph_error_set(err, SPH_ERR_INVALID, "", "--set: empty path in '%s'", assignment);
}

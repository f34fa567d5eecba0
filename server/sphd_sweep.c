/*
 * Parameter sweeps: one case, lists of values for some of its fields, one job per combination
 * (the product of the lists, the first list varying slowest). The jobs are ordinary jobs with a
 * `sweep` id and their `params`; this file expands a sweep into its cases and builds the sweep's
 * table (each job's parameters and result summary) for `export`.
 */
#include "sphd_daemon.h"

#include "sph_json.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int sphd_apply_sets(json_t *c, const json_t *sets, sphd_err *e)
{
    size_t i;
    json_t *s;
    json_array_foreach((json_t *)sets, i, s)
    {
        char path[48];
        snprintf(path, sizeof path, "/args/set/%zu", i);
        if (!json_is_string(s))
            return sphd_err_set(e, SPHD_E_BAD_REQUEST, path,
                                "each 'set' item is a string PATH=VALUE, not %s",
                                sph_json_type_name(s));
        sph_error se;
        sph_error_clear(&se);
        if (sph_json_apply_set(c, json_string_value(s), &se))
            return sphd_err_set(e, SPHD_E_INVALID_CASE, se.path[0] ? se.path : path, "set: %s",
                                se.message);
    }
    return 0;
}

json_t *sphd_sweep_expand(const json_t *case_in, const json_t *sets, const json_t *vary,
                          json_t **params_out, sphd_err *e)
{
    const size_t nv = json_array_size(vary);
    if (nv < 1 || nv > SPHD_SWEEP_MAX_LISTS) {
        sphd_err_set(e, SPHD_E_BAD_REQUEST, "/args/vary", "'vary' lists 1 to %d fields",
                     SPHD_SWEEP_MAX_LISTS);
        return NULL;
    }
    size_t count = 1;
    for (size_t i = 0; i < nv; i++) {
        const json_t *v = json_array_get(vary, i);
        char path[64];
        snprintf(path, sizeof path, "/args/vary/%zu", i);
        const json_t *p = json_object_get(v, "path"), *vals = json_object_get(v, "values");
        if (!json_is_object(v) || !json_is_string(p) || !json_is_array(vals) ||
            json_object_size(v) != 2) {
            sphd_err_set(e, SPHD_E_BAD_REQUEST, path,
                         "each 'vary' item is {\"path\": \"dotted.path\", \"values\": [...]}");
            return NULL;
        }
        if (json_array_size(vals) < 1) {
            snprintf(path, sizeof path, "/args/vary/%zu/values", i);
            sphd_err_set(e, SPHD_E_BAD_REQUEST, path, "'values' lists at least one value");
            return NULL;
        }
        for (size_t k = 0; k < i; k++)
            if (strcmp(json_string_value(p),
                       json_string_value(json_object_get(json_array_get(vary, k), "path"))) == 0) {
                snprintf(path, sizeof path, "/args/vary/%zu/path", i);
                sphd_err_set(e, SPHD_E_BAD_REQUEST, path, "'%.64s' is varied twice",
                             json_string_value(p));
                return NULL;
            }
        count *= json_array_size(vals);
        if (count > SPHD_SWEEP_MAX_JOBS) {
            sphd_err_set(e, SPHD_E_TOO_LARGE, "/args/vary",
                         "the sweep has more than %d combinations: split it", SPHD_SWEEP_MAX_JOBS);
            return NULL;
        }
    }
    json_t *base = json_deep_copy(case_in);
    json_t *cases = json_array(), *params = json_array();
    if (!base || !cases || !params)
        goto oom;
    if (sphd_apply_sets(base, sets, e) != 0)
        goto fail;
    for (size_t n = 0; n < count; n++) {
        json_t *c = json_deep_copy(base), *p = json_object();
        if (!c || !p) {
            json_decref(c);
            json_decref(p);
            goto oom;
        }
        json_array_append_new(cases, c);
        json_array_append_new(params, p);
        size_t pick[SPHD_SWEEP_MAX_LISTS], rest = n;
        for (size_t k = nv; k-- > 0;) { /* the last list varies fastest */
            const size_t len = json_array_size(json_object_get(json_array_get(vary, k), "values"));
            pick[k] = rest % len;
            rest /= len;
        }
        for (size_t k = 0; k < nv; k++) {
            const json_t *v = json_array_get(vary, k);
            const json_t *val = json_array_get(json_object_get(v, "values"), pick[k]);
            const char *path = json_string_value(json_object_get(v, "path"));
            char *text = json_dumps(val, JSON_COMPACT | JSON_ENCODE_ANY | JSON_REAL_PRECISION(17));
            size_t len = strlen(path) + (text ? strlen(text) : 0) + 2;
            char *assign = text ? malloc(len) : NULL;
            if (!assign) {
                free(text);
                goto oom;
            }
            snprintf(assign, len, "%s=%s", path, text);
            free(text);
            sph_error se;
            sph_error_clear(&se);
            const int rc = sph_json_apply_set(c, assign, &se);
            free(assign);
            if (rc) {
                char where[64];
                snprintf(where, sizeof where, "/args/vary/%zu/path", k);
                sphd_err_set(e, SPHD_E_INVALID_CASE, se.path[0] ? se.path : where, "vary: %s",
                             se.message);
                goto fail;
            }
            json_object_set(p, path, (json_t *)val);
        }
    }
    json_decref(base);
    *params_out = params;
    return cases;
oom:
    sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
fail:
    json_decref(base);
    json_decref(cases);
    json_decref(params);
    return NULL;
}

/* Adds o's scalars to row under dotted names (prefix "" at the top); arrays are left out. */
static void flatten(json_t *row, json_t *columns, const char *prefix, const json_t *o)
{
    const char *k;
    json_t *v;
    json_object_foreach((json_t *)o, k, v)
    {
        char name[256];
        snprintf(name, sizeof name, "%s%s%s", prefix, prefix[0] ? "." : "", k);
        if (json_is_object(v)) {
            flatten(row, columns, name, v);
            continue;
        }
        if (json_is_array(v))
            continue;
        json_object_set(row, name, v);
        size_t i;
        json_t *c;
        int known = 0;
        json_array_foreach(columns, i, c) known |= strcmp(json_string_value(c), name) == 0;
        if (!known)
            json_array_append_new(columns, json_string(name));
    }
}

/* A growing text; ok drops to 0 when memory runs out. */
typedef struct {
    char *s;
    size_t len, cap;
    int ok;
} text_buf;

static void put(text_buf *b, const char *s, size_t n)
{
    if (!b->ok)
        return;
    if (b->len + n + 1 > b->cap) {
        size_t ncap = b->cap ? b->cap : 4096;
        while (ncap < b->len + n + 1)
            ncap *= 2;
        char *ns = realloc(b->s, ncap);
        if (!ns) {
            b->ok = 0;
            return;
        }
        b->s = ns;
        b->cap = ncap;
    }
    memcpy(b->s + b->len, s, n);
    b->len += n;
    b->s[b->len] = '\0';
}

/* One CSV cell: numbers as %.12g, strings quoted when they need it, null and absent empty. */
static void csv_cell(text_buf *b, const json_t *v)
{
    char tmp[64];
    if (json_is_integer(v)) {
        snprintf(tmp, sizeof tmp, "%" JSON_INTEGER_FORMAT, json_integer_value(v));
        put(b, tmp, strlen(tmp));
    } else if (json_is_real(v)) {
        snprintf(tmp, sizeof tmp, "%.12g", json_real_value(v));
        put(b, tmp, strlen(tmp));
    } else if (json_is_boolean(v)) {
        put(b, json_is_true(v) ? "true" : "false", json_is_true(v) ? 4 : 5);
    } else if (json_is_string(v)) {
        const char *s = json_string_value(v);
        if (!strpbrk(s, ",\"\n\r")) {
            put(b, s, strlen(s));
            return;
        }
        put(b, "\"", 1);
        for (; *s; s++)
            put(b, *s == '"' ? "\"\"" : s, *s == '"' ? 2 : 1);
        put(b, "\"", 1);
    }
}

json_t *sphd_sweep_table(sphd_daemon *d, const char *sweep, int csv, sphd_err *e)
{
    json_t *rows = json_array(), *columns = json_pack("[s, s]", "job", "state");
    json_t *paths = json_array();
    if (!rows || !columns || !paths)
        goto oom;
    for (const sphd_job *j = d->jobs; j; j = j->next) {
        if (strcmp(j->sweep, sweep) != 0)
            continue;
        json_t *row = json_pack("{s:s, s:s}", "job", j->id, "state", sphd_job_state_name(j->state));
        if (!row)
            goto oom;
        const char *k;
        json_t *v;
        json_object_foreach(j->params, k, v)
        {
            size_t i;
            json_t *c;
            int known = 0;
            json_array_foreach(paths, i, c) known |= strcmp(json_string_value(c), k) == 0;
            if (!known) {
                json_array_append_new(paths, json_string(k));
                json_array_append_new(columns, json_string(k));
            }
            json_object_set(row, k, v);
        }
        json_array_append_new(rows, row);
    }
    if (json_array_size(rows) == 0) {
        json_decref(rows);
        json_decref(columns);
        json_decref(paths);
        sphd_err_set(e, SPHD_E_NOT_FOUND, "/args/sweep", "no sweep '%.64s'", sweep);
        return NULL;
    }
    /* the result summaries after the parameters (their own names, dotted) */
    size_t r = 0;
    for (const sphd_job *j = d->jobs; j; j = j->next) {
        if (strcmp(j->sweep, sweep) != 0)
            continue;
        json_t *row = json_array_get(rows, r++);
        if (j->result)
            flatten(row, columns, "", j->result);
        if (j->reason[0])
            json_object_set_new(row, "reason", json_string(j->reason));
    }
    {
        size_t i;
        json_t *row;
        int any_reason = 0;
        json_array_foreach(rows, i, row) any_reason |= json_object_get(row, "reason") != NULL;
        if (any_reason)
            json_array_append_new(columns, json_string("reason"));
    }
    json_t *out = json_pack("{s:s, s:O, s:O, s:I}", "sweep", sweep, "params", paths, "columns",
                            columns, "count", (json_int_t)json_array_size(rows));
    if (!out)
        goto oom;
    if (!csv) {
        json_object_set_new(out, "format", json_string("json"));
        json_object_set(out, "rows", rows);
    } else {
        text_buf t = {.ok = 1};
        size_t k;
        json_t *c;
        for (long ri = -1; ri < (long)json_array_size(rows); ri++) { /* -1: the header */
            const json_t *row = ri < 0 ? NULL : json_array_get(rows, (size_t)ri);
            json_array_foreach(columns, k, c)
            {
                if (k)
                    put(&t, ",", 1);
                csv_cell(&t, row ? json_object_get(row, json_string_value(c)) : c);
            }
            put(&t, "\n", 1);
        }
        if (t.ok) {
            json_object_set_new(out, "format", json_string("csv"));
            json_object_set_new(out, "csv", json_string(t.s));
        }
        free(t.s);
        if (!t.ok) {
            json_decref(out);
            goto oom;
        }
    }
    json_decref(rows);
    json_decref(columns);
    json_decref(paths);
    return out;
oom:
    json_decref(rows);
    json_decref(columns);
    json_decref(paths);
    sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
    return NULL;
}

/*
 * sph_triggers: a case's triggers (sph_triggers.h).
 */
#include "sph_triggers.h"

#include "sph_json.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const action_names[] = {"pause", "stop", "checkpoint", "snapshot", NULL};
static const char *const op_names[] = {">", ">=", "<", "<=", NULL};

const char *sph_trigger_action_name(sph_trigger_action a)
{
    return (unsigned)a < 4 ? action_names[a] : "unknown";
}

/* The series every simulation's diag has, and those of its probes. */
static const char *const base_series[] = {"t",    "step",    "dt",      "ekin", "epot",
                                          "vmax", "rho_min", "rho_max", "lost", NULL};
static const char *const body_members[] = {"penetration", "angle",   "omega", "torque",
                                           "x.0",         "x.1",     "v.0",   "v.1",
                                           "force.0",     "force.1", NULL};

static int in_list(const char *s, const char *const *list)
{
    for (int k = 0; list[k]; k++)
        if (strcmp(s, list[k]) == 0)
            return 1;
    return 0;
}

/* 1 if c's diag events have the series `name`. */
static int known_series(const sph_config *c, const char *name)
{
    if (in_list(name, base_series))
        return 1;
    static const struct {
        unsigned bit;
        const char *name;
    } probes[] = {{SPH_PROBE_FRONT_X, "front_x"},
                  {SPH_PROBE_HEIGHT_LEFT, "height_left"},
                  {SPH_PROBE_PENETRATION, "penetration"},
                  {SPH_PROBE_RUNUP, "runup"}};
    for (size_t k = 0; k < sizeof probes / sizeof probes[0]; k++)
        if ((c->probes & probes[k].bit) && strcmp(name, probes[k].name) == 0)
            return 1;
    if (c->method == SPH_METHOD_MPS &&
        (strcmp(name, "cg_iterations") == 0 || strcmp(name, "cg_residual") == 0 ||
         strcmp(name, "free_surface") == 0))
        return 1;
    for (int k = 0; k < c->ngauges; k++)
        if (strcmp(name, c->gauges[k].name) == 0)
            return 1;
    for (int k = 0; k < c->npressure; k++)
        if (strcmp(name, c->pressure[k].name) == 0)
            return 1;
    for (int k = 0; k < c->nbodies; k++) {
        const size_t n = strlen(c->bodies[k].name);
        if (strncmp(name, c->bodies[k].name, n) == 0 && name[n] == '.' &&
            in_list(name + n + 1, body_members))
            return 1;
    }
    return 0;
}

/* "SERIES OP VALUE" into t; 0 or -1. */
static int parse_when(const char *s, sph_trigger *t)
{
    char series[SPH_TRIGGER_SERIES_MAX], op[4], rest[2];
    double v;
    if (sscanf(s, " %63[A-Za-z0-9_.-] %3[<>=] %lf %1s", series, op, &v, rest) != 3 || !isfinite(v))
        return -1;
    int k = 0;
    while (op_names[k] && strcmp(op, op_names[k]) != 0)
        k++;
    if (!op_names[k])
        return -1;
    snprintf(t->series, sizeof t->series, "%s", series);
    t->op = (sph_trigger_op)k;
    t->value = v;
    return 0;
}

int sph_triggers_parse(const json_t *v, const char *path, const sph_config *c, sph_output_config *o,
                       sph_error *err)
{
    static const char *const keys[] = {"when", "do", NULL};
    if (!json_is_array(v) || json_array_size(v) > SPH_TRIGGERS_MAX)
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "'triggers' must be an array of 0 to %d objects {\"when\": \"SERIES "
                             "OP VALUE\", \"do\": ACTION}",
                             SPH_TRIGGERS_MAX);
    sph_trigger ts[SPH_TRIGGERS_MAX];
    memset(ts, 0, sizeof ts);
    const size_t n = json_array_size(v);
    for (size_t i = 0; i < n; i++) {
        char base[SPH_ERROR_PATH_MAX], at[SPH_ERROR_PATH_MAX];
        snprintf(base, sizeof base, "%.64s/%zu", path, i);
        const json_t *e = json_array_get(v, i);
        const char *when = NULL, *what = NULL;
        if (!json_is_object(e))
            return sph_error_set(err, SPH_ERR_INVALID, base,
                                 "a trigger is an object {\"when\": ..., \"do\": ...}");
        if (sph_json_check_keys(e, base, keys, err) ||
            sph_json_string(e, base, "when", 1, &when, err) ||
            sph_json_string(e, base, "do", 1, &what, err))
            return SPH_ERR_INVALID;
        sph_trigger *t = &ts[i];
        snprintf(at, sizeof at, "%.100s/when", base);
        if (strlen(when) >= sizeof t->when || parse_when(when, t) != 0)
            return sph_error_set(err, SPH_ERR_INVALID, at,
                                 "'%.100s' is not \"SERIES OP VALUE\" (OP one of >, >=, <, <=; "
                                 "VALUE a number): for example \"P1 > 5000\"",
                                 when);
        if (!known_series(c, t->series))
            return sph_error_set(err, SPH_ERR_INVALID, at,
                                 "the case's diagnostics have no series '%s' (a top-level diag "
                                 "number such as t, ekin, vmax or front_x, a gauge's or pressure "
                                 "probe's name, or BODY.penetration, BODY.x.1, ...)",
                                 t->series);
        snprintf(t->when, sizeof t->when, "%s", when);
        int a = 0;
        while (action_names[a] && strcmp(what, action_names[a]) != 0)
            a++;
        snprintf(at, sizeof at, "%.100s/do", base);
        if (!action_names[a])
            return sph_error_set(err, SPH_ERR_INVALID, at,
                                 "unknown action '%.40s' (known: pause, stop, checkpoint, "
                                 "snapshot)",
                                 what);
        t->action = (sph_trigger_action)a;
    }
    memcpy(o->triggers, ts, sizeof ts);
    o->ntriggers = (int)n;
    return 0;
}

json_t *sph_triggers_json(const sph_output_config *o)
{
    json_t *a = json_array();
    for (int k = 0; a && k < o->ntriggers; k++)
        json_array_append_new(a, json_pack("{s:s, s:s}", "when", o->triggers[k].when, "do",
                                           sph_trigger_action_name(o->triggers[k].action)));
    return a;
}

/* The series' value in the diag body, or NAN. */
static double series_value(const json_t *diag, const char *name)
{
    const json_t *v = json_object_get(diag, name);
    if (!v)
        v = json_object_get(json_object_get(diag, "gauges"), name);
    if (!v)
        v = json_object_get(json_object_get(diag, "pressure"), name);
    if (!v) { /* BODY.MEMBER or BODY.MEMBER.K */
        char buf[SPH_TRIGGER_SERIES_MAX];
        snprintf(buf, sizeof buf, "%s", name);
        char *dot = strchr(buf, '.');
        if (dot) {
            *dot = '\0';
            char *k = strchr(dot + 1, '.');
            if (k)
                *k = '\0';
            v = json_object_get(json_object_get(json_object_get(diag, "bodies"), buf), dot + 1);
            if (k)
                v = json_array_get(v, (size_t)atoi(k + 1));
        }
    }
    return json_is_number(v) ? json_number_value(v) : NAN;
}

int sph_trigger_holds(const sph_trigger *t, const json_t *diag)
{
    const double x = series_value(diag, t->series);
    if (!isfinite(x))
        return 0;
    switch (t->op) {
    case SPH_TRIGGER_GT:
        return x > t->value;
    case SPH_TRIGGER_GE:
        return x >= t->value;
    case SPH_TRIGGER_LT:
        return x < t->value;
    case SPH_TRIGGER_LE:
        return x <= t->value;
    }
    return 0;
}

/* sphctl's shared helpers, its bottom floor (calls no other file of sphctl): the command line of
 * one command (options, positionals, usage errors), and printing JSON, numbers, durations and a
 * sweep job's parameters. */
#include "sphctl.h"

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int sphctl_usage(const char *cmd, const char *fmt, const char *arg)
{
    fputs("sphctl: ", stderr);
    fprintf(stderr, fmt, arg);
    fprintf(stderr, "\nTry 'sphctl %s --help'.\n", cmd ? cmd : "");
    return SPHCTL_EX_USAGE;
}

int sphctl_args(const sphctl_argspec *spec, int argc, char **argv,
                int (*on_opt)(void *ud, int o, const char *arg), void *ud)
{
    static const struct option help_only[] = {{"help", no_argument, NULL, 'h'}, {NULL, 0, NULL, 0}};
    int o;
    optind = 0;
    while ((o = getopt_long(argc, argv, spec->optstring, spec->opts ? spec->opts : help_only,
                            NULL)) != -1) {
        if (o == 'h') {
            fputs(spec->help, stdout);
            return 0;
        }
        if (o == '?' || !on_opt) {
            if (spec->bad_option)
                return sphctl_usage(argv[0], "%s", spec->bad_option);
            return sphctl_usage(argv[0], "bad option for %s", argv[0]);
        }
        int rc = on_opt(ud, o, optarg);
        if (rc)
            return rc;
    }
    int npos = argc - optind;
    if (npos >= spec->min_args && npos <= spec->max_args)
        return SPHCTL_RUN;
    if (spec->bad_count)
        return sphctl_usage(argv[0], "%s", spec->bad_count);
    fprintf(stderr, "sphctl: %s takes %d argument%s\n%s", argv[0], spec->min_args,
            spec->min_args == 1 ? "" : "s", spec->help);
    return SPHCTL_EX_USAGE;
}

int sphctl_store_opt(void *ud, int o, const char *arg)
{
    ((const char **)ud)[o] = arg ? arg : "";
    return 0;
}

void sphctl_print_json(const json_t *v, int compact)
{
    char *s = json_dumps(v, (compact ? JSON_COMPACT : JSON_INDENT(2)) | JSON_REAL_PRECISION(12));
    if (s) {
        fputs(s, stdout);
        fputc('\n', stdout);
        free(s);
    }
    fflush(stdout);
}

void sphctl_fmt_duration(double s, char *buf, size_t n)
{
    if (!isfinite(s) || s < 0) {
        snprintf(buf, n, "-");
        return;
    }
    long t = (long)(s + 0.5);
    if (t >= 3600)
        snprintf(buf, n, "%ldh%02ldm", t / 3600, (t / 60) % 60);
    else if (t >= 60)
        snprintf(buf, n, "%ldm%02lds", t / 60, t % 60);
    else
        snprintf(buf, n, "%.1fs", s);
}

double sphctl_num(const json_t *o, const char *k)
{
    json_t *v = json_object_get(o, k);
    return json_is_number(v) ? json_number_value(v) : NAN;
}

/* Appends "path=value" (with a space before it unless buf is empty) to buf: a string bare
 * unless it is empty or holds a space, ',', '=' or '"' (then quoted, as JSON). */
static void add_param(char *buf, size_t n, const char *path, const json_t *v)
{
    size_t len = strlen(buf);
    if (len + 1 >= n)
        return;
    const char *str = json_string_value(v);
    const int bare = str && *str && !strpbrk(str, " ,=\"");
    char *text =
        bare ? NULL : json_dumps(v, JSON_COMPACT | JSON_ENCODE_ANY | JSON_REAL_PRECISION(12));
    snprintf(buf + len, n - len, "%s%s=%s", len ? " " : "", path, bare ? str : text ? text : "?");
    free(text);
}

const char *sphctl_fmt_params(const json_t *params, const json_t *order, char *buf, size_t n)
{
    if (n)
        buf[0] = '\0';
    size_t i;
    json_t *p;
    json_array_foreach(order, i, p)
    {
        const json_t *v = json_object_get(params, json_string_value(p));
        if (v)
            add_param(buf, n, json_string_value(p), v);
    }
    const char *k;
    json_t *v;
    json_object_foreach((json_t *)params, k, v)
    {
        int listed = 0;
        json_array_foreach(order, i, p) listed |= strcmp(json_string_value(p), k) == 0;
        if (!listed)
            add_param(buf, n, k, v);
    }
    return buf;
}

void sphctl_sweep_widths(const json_t *jobs, const json_t *order, int *wid, int *wpar)
{
    size_t i;
    const json_t *s;
    char buf[1024];
    *wid = *wpar = 0;
    json_array_foreach(jobs, i, s)
    {
        const char *id = json_string_value(json_object_get(s, "job"));
        int l = id ? (int)strlen(id) : 0;
        int lp =
            (int)strlen(sphctl_fmt_params(json_object_get(s, "params"), order, buf, sizeof buf));
        *wid = l > *wid ? l : *wid;
        *wpar = lp > *wpar ? lp : *wpar;
    }
}

int sphctl_resources_opt(const char *cmd, const char *arg, json_t **out)
{
    json_error_t err;
    json_t *r = json_loads(arg, 0, &err);
    if (!json_is_object(r)) {
        json_decref(r);
        return sphctl_usage(cmd,
                            "--resources takes a JSON object, e.g. '{\"executor\": \"slurm\", "
                            "\"threads\": 4}', not '%s'",
                            arg);
    }
    json_decref(*out);
    *out = r;
    return 0;
}

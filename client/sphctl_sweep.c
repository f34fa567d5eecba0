/* sphctl sweep: one case file, lists of values for some of its fields (--set PATH=V1,V2,...),
 * one job per combination, created by sphd's `sweep` op. */
#include "sphctl.h"

#include "sph_case.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct sweep_opts {
    const char *id;
    int nostart, watch;
    json_t *sets;  /* fixed overrides: "PATH=VALUE" strings */
    json_t *vary;  /* [{"path": PATH, "values": [...]}] */
    json_t *paths; /* the varied paths, in the order given */
    json_t *resources;
} sweep_opts;

/* One value of a --set list: JSON where it parses, else the text as a string. */
static json_t *parse_value(const char *s, size_t len)
{
    json_error_t err;
    json_t *v = json_loadb(s, len, JSON_DECODE_ANY, &err);
    return v ? v : json_stringn(s, len);
}

/* Splits s on the commas outside [], {} and "..." into a new array of values. */
static json_t *split_values(const char *s)
{
    json_t *vals = json_array();
    int depth = 0, in_str = 0;
    const char *start = s;
    for (const char *p = s;; p++) {
        if (in_str) {
            if (*p == '\\' && p[1])
                p++;
            else if (*p == '"')
                in_str = 0;
            else if (!*p)
                in_str = 0; /* unterminated: the piece stays a string */
        } else if (*p == '"') {
            in_str = 1;
        } else if (*p == '[' || *p == '{') {
            depth++;
        } else if ((*p == ']' || *p == '}') && depth > 0) {
            depth--;
        }
        if (!*p || (*p == ',' && depth == 0 && !in_str)) {
            json_array_append_new(vals, parse_value(start, (size_t)(p - start)));
            if (!*p)
                break;
            start = p + 1;
        }
    }
    return vals;
}

static int sweep_opt(void *ud, int o, const char *arg)
{
    sweep_opts *so = ud;
    switch (o) {
    case 'i':
        so->id = arg;
        break;
    case 's': {
        const char *eq = strchr(arg, '=');
        if (!eq || eq == arg)
            return sphctl_usage("sweep", "--set takes PATH=VALUE or PATH=V1,V2,..., not '%s'", arg);
        json_t *vals = split_values(eq + 1);
        if (json_array_size(vals) < 2) {
            json_decref(vals);
            json_array_append_new(so->sets, json_string(arg));
            break;
        }
        json_t *path = json_stringn(arg, (size_t)(eq - arg));
        json_array_append(so->paths, path);
        json_array_append_new(so->vary, json_pack("{s:o, s:o}", "path", path, "values", vals));
        break;
    }
    case 'r':
        return sphctl_resources_opt("sweep", arg, &so->resources);
    case 'n':
        so->nostart = 1;
        break;
    case 'w':
        so->watch = 1;
        break;
    }
    return 0;
}

/* The jobs created, one a line: ID, its parameters (in the order of the --set options), state. */
static void print_sweep(const json_t *r, const json_t *paths)
{
    const json_t *jobs = json_object_get(r, "jobs");
    int wid, wpar;
    sphctl_sweep_widths(jobs, paths, &wid, &wpar);
    size_t i;
    json_t *s;
    char buf[1024];
    json_array_foreach(jobs, i, s)
    {
        printf("%-*s  %-*s  (%s%s)\n", wid, json_string_value(json_object_get(s, "job")), wpar,
               sphctl_fmt_params(json_object_get(s, "params"), paths, buf, sizeof buf),
               json_string_value(json_object_get(s, "state")),
               json_is_false(json_object_get(s, "created")) ? ", already submitted" : "");
    }
    printf("sweep %s: %lld jobs\n", json_string_value(json_object_get(r, "sweep")),
           (long long)json_integer_value(json_object_get(r, "count")));
}

int sphctl_cmd_sweep(sphctl *c, int argc, char **argv)
{
    static const char help[] =
        "Usage: sphctl sweep FILE --set PATH=V1,V2,... [--set PATH=VALUE]... [--id SWEEP]\n"
        "                    [--resources JSON] [--no-start] [--watch]\n"
        "Sends the case in FILE with lists of values for some of its fields; sphd creates one\n"
        "job per combination (the last list varies fastest), ids SWEEP-0, SWEEP-1, ... Prints\n"
        "each job's id, parameters and state. 'sphctl list --sweep SWEEP' shows them, 'sphctl\n"
        "export --sweep SWEEP' gives their parameters and results as one table.\n"
        "  --set PATH=V1,V2,...  vary the field at the dotted PATH over the values (split at the\n"
        "                        commas outside [], {} and \"...\"; each is JSON where it parses,\n"
        "                        else a string: kernel.type=wendland_c2,gaussian or\n"
        "                        domain.max=[1,1],[2,1]); with one value, a fixed override\n"
        "                        like submit's (repeatable; at least one with two values)\n"
        "  --id SWEEP            choose the sweep id (letters, digits, '.', '_', '-'; default:\n"
        "                        NAME-sN, a new one each time): the same sweep with the same\n"
        "                        id again returns the same jobs, another one is refused\n"
        "                        (conflict)\n"
        "  --resources JSON      as submit's, for every job; with the Slurm executor the jobs\n"
        "                        go to Slurm as one job array\n"
        "  --no-start            create the jobs paused; 'sphctl start JOB' runs one\n"
        "  --watch               then follow every job until each is done, failed or stopped:\n"
        "                        on a TTY a line per job (parameters, state, progress) redrawn\n"
        "                        in place, else the jobs' table and then a line per change of\n"
        "                        state; Ctrl-C stops watching, the jobs go on\n"
        "With --json: sphd's result, {\"sweep\", \"count\", \"jobs\": [STATUS, ...]}, on one "
        "line;\nwith --watch the same once every job has ended, with each one's final status.\n"
        "Exit codes: 0 created (with --watch: every job done), 1 refused (with --watch: or a\n"
        "job failed or was stopped: the worst job's 'watch' code), 64 usage, 65 invalid case,\n"
        "66 no such file, 69 sphd unreachable, 75 busy, 77 not authorised.\n"
        "The files the case names are sent with it, as submit's (every combination's).\n";
    static const struct option lo[] = {{"id", required_argument, NULL, 'i'},
                                       {"set", required_argument, NULL, 's'},
                                       {"no-start", no_argument, NULL, 'n'},
                                       {"resources", required_argument, NULL, 'r'},
                                       {"watch", no_argument, NULL, 'w'},
                                       {"help", no_argument, NULL, 'h'},
                                       {NULL, 0, NULL, 0}};
    static const sphctl_argspec spec = {
        help, "h", lo, "bad option", 1, 1, "sweep takes one case FILE"};
    sweep_opts so = {.sets = json_array(), .vary = json_array(), .paths = json_array()};
    int rc = sphctl_args(&spec, argc, argv, sweep_opt, &so);
    if (rc == SPHCTL_RUN && json_array_size(so.vary) == 0)
        rc = sphctl_usage("sweep", "%s",
                          "sweep needs at least one --set with two or more values (use submit "
                          "for one case)");
    json_t *root = NULL;
    sph_error err;
    if (rc == SPHCTL_RUN && sph_case_load(c->file = argv[optind], &root, &err)) {
        fprintf(stderr, "sphctl: %s\n", err.message);
        rc = err.code == SPH_ERR_IO ? SPHCTL_EX_NOINPUT : SPHCTL_EX_DATAERR;
    }
    if (rc != SPHCTL_RUN) {
        json_decref(so.sets);
        json_decref(so.vary);
        json_decref(so.paths);
        json_decref(so.resources);
        return rc;
    }
    json_t *args = json_pack("{s:o, s:o}", "case", root, "vary", so.vary);
    if ((rc = sphctl_attach_files(c, root, so.sets, so.vary, args)) != 0) {
        json_decref(args);
        json_decref(so.sets);
        json_decref(so.paths);
        json_decref(so.resources);
        return rc;
    }
    if (json_array_size(so.sets))
        json_object_set(args, "set", so.sets);
    json_decref(so.sets);
    if (so.id)
        json_object_set_new(args, "sweep", json_string(so.id));
    if (so.nostart)
        json_object_set_new(args, "start", json_false());
    if (so.resources) /* with the Slurm executor the jobs go as one job array */
        json_object_set_new(args, "resources", so.resources);
    /* --watch: listen before the jobs exist (as submit --watch does), to the sweep's jobs
     * (ID-0, ID-1, ...) when its id is given, else to every job until the reply names it */
    sphctl_stream st = {0};
    char topic[128];
    snprintf(topic, sizeof topic, "%s%s", so.id ? so.id : "", so.id ? "-" : "");
    if (so.watch && (rc = sphctl_stream_open(c, topic, &st)) != 0) {
        json_decref(args);
        json_decref(so.paths);
        return rc;
    }
    json_t *r;
    if ((rc = sphctl_request(c, "sweep", args, &r, NULL, 0)) == 0) {
        if (c->json && !so.watch)
            sphctl_print_json(r, 1);
        else if (!c->json && !(so.watch && sphctl_watch_tty(c)))
            print_sweep(r, so.paths);
        if (so.watch) {
            fflush(stdout);
            rc = sphctl_sweep_watch(c, &st, r, so.paths);
        }
        json_decref(r);
    }
    sphctl_stream_close(&st);
    json_decref(so.paths);
    return rc;
}

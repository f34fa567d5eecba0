/* sphctl: the client of sphd. This file parses the command line and runs one command. */
#include "sphctl.h"

#include "sph_case.h"

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static const char usage_text[] =
    "Usage: sphctl [--endpoint EP] [--json] [--timeout S] COMMAND [ARGS]\n"
    "\n"
    "Commands:\n"
    "  ping                          is sphd there? (round-trip time)\n"
    "  submit FILE [--id ID] [--set PATH=VALUE]... [--resources JSON] [--no-start] [--watch]\n"
    "                                send a case file (and the files it names); prints\n"
    "                                the job id\n"
    "  sweep FILE --set PATH=V1,V2,... [--set ...]... [--id SWEEP] [--resources JSON]\n"
    "        [--no-start] [--watch]  one job per combination of values; prints the jobs\n"
    "                                (--watch: then follows them all; exit 0 all done)\n"
    "  status [JOB]                  one job's state and progress, or all jobs\n"
    "  list [--sweep SWEEP]          all jobs (a sweep's jobs together), or one sweep's\n"
    "  watch JOB                     follow a job to its end (progress line on a TTY, JSON\n"
    "                                Lines otherwise); exit 0 done, 1 failed or stopped\n"
    "  start JOB                     start a job submitted with --no-start\n"
    "  step JOB N | step JOB --until T   advance a paused job by N steps or to time T, then\n"
    "                                pause it\n"
    "  pause JOB | resume JOB | stop JOB\n"
    "  set JOB PATH=VALUE...         change a running or paused job's parameters at its\n"
    "                                next step boundary (viscosity, gravity, cfl, end time,\n"
    "                                triggers)\n"
    "  query JOB [--fields pos,vel,...] [--max N]   state, diagnostics, particle fields\n"
    "  results JOB [--checksums]     the job's files: name, size, kind (CRC-32)\n"
    "  fetch JOB [--dest DIR] [--include-checkpoints]   download the job's files into\n"
    "                                DIR/JOB/, checksums verified (for another machine)\n"
    "  export JOB [--out FILE]       the diagnostics time series as CSV\n"
    "  export --sweep SWEEP [--format csv|json] [--out FILE]\n"
    "                                a sweep's parameters and results, one row per job\n"
    "  shutdown                      pause every job and stop sphd\n"
    "  keygen [--out PATH]           make a CURVE key pair for this client (or a server)\n"
    "\n"
    "Options:\n"
    "  --endpoint EP   sphd's control endpoint (default: $SPHD_ENDPOINT, else\n"
    "                  ipc://$XDG_RUNTIME_DIR/sphd/control)\n"
    "  --json          print exactly one JSON document on stdout (JSON Lines for watch)\n"
    "  --timeout S     seconds to wait for each reply (default 10)\n"
    "  --server-key K  sphd's CURVE public key (Z85, or a file holding it; default:\n"
    "                  $SPHD_SERVER_KEY, else server_key in the config file): talk CURVE\n"
    "  --key FILE      this client's CURVE secret key file (default: $SPHCTL_KEY, else key\n"
    "                  in the config file, else client.key in the config directory)\n"
    "  The config file $XDG_CONFIG_HOME/sphctl/config (~/.config/sphctl/config) holds\n"
    "  'name = value' lines: endpoint, server_key, key.\n"
    "  -h, --help      this text; 'sphctl COMMAND --help' for one command\n"
    "  (these options may also follow the command)\n"
    "  --version       print the version\n"
    "\n"
    "Exit codes: 0 ok, 1 the job failed or sphd refused the request (or a checksum\n"
    "mismatch in fetch), 64 usage, 65 invalid case file, 66 file not found, 69 sphd\n"
    "unreachable or timed out, 73 cannot write an output file, 75 busy (retry later),\n"
    "77 not authorised (sphd refused this client's key, or requires CURVE), 78 bad keys or\n"
    "config file.\n";

typedef struct command {
    const char *name;
    int (*run)(sphctl *c, int argc, char **argv);
    const char *help;
} command;

/* ---- helpers ---- */

/* Parses the options of a command that takes none but --help, and exactly nargs positionals. */
static int simple_args(int argc, char **argv, int nargs, const char *help)
{
    const sphctl_argspec spec = {
        .help = help, .optstring = "+h", .min_args = nargs, .max_args = nargs};
    return sphctl_args(&spec, argc, argv, NULL, NULL);
}

/* One job's row; a sweep's job has its params appended. */
static void print_status_line(const json_t *s)
{
    const json_t *p = json_object_get(s, "progress");
    char prog[64] = "-", eta[32] = "-", wall[32];
    double t = sphctl_num(p, "t"), te = sphctl_num(p, "t_end");
    if (isfinite(t) && isfinite(te) && te > 0)
        snprintf(prog, sizeof prog, "%.4g/%.4g s", t, te);
    sphctl_fmt_duration(sphctl_num(p, "eta"), eta, sizeof eta);
    sphctl_fmt_duration(sphctl_num(p, "wall"), wall, sizeof wall);
    printf("%-24s %-8s %-13s %-18s %10lld %9s %8s", json_string_value(json_object_get(s, "job")),
           json_string_value(json_object_get(s, "state")),
           json_string_value(json_object_get(s, "method")), prog,
           (long long)json_integer_value(json_object_get(p, "steps")), wall, eta);
    char params[1024];
    if (json_object_get(s, "sweep"))
        printf("  %s",
               sphctl_fmt_params(json_object_get(s, "params"), NULL, params, sizeof params));
    printf("\n");
}

/* The jobs table: the jobs of no sweep first, then each sweep's (in the order of its first job)
 * under a line "sweep S (N jobs)". */
static void print_status_table(const json_t *r, const void *ud)
{
    (void)ud;
    printf("%-24s %-8s %-13s %-18s %10s %9s %8s\n", "JOB", "STATE", "METHOD", "TIME", "STEPS",
           "WALL", "ETA");
    json_t *sweeps = json_object(), *order = json_array(); /* sweep -> [STATUS]; the sweeps */
    size_t i;
    json_t *s;
    json_array_foreach(json_object_get(r, "jobs"), i, s)
    {
        const char *sw = json_string_value(json_object_get(s, "sweep"));
        if (!sw) {
            print_status_line(s);
            continue;
        }
        json_t *jobs = json_object_get(sweeps, sw);
        if (!jobs) {
            json_object_set_new(sweeps, sw, jobs = json_array());
            json_array_append_new(order, json_string(sw));
        }
        json_array_append(jobs, s);
    }
    json_t *name;
    json_array_foreach(order, i, name)
    {
        const json_t *jobs = json_object_get(sweeps, json_string_value(name));
        printf("sweep %s (%zu job%s)\n", json_string_value(name), json_array_size(jobs),
               json_array_size(jobs) == 1 ? "" : "s");
        size_t k;
        json_array_foreach(jobs, k, s) print_status_line(s);
    }
    json_decref(sweeps);
    json_decref(order);
}

static void print_status_long(const json_t *s, const void *ud)
{
    (void)ud;
    const json_t *p = json_object_get(s, "progress");
    printf("job      %s\n", json_string_value(json_object_get(s, "job")));
    printf("state    %s", json_string_value(json_object_get(s, "state")));
    const char *reason = json_string_value(json_object_get(s, "reason"));
    if (reason && *reason)
        printf(" (%s)", reason);
    printf("\nmethod   %s (case '%s')\n", json_string_value(json_object_get(s, "method")),
           json_string_value(json_object_get(s, "name")));
    double t = sphctl_num(p, "t"), te = sphctl_num(p, "t_end"), rate = sphctl_num(p, "steps_per_s");
    if (isfinite(t))
        printf("time     %.6g s of %.6g s\n", t, te);
    printf("steps    %lld", (long long)json_integer_value(json_object_get(p, "steps")));
    if (isfinite(rate) && rate > 0)
        printf(" (%.0f steps/s)", rate);
    char buf[32];
    sphctl_fmt_duration(sphctl_num(p, "wall"), buf, sizeof buf);
    printf("\nwall     %s", buf);
    if (isfinite(sphctl_num(p, "eta"))) {
        sphctl_fmt_duration(sphctl_num(p, "eta"), buf, sizeof buf);
        printf(", ETA %s", buf);
    }
    printf("\ndir      %s\n", json_string_value(json_object_get(s, "dir")));
    const json_t *ps = json_object_get(s, "pending_step");
    if (json_object_get(ps, "n"))
        printf("pending  step %lld\n", (long long)json_integer_value(json_object_get(ps, "n")));
    else if (json_object_get(ps, "until"))
        printf("pending  step until t = %g s\n", sphctl_num(ps, "until"));
    const json_t *d = json_object_get(s, "diag");
    if (json_is_object(d)) {
        printf("diag    ");
        const char *k;
        json_t *v;
        json_object_foreach((json_t *)d, k, v)
        {
            if (json_is_number(v) && strcmp(k, "seq") != 0)
                printf(" %s=%.6g", k, json_number_value(v));
        }
        printf("\n");
    }
    if (json_object_get(s, "result"))
        printf("result   in %s/result.json\n", json_string_value(json_object_get(s, "dir")));
}

/* Prints a one-job result (for pause, resume, stop, start, step); ud is the verb. */
static void print_job_result(const json_t *r, const void *verb)
{
    printf("%s: %s%s\n", json_string_value(json_object_get(r, "job")),
           json_string_value(json_object_get(r, "state")), (const char *)verb);
}

/* ---- commands ---- */

static int cmd_ping(sphctl *c, int argc, char **argv)
{
    static const char help[] = "Usage: sphctl ping\nAsks sphd for a pong; prints the round trip.\n";
    int rc = simple_args(argc, argv, 0, help);
    if (rc != SPHCTL_RUN)
        return rc;
    struct timespec a, b;
    clock_gettime(CLOCK_MONOTONIC, &a);
    json_t *r;
    if ((rc = sphctl_request(c, "ping", NULL, &r, NULL, 0)))
        return rc;
    clock_gettime(CLOCK_MONOTONIC, &b);
    double ms = 1e3 * (double)(b.tv_sec - a.tv_sec) + 1e-6 * (double)(b.tv_nsec - a.tv_nsec);
    if (c->json) {
        json_object_set_new(r, "rtt_ms", json_real(ms));
        sphctl_print_json(r, 1);
    } else {
        printf("pong from %s in %.2f ms\n", c->endpoint, ms);
    }
    json_decref(r);
    return 0;
}

typedef struct submit_opts {
    const char *id;
    int watch, nostart;
    json_t *sets;
    json_t *resources;
} submit_opts;

static int submit_opt(void *ud, int o, const char *arg)
{
    submit_opts *so = ud;
    switch (o) {
    case 'i':
        so->id = arg;
        break;
    case 's':
        if (!strchr(arg, '='))
            return sphctl_usage("submit", "--set takes PATH=VALUE, not '%s'", arg);
        json_array_append_new(so->sets, json_string(arg));
        break;
    case 'n':
        so->nostart = 1;
        break;
    case 'w':
        so->watch = 1;
        break;
    case 'r':
        return sphctl_resources_opt("submit", arg, &so->resources);
    }
    return 0;
}

static int cmd_submit(sphctl *c, int argc, char **argv)
{
    static const char help[] =
        "Usage: sphctl submit FILE [--id ID] [--set PATH=VALUE]... [--resources JSON]\n"
        "                          [--no-start] [--watch]\n"
        "Sends the case in FILE to sphd and prints the job id.\n"
        "  --id ID           choose the job id (letters, digits, '.', '_', '-'): submitting\n"
        "                    the same case with the same id again returns the same job; a\n"
        "                    different case with that id is refused (conflict)\n"
        "  --set PATH=VALUE  override one field of the case by its dotted path (repeatable)\n"
        "  --resources JSON  where and with what it runs, e.g. '{\"executor\": \"slurm\",\n"
        "                    \"threads\": 4, \"time_limit\": 60, \"partition\": \"short\"}'\n"
        "                    (PROTOCOL.md: executor, threads, time_limit, partition, account,\n"
        "                    sbatch, retries)\n"
        "  --no-start        create the job paused; 'sphctl start JOB' or 'step' runs it\n"
        "  --watch           then follow it to its end like 'sphctl watch'\n"
        "The files the case names (a geometry item's \"mesh\", a wavemaker's series\n"
        "\"file\": a path relative to FILE's directory, no '..', at most 127 bytes) are\n"
        "read and sent with it (at most 8 MiB\n"
        "each and in all); sphd keeps them with the job ('sphctl results JOB': files/NAME).\n"
        "Exit codes: 0 submitted (with --watch: the job is done), 1 refused or the job failed,\n"
        "65 invalid case (or a file name it gives that is not usable, or a file too large),\n"
        "66 no such file (the case, or a file it names), 69 sphd unreachable, 75 busy.\n";
    static const struct option lo[] = {{"id", required_argument, NULL, 'i'},
                                       {"set", required_argument, NULL, 's'},
                                       {"no-start", no_argument, NULL, 'n'},
                                       {"watch", no_argument, NULL, 'w'},
                                       {"resources", required_argument, NULL, 'r'},
                                       {"help", no_argument, NULL, 'h'},
                                       {NULL, 0, NULL, 0}};
    static const sphctl_argspec spec = {
        help, "h", lo, "bad option", 1, 1, "submit takes one case FILE"};
    submit_opts so = {.sets = json_array()};
    int rc = sphctl_args(&spec, argc, argv, submit_opt, &so);
    if (rc != SPHCTL_RUN) {
        json_decref(so.sets);
        json_decref(so.resources);
        return rc;
    }
    c->file = argv[optind];
    json_t *root;
    sph_error err;
    if (sph_case_load(c->file, &root, &err)) {
        json_decref(so.sets);
        json_decref(so.resources);
        fprintf(stderr, "sphctl: %s\n", err.message);
        return err.code == SPH_ERR_IO ? SPHCTL_EX_NOINPUT : SPHCTL_EX_DATAERR;
    }
    json_t *args = json_pack("{s:o}", "case", root);
    if ((rc = sphctl_attach_files(c, root, so.sets, NULL, args)) != 0) {
        json_decref(args);
        json_decref(so.sets);
        json_decref(so.resources);
        return rc;
    }
    if (so.id)
        json_object_set_new(args, "job", json_string(so.id));
    if (so.nostart)
        json_object_set_new(args, "start", json_false());
    if (json_array_size(so.sets))
        json_object_set(args, "set", so.sets);
    json_decref(so.sets);
    if (so.resources)
        json_object_set_new(args, "resources", so.resources);
    /* --watch: listen before the job exists, so that a short one cannot end unseen */
    sphctl_stream st = {0};
    if (so.watch && (rc = sphctl_stream_open(c, so.id ? so.id : "", &st)) != 0) {
        json_decref(args);
        return rc;
    }
    json_t *r;
    if ((rc = sphctl_request(c, "submit", args, &r, NULL, 0))) {
        sphctl_stream_close(&st);
        return rc;
    }
    char job[128];
    snprintf(job, sizeof job, "%s", json_string_value(json_object_get(r, "job")));
    if (c->json && !so.watch)
        sphctl_print_json(r, 1);
    else if (!c->json)
        fprintf(so.watch ? stderr : stdout, "%s%s\n", job,
                json_is_false(json_object_get(r, "created")) ? " (already submitted)" : "");
    const int created = !json_is_false(json_object_get(r, "created"));
    json_decref(r);
    if (!so.watch)
        return 0;
    return sphctl_watch_stream(c, &st, job, created);
}

static int cmd_status(sphctl *c, int argc, char **argv)
{
    static const char help[] =
        "Usage: sphctl status [JOB]\n"
        "One job's state, progress (t / t_end, steps, wall time, steps/s, ETA) and latest\n"
        "diagnostics; without JOB, a table of all jobs (like 'list').\n";
    static const sphctl_argspec spec = {
        help, "+h", NULL, "bad option", 0, 1, "status takes at most one JOB"};
    int rc = sphctl_args(&spec, argc, argv, NULL, NULL);
    if (rc != SPHCTL_RUN)
        return rc;
    if (argc - optind == 0)
        return sphctl_show(c, "list", NULL, print_status_table, NULL);
    return sphctl_show(c, "query", json_pack("{s:s}", "job", argv[optind]), print_status_long,
                       NULL);
}

static int cmd_list(sphctl *c, int argc, char **argv)
{
    static const char help[] =
        "Usage: sphctl list [--sweep SWEEP]\n"
        "All jobs sphd holds, oldest first; the jobs of a sweep together, under a line\n"
        "'sweep SWEEP (N jobs)', each with its parameters.\n"
        "  --sweep SWEEP   only that sweep's jobs\n";
    static const struct option lo[] = {{"sweep", required_argument, NULL, 0},
                                       {"help", no_argument, NULL, 'h'},
                                       {NULL, 0, NULL, 0}};
    static const sphctl_argspec spec = {help, "+h", lo, NULL, 0, 0, NULL};
    const char *sweep = NULL;
    int rc = sphctl_args(&spec, argc, argv, sphctl_store_opt, &sweep);
    if (rc != SPHCTL_RUN)
        return rc;
    return sphctl_show(c, "list", sweep ? json_pack("{s:s}", "sweep", sweep) : NULL,
                       print_status_table, NULL);
}

static int cmd_watch(sphctl *c, int argc, char **argv)
{
    static const char help[] =
        "Usage: sphctl watch JOB\n"
        "Follows JOB until it is done, failed or stopped: a live progress line on a TTY\n"
        "(t / t_end, steps/s, ETA, key diagnostics), JSON Lines otherwise (a snapshot line,\n"
        "then the job's events). Missed events are reported as gaps.\n"
        "Exit codes: 0 done, 1 failed or stopped, 69 sphd unreachable.\n";
    int rc = simple_args(argc, argv, 1, help);
    if (rc != SPHCTL_RUN)
        return rc;
    return sphctl_watch(c, argv[optind]);
}

/* pause, resume, stop, start: one job, one op. */
static int job_op(sphctl *c, int argc, char **argv, const char *help)
{
    int rc = simple_args(argc, argv, 1, help);
    if (rc != SPHCTL_RUN)
        return rc;
    return sphctl_show(c, argv[0], json_pack("{s:s}", "job", argv[optind]), print_job_result, "");
}

static int cmd_pause(sphctl *c, int argc, char **argv)
{
    return job_op(c, argc, argv,
                  "Usage: sphctl pause JOB\nPauses JOB at the next step boundary (replies once "
                  "it is paused).\n");
}

static int cmd_resume(sphctl *c, int argc, char **argv)
{
    return job_op(c, argc, argv, "Usage: sphctl resume JOB\nRuns a paused JOB again.\n");
}

static int cmd_stop(sphctl *c, int argc, char **argv)
{
    return job_op(c, argc, argv,
                  "Usage: sphctl stop JOB\nStops JOB for good at the next step boundary.\n");
}

static int cmd_set(sphctl *c, int argc, char **argv)
{
    static const char help[] =
        "Usage: sphctl set JOB PATH=VALUE...\n"
        "Changes a running or paused job's parameters at its next step boundary (steering):\n"
        "physics.viscosity.alpha, physics.viscosity.nu, physics.delta_sph, physics.gravity (or\n"
        "physics.gravity.K), time.cfl, time.end, output.every, diagnostics.every,\n"
        "diagnostics.interval, triggers. VALUE is JSON (a bare word is a string).\n"
        "Replies once the change is made, with the step it took effect at; exit 1 when sphd\n"
        "refuses it (the reason names the path).\n";
    const sphctl_argspec spec = {.help = help, .optstring = "+h", .min_args = 2, .max_args = 33};
    int rc = sphctl_args(&spec, argc, argv, NULL, NULL);
    if (rc != SPHCTL_RUN)
        return rc;
    json_t *set = json_array();
    for (int k = optind + 1; k < argc; k++) {
        if (!strchr(argv[k], '=') || argv[k][0] == '=') {
            json_decref(set);
            return sphctl_usage("set", "an assignment is PATH=VALUE, not '%s'", argv[k]);
        }
        json_array_append_new(set, json_string(argv[k]));
    }
    json_t *r;
    if ((rc = sphctl_request(c, "set", json_pack("{s:s, s:o}", "job", argv[optind], "set", set), &r,
                             NULL, 0)))
        return rc;
    const json_t *st = json_object_get(r, "steering");
    const char *why = json_string_value(json_object_get(st, "error"));
    const json_t *hist = json_object_get(st, "history");
    const json_t *last = json_array_get(hist, json_array_size(hist) - 1);
    if (c->json)
        sphctl_print_json(r, 1);
    else if (why)
        fprintf(stderr, "sphctl: %s: the change was not made: %s\n", argv[optind], why);
    else
        printf("%s: changed at step %lld (t = %.6g s); %s\n", argv[optind],
               (long long)json_integer_value(json_object_get(last, "step")), sphctl_num(last, "t"),
               json_string_value(json_object_get(r, "state")));
    json_decref(r);
    return why ? 1 : 0;
}

static int cmd_start(sphctl *c, int argc, char **argv)
{
    return job_op(c, argc, argv,
                  "Usage: sphctl start JOB\nStarts a job submitted with --no-start.\n");
}

static int cmd_step(sphctl *c, int argc, char **argv)
{
    static const char help[] =
        "Usage: sphctl step JOB N\n"
        "       sphctl step JOB --until T\n"
        "Advances a paused (or queued) JOB by N solver steps, or to simulated time T in\n"
        "seconds, then leaves it paused.\n";
    static const struct option lo[] = {{"until", required_argument, NULL, 0},
                                       {"help", no_argument, NULL, 'h'},
                                       {NULL, 0, NULL, 0}};
    static const char bad_count[] = "step takes JOB and N, or JOB and --until T";
    static const sphctl_argspec spec = {help, "h", lo, "bad option", 1, 2, bad_count};
    const char *until = NULL;
    int rc = sphctl_args(&spec, argc, argv, sphctl_store_opt, &until);
    if (rc != SPHCTL_RUN)
        return rc;
    if ((argc - optind == 2) == (until != NULL))
        return sphctl_usage("step", "%s", bad_count);
    json_t *args = json_pack("{s:s}", "job", argv[optind]);
    char *end;
    if (until) {
        double t = strtod(until, &end);
        if (*end || end == until || !isfinite(t)) {
            json_decref(args);
            return sphctl_usage("step", "--until takes a time in seconds, not '%s'", until);
        }
        json_object_set_new(args, "until", json_real(t));
    } else {
        long n = strtol(argv[optind + 1], &end, 10);
        if (*end || n < 1) {
            json_decref(args);
            return sphctl_usage("step", "N must be a positive integer, not '%s'", argv[optind + 1]);
        }
        json_object_set_new(args, "n", json_integer(n));
    }
    return sphctl_show(c, "step", args, print_job_result, " (stepping; it pauses when done)");
}

static int cmd_query(sphctl *c, int argc, char **argv)
{
    static const char help[] =
        "Usage: sphctl query JOB [--fields pos,vel,rho,p] [--max N]\n"
        "Prints the job's state, progress and latest diagnostics as JSON; with --fields also\n"
        "the particle fields, downsampled to at most N particles with --max.\n";
    enum { FIELDS, MAX, NOPTS };
    static const struct option lo[] = {{"fields", required_argument, NULL, FIELDS},
                                       {"max", required_argument, NULL, MAX},
                                       {"help", no_argument, NULL, 'h'},
                                       {NULL, 0, NULL, 0}};
    static const sphctl_argspec spec = {help, "h", lo, "bad option", 1, 1, "query takes one JOB"};
    const char *opt[NOPTS] = {NULL};
    int rc = sphctl_args(&spec, argc, argv, sphctl_store_opt, opt);
    if (rc != SPHCTL_RUN)
        return rc;
    json_t *args = json_pack("{s:s}", "job", argv[optind]);
    if (opt[FIELDS]) {
        json_t *arr = json_array();
        char buf[512];
        snprintf(buf, sizeof buf, "%s", opt[FIELDS]);
        char *save = NULL;
        for (char *t = strtok_r(buf, ",", &save); t; t = strtok_r(NULL, ",", &save))
            json_array_append_new(arr, json_string(t));
        json_object_set_new(args, "fields", arr);
    }
    if (opt[MAX]) {
        char *end;
        long n = strtol(opt[MAX], &end, 10);
        if (*end || n < 1) {
            json_decref(args);
            return sphctl_usage("query", "--max takes a positive integer, not '%s'", opt[MAX]);
        }
        json_object_set_new(args, "max", json_integer(n));
    }
    return sphctl_show(c, "query", args, NULL, NULL);
}

static void print_shutdown(const json_t *r, const void *ud)
{
    (void)ud;
    printf("sphd is stopping; %zu unfinished job(s) kept\n",
           json_array_size(json_object_get(r, "kept")));
}

static int cmd_shutdown(sphctl *c, int argc, char **argv)
{
    static const char help[] =
        "Usage: sphctl shutdown\n"
        "Pauses every running job at a step boundary, records the jobs for a later resume,\n"
        "and stops sphd.\n";
    int rc = simple_args(argc, argv, 0, help);
    if (rc != SPHCTL_RUN)
        return rc;
    return sphctl_show(c, "shutdown", NULL, print_shutdown, NULL);
}

static const command commands[] = {
    {"ping", cmd_ping, ""},
    {"submit", cmd_submit, ""},
    {"sweep", sphctl_cmd_sweep, ""},
    {"status", cmd_status, ""},
    {"list", cmd_list, ""},
    {"watch", cmd_watch, ""},
    {"start", cmd_start, ""},
    {"step", cmd_step, ""},
    {"pause", cmd_pause, ""},
    {"resume", cmd_resume, ""},
    {"stop", cmd_stop, ""},
    {"set", cmd_set, ""},
    {"query", cmd_query, ""},
    {"shutdown", cmd_shutdown, ""},
    {"results", sphctl_cmd_results, ""},
    {"fetch", sphctl_cmd_fetch, ""},
    {"export", sphctl_cmd_export, ""},
    {"keygen", sphctl_cmd_keygen, ""},
};

int main(int argc, char **argv)
{
    sphctl c = {.timeout = 10.0};
    const char *endpoint = NULL, *server_key = NULL, *key = NULL;
    enum { OPT_ENDPOINT = 256, OPT_JSON, OPT_TIMEOUT, OPT_VERSION, OPT_SERVER_KEY, OPT_KEY };
    static const struct option lo[] = {{"endpoint", required_argument, NULL, OPT_ENDPOINT},
                                       {"json", no_argument, NULL, OPT_JSON},
                                       {"timeout", required_argument, NULL, OPT_TIMEOUT},
                                       {"server-key", required_argument, NULL, OPT_SERVER_KEY},
                                       {"key", required_argument, NULL, OPT_KEY},
                                       {"help", no_argument, NULL, 'h'},
                                       {"version", no_argument, NULL, OPT_VERSION},
                                       {NULL, 0, NULL, 0}};
    int o;
    while ((o = getopt_long(argc, argv, "+h", lo, NULL)) != -1) {
        switch (o) {
        case OPT_ENDPOINT:
            if (strlen(optarg) >= sizeof c.endpoint)
                return sphctl_usage(NULL, "endpoint too long: %s", optarg);
            endpoint = optarg;
            break;
        case OPT_SERVER_KEY:
            server_key = optarg;
            break;
        case OPT_KEY:
            key = optarg;
            break;
        case OPT_JSON:
            c.json = 1;
            break;
        case OPT_TIMEOUT: {
            char *end;
            c.timeout = strtod(optarg, &end);
            if (*end || end == optarg || !(c.timeout > 0) || c.timeout > 86400)
                return sphctl_usage(NULL, "--timeout takes seconds (0 < S <= 86400), not '%s'",
                                    optarg);
            break;
        }
        case 'h':
            fputs(usage_text, stdout);
            return 0;
        case OPT_VERSION:
            printf("sphctl %s\n", SPH_VERSION);
            return 0;
        default:
            fputs("Try 'sphctl --help'.\n", stderr);
            return SPHCTL_EX_USAGE;
        }
    }
    if (optind >= argc) {
        fputs(usage_text, stderr);
        return SPHCTL_EX_USAGE;
    }
    const char *name = argv[optind];
    /* The global options may also follow the command (`sphctl status JOB --json`): take them
     * out, leaving the command's own options (and their values) alone. */
    int n = optind + 1;
    for (int i = optind + 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--") == 0) {
            while (i < argc)
                argv[n++] = argv[i++];
            break;
        }
        if (strcmp(a, "--json") == 0) {
            c.json = 1;
            continue;
        }
        const char *val = NULL;
        int is_ep = strncmp(a, "--endpoint", 10) == 0 && (a[10] == '\0' || a[10] == '=');
        int is_to = strncmp(a, "--timeout", 9) == 0 && (a[9] == '\0' || a[9] == '=');
        int is_sk = strncmp(a, "--server-key", 12) == 0 && (a[12] == '\0' || a[12] == '=');
        int is_key = strncmp(a, "--key", 5) == 0 && (a[5] == '\0' || a[5] == '=');
        if (is_ep || is_to || is_sk || is_key) {
            const char *eq = strchr(a, '=');
            if (eq)
                val = eq + 1;
            else if (i + 1 < argc)
                val = argv[++i];
            else
                return sphctl_usage(name, "%s needs a value", a);
            if (is_sk) {
                server_key = val;
            } else if (is_key) {
                key = val;
            } else if (is_ep) {
                if (strlen(val) >= sizeof c.endpoint)
                    return sphctl_usage(name, "endpoint too long: %s", val);
                endpoint = val;
            } else {
                char *end;
                c.timeout = strtod(val, &end);
                if (*end || end == val || !(c.timeout > 0) || c.timeout > 86400)
                    return sphctl_usage(name, "--timeout takes seconds (0 < S <= 86400), not '%s'",
                                        val);
            }
            continue;
        }
        argv[n++] = argv[i];
        /* the command's options that take a value: keep the value with them */
        static const char *const with_value[] = {"--id",     "--set",       "--until", "--fields",
                                                 "--max",    "--dest",      "--out",   "--sweep",
                                                 "--format", "--resources", NULL};
        for (const char *const *w = with_value; *w; w++)
            if (strcmp(a, *w) == 0 && i + 1 < argc)
                argv[n++] = argv[++i];
    }
    argc = n;
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++) {
        if (strcmp(commands[i].name, name) == 0) {
            /* keygen needs no server (nor the keys it is about to make) */
            int rc =
                strcmp(name, "keygen") == 0 ? 0 : sphctl_settings(&c, endpoint, server_key, key);
            if (rc)
                return rc;
            rc = commands[i].run(&c, argc - optind, argv + optind);
            sphctl_close(&c);
            return rc;
        }
    }
    fprintf(stderr, "sphctl: unknown command '%s'\nTry 'sphctl --help'.\n", name);
    return SPHCTL_EX_USAGE;
}

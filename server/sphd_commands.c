/*
 * The command table and the dispatcher. Each op is one row: name, handler, argument spec, flags.
 * The dispatcher alone parses the request, checks the envelope and the arguments (with jansson's
 * strict unpacking), finds the job, refuses mutations during shutdown, calls the handler and turns
 * errors into replies: every error code of the protocol is produced here.
 */
#include "sphd.h"
#include "sphd_daemon.h"

#include "sph_case_table.h"
#include "sph_json.h"
#include "sph_sim.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* ---- the table ---- */

/* Argument types: 's' string, 'I' integer, 'F' number, 'b' boolean, 'O' object, 'A' array. */
typedef struct sphd_arg {
    const char *name;
    char type;
    int required;
} sphd_arg;

#define SPHD_MAX_ARGS 7

enum {
    CMD_JOB = 1,     /* args.job names an existing job (else not_found) */
    CMD_MUTATES = 2, /* refused while sphd shuts down */
};

typedef struct sphd_request {
    sphd_daemon *d;
    const sphd_pending *from; /* envelope + id, for deferred replies */
    json_t *args;             /* borrowed */
    sphd_job *job;            /* CMD_JOB */
    const char *raw;          /* a handler's result already encoded (borrowed), or NULL */
    char *raw_owned;          /* the same, to be freed by the dispatcher */
} sphd_request;

/* Returns 0 (result set), -1 (e set) or 1 (the reply is deferred). */
typedef int (*sphd_handler)(sphd_request *r, json_t **result, sphd_err *e);

typedef struct sphd_command {
    const char *name;
    sphd_handler handler;
    sphd_arg args[SPHD_MAX_ARGS + 1];
    unsigned flags;
    const char *help;
} sphd_command;

static int op_hello(sphd_request *r, json_t **result, sphd_err *e);
static int op_ping(sphd_request *r, json_t **result, sphd_err *e);
static int op_submit(sphd_request *r, json_t **result, sphd_err *e);
static int op_start(sphd_request *r, json_t **result, sphd_err *e);
static int op_step(sphd_request *r, json_t **result, sphd_err *e);
static int op_pause(sphd_request *r, json_t **result, sphd_err *e);
static int op_resume(sphd_request *r, json_t **result, sphd_err *e);
static int op_query(sphd_request *r, json_t **result, sphd_err *e);
static int op_stop(sphd_request *r, json_t **result, sphd_err *e);
static int op_list(sphd_request *r, json_t **result, sphd_err *e);
static int op_shutdown(sphd_request *r, json_t **result, sphd_err *e);
static int op_results(sphd_request *r, json_t **result, sphd_err *e);
static int op_fetch(sphd_request *r, json_t **result, sphd_err *e);
static int op_export(sphd_request *r, json_t **result, sphd_err *e);
static int op_sweep(sphd_request *r, json_t **result, sphd_err *e);
static int op_set(sphd_request *r, json_t **result, sphd_err *e);

static const sphd_command commands[] = {
    {"hello", op_hello, {{0}}, 0, "version, capabilities and the stream endpoint"},
    {"ping", op_ping, {{0}}, 0, "liveness"},
    {"submit",
     op_submit,
     {{"case", 'O', 1},
      {"job", 's', 0},
      {"start", 'b', 0},
      {"set", 'A', 0},
      {"resources", 'O', 0},
      {"files", 'O', 0},
      {0}},
     CMD_MUTATES,
     "create a job from a case (and the files it names)"},
    {"start",
     op_start,
     {{"job", 's', 1}, {0}},
     CMD_JOB | CMD_MUTATES,
     "start a job submitted with start: false"},
    {"step",
     op_step,
     {{"job", 's', 1}, {"n", 'I', 0}, {"until", 'F', 0}, {0}},
     CMD_JOB | CMD_MUTATES,
     "advance a paused or queued job by n steps or to a time, then pause"},
    {"pause",
     op_pause,
     {{"job", 's', 1}, {0}},
     CMD_JOB | CMD_MUTATES,
     "pause at the next step boundary"},
    {"resume", op_resume, {{"job", 's', 1}, {0}}, CMD_JOB | CMD_MUTATES, "run a paused job again"},
    {"query",
     op_query,
     {{"job", 's', 1}, {"fields", 'A', 0}, {"max", 'I', 0}, {0}},
     CMD_JOB,
     "state, progress, latest diagnostics, optionally particle fields"},
    {"stop", op_stop, {{"job", 's', 1}, {0}}, CMD_JOB, "stop a job for good"},
    {"set",
     op_set,
     {{"job", 's', 1}, {"set", 'A', 1}, {0}},
     CMD_JOB | CMD_MUTATES,
     "change a running or paused job's parameters at its next step boundary (steering)"},
    {"sweep",
     op_sweep,
     {{"case", 'O', 1},
      {"vary", 'A', 1},
      {"set", 'A', 0},
      {"sweep", 's', 0},
      {"start", 'b', 0},
      {"resources", 'O', 0},
      {"files", 'O', 0},
      {0}},
     CMD_MUTATES,
     "create one job per combination of values of some of a case's fields"},
    {"list", op_list, {{"sweep", 's', 0}, {0}}, 0, "all jobs, or a sweep's"},
    {"shutdown", op_shutdown, {{0}}, 0, "pause every job at a step boundary and exit"},
    {"results",
     op_results,
     {{"job", 's', 1}, {"checksums", 'b', 0}, {0}},
     CMD_JOB,
     "the job's files: name, size, kind, optionally CRC-32"},
    {"fetch",
     op_fetch,
     {{"job", 's', 1}, {"file", 's', 1}, {"offset", 'I', 0}, {"length", 'I', 0}, {0}},
     CMD_JOB,
     "one chunk of one of the job's files, base64"},
    {"export",
     op_export,
     {{"job", 's', 0}, {"sweep", 's', 0}, {"format", 's', 0}, {0}},
     0,
     "a job's diagnostics time series as CSV, or a sweep's table (CSV or JSON)"},
};

#define NCOMMANDS (sizeof commands / sizeof commands[0])

const char *sphd_op_name(size_t i)
{
    return i < NCOMMANDS ? commands[i].name : NULL;
}

static const sphd_command *lookup(const char *op)
{
    for (size_t i = 0; i < NCOMMANDS; i++)
        if (strcmp(commands[i].name, op) == 0)
            return &commands[i];
    return NULL;
}

static const char *type_word(char t)
{
    switch (t) {
    case 's':
        return "a string";
    case 'I':
        return "an integer";
    case 'F':
        return "a number";
    case 'b':
        return "a boolean";
    case 'O':
        return "an object";
    case 'A':
        return "an array";
    }
    return "a value";
}

static int type_ok(char t, const json_t *v)
{
    switch (t) {
    case 's':
        return json_is_string(v);
    case 'I':
        return json_is_integer(v);
    case 'F':
        return json_is_number(v);
    case 'b':
        return json_is_boolean(v);
    case 'O':
        return json_is_object(v);
    case 'A':
        return json_is_array(v);
    }
    return 1;
}

/* Checks args against the command's spec: jansson's strict unpacking decides; the table then
 * names the field at fault. */
static int check_args(const sphd_command *c, json_t *args, sphd_err *e)
{
    char fmt[8 * SPHD_MAX_ARGS + 8] = "{";
    const char *keys[SPHD_MAX_ARGS] = {0};
    int n = 0;
    for (const sphd_arg *a = c->args; a->name; a++, n++) {
        const char *conv = a->type == 'O' || a->type == 'A' ? "o" : (char[]){a->type, 0};
        size_t used = strlen(fmt);
        snprintf(fmt + used, sizeof fmt - used, "%ss%s%s", n ? ", " : "", a->required ? ":" : "?",
                 conv);
        keys[n] = a->name;
    }
    strcat(fmt, "}");
    json_error_t jerr;
    int bad = json_unpack_ex(args, &jerr, JSON_STRICT | JSON_VALIDATE_ONLY, fmt, keys[0], keys[1],
                             keys[2], keys[3], keys[4], keys[5], keys[6]);
    /* objects and arrays are 'o' for jansson: check their type here */
    for (const sphd_arg *a = c->args; !bad && a->name; a++) {
        json_t *v = json_object_get(args, a->name);
        if (v && !type_ok(a->type, v))
            bad = 1;
    }
    if (!bad)
        return 0;
    char path[SPH_ERROR_PATH_MAX];
    const char *key;
    json_t *v;
    json_object_foreach(args, key, v)
    {
        const sphd_arg *a = c->args;
        while (a->name && strcmp(a->name, key) != 0)
            a++;
        snprintf(path, sizeof path, "/args/%s", key);
        if (!a->name) {
            char list[160] = "";
            for (const sphd_arg *b = c->args; b->name; b++)
                snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s",
                         b == c->args ? "" : ", ", b->name);
            return sphd_err_set(e, SPHD_E_BAD_REQUEST, path,
                                "unknown argument '%s' for '%s' (allowed: %s)", key, c->name,
                                list[0] ? list : "none");
        }
        if (!type_ok(a->type, v))
            return sphd_err_set(e, SPHD_E_BAD_REQUEST, path, "'%s' must be %s, not %s", key,
                                type_word(a->type), sph_json_type_name(v));
    }
    for (const sphd_arg *a = c->args; a->name; a++) {
        if (a->required && !json_object_get(args, a->name)) {
            snprintf(path, sizeof path, "/args/%s", a->name);
            return sphd_err_set(e, SPHD_E_BAD_REQUEST, path, "'%s' needs the argument '%s'",
                                c->name, a->name);
        }
    }
    return sphd_err_set(e, SPHD_E_BAD_REQUEST, "/args", "bad arguments: %s", jerr.text);
}

static char *encode(json_t *reply)
{
    char *text = reply ? json_dumps(reply, JSON_COMPACT | JSON_REAL_PRECISION(12)) : NULL;
    json_decref(reply);
    return text;
}

/* {"v":1,"id":ID,"ok":true,"result":RAW} without decoding RAW again. */
static char *encode_raw(json_t *id, const char *raw)
{
    char *idtext = json_dumps(id ? id : json_null(), JSON_COMPACT | JSON_ENCODE_ANY);
    if (!idtext)
        return NULL;
    size_t n = strlen(idtext) + strlen(raw) + 64;
    char *text = malloc(n);
    if (text)
        snprintf(text, n, "{\"v\":%d,\"id\":%s,\"ok\":true,\"result\":%s}", SPHD_PROTOCOL_VERSION,
                 idtext, raw);
    free(idtext);
    return text;
}

char *sphd_dispatch(sphd_daemon *d, const sphd_pending *req, const char *body, size_t len)
{
    sphd_err e;
    json_t *result = NULL, *id = NULL;
    json_error_t jerr;
    d->requests++;
    json_t *root = json_loadb(body, len, JSON_REJECT_DUPLICATES, &jerr);
    if (!root) {
        sphd_err_set(&e, SPHD_E_BAD_REQUEST, NULL,
                     "a request must be one JSON object (UTF-8): %s at byte %d", jerr.text,
                     jerr.position);
        goto fail;
    }
    if (!json_is_object(root)) {
        sphd_err_set(&e, SPHD_E_BAD_REQUEST, "", "a request must be a JSON object, not %s",
                     sph_json_type_name(root));
        goto fail;
    }
    id = json_object_get(root, "id");
    if (id && !json_is_string(id) && !json_is_integer(id)) {
        id = NULL;
        sphd_err_set(&e, SPHD_E_BAD_REQUEST, "/id", "'id' must be a string or an integer");
        goto fail;
    }
    json_int_t v = SPHD_PROTOCOL_VERSION;
    json_t *op_j = NULL, *args = NULL, *ignored = NULL;
    if (json_unpack_ex(root, &jerr, JSON_STRICT, "{s?I, s?o, s?o, s?o}", "v", &v, "id", &ignored,
                       "op", &op_j, "args", &args)) {
        static const char *const keys[] = {"v", "id", "op", "args", NULL};
        sph_error se;
        if (sph_json_check_keys(root, "", keys, &se))
            sphd_err_set(&e, SPHD_E_BAD_REQUEST, se.path, "%s", se.message);
        else
            sphd_err_set(&e, SPHD_E_BAD_REQUEST, "/v", "'v' must be the integer %d",
                         SPHD_PROTOCOL_VERSION);
        goto fail;
    }
    if (v != SPHD_PROTOCOL_VERSION) {
        sphd_err_set(&e, SPHD_E_BAD_REQUEST, "/v",
                     "protocol version %lld is not supported (this sphd speaks %d)", (long long)v,
                     SPHD_PROTOCOL_VERSION);
        goto fail;
    }
    if (!op_j) {
        sphd_err_set(&e, SPHD_E_BAD_REQUEST, "/op", "missing 'op' (e.g. \"op\": \"ping\")");
        goto fail;
    }
    if (!json_is_string(op_j)) {
        sphd_err_set(&e, SPHD_E_BAD_REQUEST, "/op", "'op' must be a string, not %s",
                     sph_json_type_name(op_j));
        goto fail;
    }
    const char *op = json_string_value(op_j);
    const sphd_command *c = lookup(op);
    if (!c) {
        char list[256] = "";
        for (size_t i = 0; i < NCOMMANDS; i++)
            snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", i ? ", " : "",
                     commands[i].name);
        sphd_err_set(&e, SPHD_E_UNKNOWN_OP, "/op", "unknown op '%.40s' (known: %s)", op, list);
        goto fail;
    }
    if (args && !json_is_object(args)) {
        sphd_err_set(&e, SPHD_E_BAD_REQUEST, "/args", "'args' must be an object, not %s",
                     sph_json_type_name(args));
        goto fail;
    }
    json_t *empty = NULL;
    if (!args)
        args = empty = json_object();
    int rc = check_args(c, args, &e);
    sphd_request r = {.d = d, .from = req, .args = args};
    if (rc == 0 && (c->flags & CMD_MUTATES) && d->stopping)
        rc = sphd_err_set(&e, SPHD_E_BUSY, NULL, "sphd is shutting down");
    if (rc == 0 && (c->flags & CMD_JOB)) {
        const char *job = json_string_value(json_object_get(args, "job"));
        if (!(r.job = sphd_job_find(d, job)))
            rc = sphd_err_set(&e, SPHD_E_NOT_FOUND, "/args/job", "no job '%.64s'", job);
    }
    if (rc == 0) {
        sphd_pending from = *req;
        from.id = id ? id : json_null();
        from.op = c->name;
        r.from = &from;
        rc = c->handler(&r, &result, &e);
    }
    json_decref(empty);
    if (rc > 0) {
        json_decref(root);
        return NULL; /* deferred */
    }
    if (rc < 0)
        goto fail;
    if (r.raw_owned)
        r.raw = r.raw_owned;
    char *reply = r.raw ? encode_raw(id, r.raw) : encode(sphd_reply_new(id, result, NULL));
    if (r.raw)
        json_decref(result);
    free(r.raw_owned);
    json_decref(root);
    return reply;
fail:
    d->errors++;
    char *reply_e = encode(sphd_reply_new(id, result, &e));
    json_decref(root);
    return reply_e;
}

/* ---- handlers ---- */

static int op_hello(sphd_request *r, json_t **result, sphd_err *e)
{
    (void)e;
    sphd_daemon *d = r->d;
    json_t *ops = json_array();
    for (size_t i = 0; i < NCOMMANDS; i++)
        json_array_append_new(ops, json_string(commands[i].name));
    json_t *methods = json_array();
    for (int m = SPH_METHOD_KERNEL_STUDY; m < SPH_METHOD_COUNT; m++)
        if (sphd_method_available((sph_method)m))
            json_array_append_new(methods, json_string(sph_method_name((sph_method)m)));
    *result = json_pack(
        "{s:s, s:s, s:i, s:s, s:o, s:o, s:{s:I, s:i, s:i, s:i}, s:I, s:f}", "server", "sphd",
        "version", SPH_VERSION, "protocol", SPHD_PROTOCOL_VERSION, "stream", d->opts.publish, "ops",
        ops, "methods", methods, "limits", "max_msg_size", (json_int_t)d->opts.max_msg_size,
        "threads", d->opts.threads, "max_jobs", d->opts.max_jobs, "diag_rate", d->opts.diag_rate,
        "pid", (json_int_t)getpid(), "uptime", sphd_now() - d->started_at);
    /* the devices a case may name (/device): the CPU, and each GPU this sphd sees (a build with
     * CUDA); jobs on one GPU share it */
    json_t *devices = json_pack("[{s:s, s:i}]", "device", "cpu", "threads", d->opts.threads);
    const int ngpus = sph_sim_gpu_count();
    for (int k = 0; k < ngpus; k++) {
        char name[256];
        double bytes = 0.0;
        if (sph_sim_gpu_describe(k, name, sizeof name, &bytes) == 0)
            json_array_append_new(devices,
                                  json_pack("{s:s, s:i, s:s, s:f}", "device", "gpu", "index", k,
                                            "name", name, "memory_bytes", bytes));
    }
    json_object_set_new(*result, "devices", devices);
    /* where jobs run: here (worker threads) and, with --executor slurm, on a Slurm cluster */
    json_object_set_new(*result, "executors",
                        d->opts.executor_slurm ? json_pack("[s, s]", "local", "slurm")
                                               : json_pack("[s]", "local"));
    if (d->opts.executor_slurm)
        json_object_set_new(*result, "default_executor", json_string("slurm"));
    /* how the sockets are secured: "curve" (sphd --curve: authenticated and encrypted) */
    json_object_set_new(*result, "security", json_string(d->curve ? "curve" : "none"));
    /* what the physics options mean where a job's figures depend on them */
    json_object_set_new(
        *result, "physics",
        json_pack("{s:o*, s:o*, s:o*, s:s}", "viscosity",
                  sph_case_field_names("/physics/viscosity/type"), "boundary",
                  sph_case_field_names("/boundary/type"), "initial",
                  sph_case_field_names("/initial/type"), "monaghan_alpha",
                  "alpha = 2 (dim + 2) nu / (h c0), reported per job in result.viscosity.alpha"));
    return 0;
}

static int op_ping(sphd_request *r, json_t **result, sphd_err *e)
{
    (void)r;
    (void)e;
    *result = json_pack("{s:b, s:f}", "pong", 1, "time", sphd_now());
    return 0;
}

/* A job's `resources`: known fields, and the Slurm executor only where sphd has it. */
static int check_resources(const sphd_daemon *d, const json_t *res, sphd_err *e)
{
    if (!res)
        return 0;
    if (sphd_resources_check(res, "/args/resources", e))
        return -1;
    const char *ex = json_string_value(json_object_get(res, "executor"));
    if (ex && strcmp(ex, "slurm") == 0 && !d->opts.executor_slurm)
        return sphd_err_set(e, SPHD_E_BAD_REQUEST, "/args/resources/executor",
                            "this sphd has no Slurm executor: start it with --executor slurm");
    return 0;
}

static int op_submit(sphd_request *r, json_t **result, sphd_err *e)
{
    sphd_daemon *d = r->d;
    json_t *case_in = json_object_get(r->args, "case");
    json_t *jid = json_object_get(r->args, "job");
    json_t *sets = json_object_get(r->args, "set");
    json_t *start_j = json_object_get(r->args, "start");
    const int start = start_j ? json_is_true(start_j) : 1;
    const char *id = jid ? json_string_value(jid) : NULL;
    if (id && !sphd_job_id_ok(id))
        return sphd_err_set(e, SPHD_E_BAD_REQUEST, "/args/job",
                            "job id '%.64s' is not usable as a file name: use 1-%d letters, "
                            "digits, '.', '_' or '-', not starting with '.'",
                            id, SPHD_JOB_ID_MAX - 1);
    if (check_resources(d, json_object_get(r->args, "resources"), e))
        return -1;
    json_t *c = json_deep_copy(case_in);
    if (!c)
        return sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
    if (sphd_apply_sets(c, sets, e) != 0) {
        json_decref(c);
        return -1;
    }
    /* the files the case names: exactly those, intact */
    sphd_inputs in;
    unsigned char used[SPH_INPUT_MAX_COUNT] = {0};
    if (sphd_inputs_decode(json_object_get(r->args, "files"), &in, e) != 0) {
        json_decref(c);
        return -1;
    }
    if (sphd_inputs_match(c, &in, used, e) != 0 || sphd_inputs_unused(&in, used, e) != 0) {
        sphd_inputs_free(&in);
        json_decref(c);
        return -1;
    }
    sphd_job *j = id ? sphd_job_find(d, id) : NULL;
    if (j) {
        const int same = json_equal(j->case_json, c);
        const int same_files = same && sphd_inputs_same(j->dir, c, &in);
        sphd_inputs_free(&in);
        json_decref(c);
        if (!same)
            return sphd_err_set(e, SPHD_E_CONFLICT, "/args/case",
                                "job '%s' exists with a different case; choose another id", id);
        if (!same_files)
            return sphd_err_set(e, SPHD_E_CONFLICT, "/args/files",
                                "job '%s' exists with the same case but other files (their "
                                "bytes differ); choose another id",
                                id);
        *result = sphd_job_status(j);
        json_object_set_new(*result, "created", json_false());
        return 0;
    }
    j = sphd_job_submit(d, id, c, start, NULL, NULL, json_object_get(r->args, "resources"), &in, e);
    sphd_inputs_free(&in);
    json_decref(c);
    if (!j)
        return -1;
    *result = sphd_job_status(j);
    json_object_set_new(*result, "created", json_true());
    sphd_jobs_schedule(d);
    return 0;
}

static int final_state_error(const sphd_job *j, const char *op, sphd_err *e)
{
    return sphd_err_set(e, SPHD_E_BAD_STATE, "/args/job", "cannot %s job %s: it is %s", op, j->id,
                        sphd_job_state_name(j->state));
}

static int reply_status(sphd_request *r, json_t **result)
{
    sphd_jobs_schedule(r->d);
    *result = sphd_job_status(r->job);
    return 0;
}

static int defer_until_run_ends(sphd_request *r, sphd_err *e)
{
    sphd_pending *p = sphd_pending_copy(r->from);
    if (!p)
        return sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
    p->next = r->job->waiters;
    r->job->waiters = p;
    return 1;
}

static int op_start(sphd_request *r, json_t **result, sphd_err *e)
{
    sphd_job *j = r->job;
    if (sphd_job_state_final(j->state))
        return final_state_error(j, "start", e);
    if (j->state == SPHD_JOB_PAUSED) {
        if (j->started)
            return sphd_err_set(e, SPHD_E_BAD_STATE, "/args/job",
                                "job %s was started and is paused: use resume", j->id);
        j->started = 1;
        sphd_job_set_state(r->d, j, SPHD_JOB_QUEUED, NULL);
    }
    return reply_status(r, result);
}

static int op_step(sphd_request *r, json_t **result, sphd_err *e)
{
    sphd_job *j = r->job;
    json_t *n = json_object_get(r->args, "n"), *until = json_object_get(r->args, "until");
    if (!n == !until)
        return sphd_err_set(e, SPHD_E_BAD_REQUEST, "/args",
                            "step takes either 'n' (steps) or 'until' (a time in s)");
    if (n && json_integer_value(n) < 1)
        return sphd_err_set(e, SPHD_E_BAD_REQUEST, "/args/n", "'n' must be at least 1");
    if (until && !isfinite(json_number_value(until)))
        return sphd_err_set(e, SPHD_E_BAD_REQUEST, "/args/until", "'until' must be finite");
    if (sphd_job_state_final(j->state))
        return final_state_error(j, "step", e);
    if (j->state == SPHD_JOB_RUNNING)
        return sphd_err_set(e, SPHD_E_BAD_STATE, "/args/job",
                            "job %s is running: pause it before stepping it", j->id);
    j->step_n = n ? (long)json_integer_value(n) : 0;
    j->step_until = until ? json_number_value(until) : INFINITY;
    sphd_job_touch(j);
    return reply_status(r, result);
}

/* A Slurm job whose runner has not said hello yet (pending in Slurm's queue, or starting). */
static int waiting_in_slurm(const sphd_job *j)
{
    return j->worker == SPHD_WORKER_REMOTE && !j->runner_seen;
}

/* Cancels a job's Slurm job that has not started running: it is paused or stopped at once
 * (a later resume submits a new one, from the checkpoint if the job ever ran). */
static void cancel_remote(sphd_daemon *d, sphd_job *j, sphd_job_state to)
{
    if (j->slurm_id[0]) { /* else sbatch has not answered: its answer cancels it */
        sphd_scmd cmd = {.kind = SPHD_S_CANCEL, .arg = strdup(j->slurm_id)};
        if (cmd.arg)
            sphd_slurm_send(d, &cmd);
    }
    j->worker = -1;
    j->stepping = 0;
    sphd_job_set_state(d, j, to, NULL);
}

static int op_pause(sphd_request *r, json_t **result, sphd_err *e)
{
    sphd_job *j = r->job;
    if (sphd_job_state_final(j->state))
        return final_state_error(j, "pause", e);
    /* a pending `step` is cancelled too: paused means it does not run */
    j->step_n = 0;
    j->step_until = INFINITY;
    sphd_job_touch(j);
    if (j->state == SPHD_JOB_QUEUED) {
        sphd_job_set_state(r->d, j, SPHD_JOB_PAUSED, NULL);
    } else if (j->state == SPHD_JOB_RUNNING && waiting_in_slurm(j)) {
        cancel_remote(r->d, j, SPHD_JOB_PAUSED);
    } else if (j->state == SPHD_JOB_RUNNING) {
        if (!j->pause_requested) {
            /* journaled first: a pause its runner may act on is never forgotten by a restart */
            j->pause_requested = 1;
            sphd_job_journal_requests(r->d, j);
            sphd_wcmd cmd = {.kind = SPHD_W_PAUSE, .job = j};
            if (sphd_jobs_send(r->d, j, &cmd) != 0) {
                j->pause_requested = 0;
                sphd_job_journal_requests(r->d, j);
                return sphd_err_set(e, SPHD_E_INTERNAL, NULL, "cannot reach the job's runner");
            }
        }
        return defer_until_run_ends(r, e);
    }
    return reply_status(r, result);
}

/* Steering (PROTOCOL.md 3.12): the assignments checked (steerable fields, values the case
 * accepts), then made at the job's next step boundary: a running job's run ends there
 * (SPHD_W_STEER) and the loop makes the change and runs it on; a job whose simulation is in
 * memory and not running is changed at once. The reply is the job's status once the change is
 * made (or refused: its "steering" says why). */
static int op_set(sphd_request *r, json_t **result, sphd_err *e)
{
    sphd_job *j = r->job;
    const json_t *set = json_object_get(r->args, "set");
    if (sphd_job_state_final(j->state))
        return final_state_error(j, "set", e);
    if (!sph_case_is_sim(j->c))
        return sphd_err_set(e, SPHD_E_BAD_REQUEST, "/args/job",
                            "job %s is a kernel study: it has no parameters to change", j->id);
    if (j->slurm)
        return sphd_err_set(e, SPHD_E_BAD_REQUEST, "/args/job",
                            "job %s runs on Slurm: a Slurm job is not steered in this version "
                            "(its state lives on its node); pause it, or submit another",
                            j->id);
    if (j->c->sim.device != SPH_DEVICE_CPU)
        return sphd_err_set(e, SPHD_E_BAD_REQUEST, "/args/job",
                            "job %s runs on the GPU: a GPU job is not steered in this version "
                            "(the device's copy of the parameters is made once)",
                            j->id);
    const size_t n = json_array_size(set);
    if (n < 1 || n > 32)
        return sphd_err_set(e, SPHD_E_BAD_REQUEST, "/args/set",
                            "'set' holds 1 to 32 assignments \"path=value\"");
    json_t *next = json_deep_copy(j->case_now ? j->case_now : j->case_json);
    if (!next)
        return sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
    for (size_t k = 0; k < n; k++) {
        char at[32], path[256];
        snprintf(at, sizeof at, "/args/set/%zu", k);
        const char *a = json_string_value(json_array_get(set, k));
        const char *eq = a ? strchr(a, '=') : NULL;
        sph_error err;
        sph_error_clear(&err);
        if (!eq || eq == a || (size_t)(eq - a) >= sizeof path) {
            json_decref(next);
            return sphd_err_set(e, SPHD_E_BAD_REQUEST, at,
                                "an assignment is a string \"path=value\" "
                                "(physics.viscosity.alpha=0.05)");
        }
        snprintf(path, sizeof path, "%.*s", (int)(eq - a), a);
        if (sph_case_steerable(path, &err) || sph_json_apply_set(next, a, &err)) {
            json_decref(next);
            return sphd_err_set(e, SPHD_E_BAD_REQUEST, at, "%s", err.message);
        }
    }
    sph_case *tmp = calloc(1, sizeof *tmp);
    sph_error err;
    sph_error_clear(&err);
    const int bad = !tmp || sph_case_from_json(next, tmp, &err) != 0;
    if (bad || j->steer_set) {
        json_decref(next);
        if (tmp) {
            sph_case_clear(tmp);
            free(tmp);
        }
    }
    if (bad)
        return tmp ? sphd_err_set(e, SPHD_E_INVALID_CASE, err.path, "%s", err.message)
                   : sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
    if (j->steer_set) {
        return sphd_err_set(e, SPHD_E_BUSY, "/args/job",
                            "a change to job %s waits for its next step boundary; ask again",
                            j->id);
    }
    if (!(j->state == SPHD_JOB_RUNNING && j->worker >= 0) && !j->exec) {
        json_decref(next);
        sph_case_clear(tmp);
        free(tmp);
        return sphd_err_set(e, SPHD_E_BAD_STATE, "/args/job",
                            "job %s has no simulation in memory (it has not started, or sphd "
                            "restarted since it ran): start or resume it, then change it",
                            j->id);
    }
    j->steer_set = json_deep_copy(set);
    j->steer_case = next;
    j->steer_next = tmp; /* parsed once, here */
    j->steer_error[0] = '\0';
    sphd_job_touch(j);
    if (j->state == SPHD_JOB_RUNNING && j->worker >= 0) {
        /* a `step` run ends at its target, where the change is made; any other is ended now */
        if (!j->stepping) {
            sphd_wcmd cmd = {.kind = SPHD_W_STEER, .job = j};
            if (sphd_jobs_send(r->d, j, &cmd) != 0) {
                sphd_job_steer_drop(j);
                return sphd_err_set(e, SPHD_E_INTERNAL, NULL, "cannot reach the job's runner");
            }
        }
        return defer_until_run_ends(r, e);
    }
    if (sphd_job_steer_apply(r->d, j, e) != 0)
        return -1;
    return reply_status(r, result);
}

static int op_resume(sphd_request *r, json_t **result, sphd_err *e)
{
    sphd_job *j = r->job;
    if (sphd_job_state_final(j->state))
        return final_state_error(j, "resume", e);
    if (j->state == SPHD_JOB_PAUSED) {
        j->step_n = 0;
        j->step_until = INFINITY;
        sphd_job_touch(j);
        j->started = 1;
        sphd_job_set_state(r->d, j, SPHD_JOB_QUEUED, NULL);
    } else if (j->state == SPHD_JOB_RUNNING) {
        if (j->pause_requested) {
            j->pause_requested = 0; /* the run's end will queue it again */
            sphd_job_journal_requests(r->d, j);
        }
        j->stepping = 0;
    }
    return reply_status(r, result);
}

static int op_stop(sphd_request *r, json_t **result, sphd_err *e)
{
    sphd_job *j = r->job;
    if (j->state == SPHD_JOB_DONE || j->state == SPHD_JOB_FAILED)
        return final_state_error(j, "stop", e);
    if (j->state == SPHD_JOB_QUEUED || j->state == SPHD_JOB_PAUSED) {
        sphd_job_set_state(r->d, j, SPHD_JOB_STOPPED, NULL);
    } else if (j->state == SPHD_JOB_RUNNING && waiting_in_slurm(j)) {
        cancel_remote(r->d, j, SPHD_JOB_STOPPED);
    } else if (j->state == SPHD_JOB_RUNNING) {
        if (!j->stop_requested) {
            j->stop_requested = 1;
            sphd_job_journal_requests(r->d, j);
            sphd_wcmd cmd = {.kind = SPHD_W_STOP, .job = j};
            if (sphd_jobs_send(r->d, j, &cmd) != 0) {
                j->stop_requested = 0;
                sphd_job_journal_requests(r->d, j);
                return sphd_err_set(e, SPHD_E_INTERNAL, NULL, "cannot reach the job's runner");
            }
        }
        return defer_until_run_ends(r, e);
    }
    return reply_status(r, result);
}

static int op_query(sphd_request *r, json_t **result, sphd_err *e)
{
    sphd_daemon *d = r->d;
    sphd_job *j = r->job;
    json_t *fields = json_object_get(r->args, "fields"), *max_j = json_object_get(r->args, "max");
    long max = max_j ? (long)json_integer_value(max_j) : 0;
    if (max_j && max < 1)
        return sphd_err_set(e, SPHD_E_BAD_REQUEST, "/args/max", "'max' must be at least 1");
    if (max_j && !fields)
        return sphd_err_set(e, SPHD_E_BAD_REQUEST, "/args/max", "'max' goes with 'fields'");
    size_t i;
    json_t *f;
    json_array_foreach(fields, i, f)
    {
        if (!json_is_string(f)) {
            char path[48];
            snprintf(path, sizeof path, "/args/fields/%zu", i);
            return sphd_err_set(e, SPHD_E_BAD_REQUEST, path, "field names are strings, not %s",
                                sph_json_type_name(f));
        }
    }
    if (fields && sphd_job_state_final(j->state))
        return sphd_err_set(e, SPHD_E_BAD_STATE, "/args/fields",
                            "job %s is %s: its particles are gone (outputs are in %s)", j->id,
                            sphd_job_state_name(j->state), j->dir);
    if (fields && !j->exec && j->worker == -1 && !j->slurm && !j->resume)
        return sphd_err_set(e, SPHD_E_BAD_STATE, "/args/fields",
                            "job %s has not run yet: its particles are made when it first runs "
                            "(step it once)",
                            j->id);
    if (fields && waiting_in_slurm(j))
        return sphd_err_set(e, SPHD_E_BAD_STATE, "/args/fields",
                            "job %s waits in Slurm's queue (Slurm job %s): its particles are made "
                            "when its runner starts",
                            j->id, j->slurm_id);
    if (fields && j->worker == -1 && j->slurm && !d->files_started)
        return sphd_err_set(e, SPHD_E_BAD_STATE, "/args/fields",
                            "job %s runs on the Slurm executor and is not running: its particles "
                            "are in its checkpoint (resume or step it, then ask)",
                            j->id);
    if (fields && (j->worker != -1 || d->files_started)) {
        /* the thread that may read the executor answers and encodes the reply: the job's
         * worker between two slices while it runs, else the files thread */
        json_t *s = sphd_job_status(j);
        if (s)
            json_object_set(s, "diag", j->diag ? j->diag : json_null());
        sphd_pending *p = sphd_pending_copy(r->from);
        json_t *status = s ? json_deep_copy(s) : NULL, *id = json_deep_copy(r->from->id);
        json_t *names = json_deep_copy(fields); /* the thread's own copies */
        json_decref(s);
        if (!p || !status || !id || !names) {
            sphd_pending_free(p);
            json_decref(status);
            json_decref(id);
            json_decref(names);
            return sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
        }
        if (j->worker == -1) {
            sphd_pending_free(p);
            sphd_fcmd cmd = {.kind = SPHD_F_PARTICLES,
                             .job = j,
                             .exec = j->exec, /* NULL on the Slurm executor: the checkpoint */
                             .fields = names,
                             .status = status,
                             .id = id,
                             .max = max};
            return sphd_files_send(d, &cmd, r->from, e);
        }
        p->token = ++d->next_token;
        snprintf(p->job, sizeof p->job, "%s", j->id);
        sphd_wcmd cmd = {.kind = SPHD_W_PARTICLES,
                         .job = j,
                         .fields = names,
                         .max = max,
                         .token = p->token,
                         .status = status,
                         .id = id};
        if (sphd_jobs_send(d, j, &cmd) != 0) {
            json_decref(cmd.fields); /* still ours (the wire send takes them only on success) */
            json_decref(cmd.status);
            json_decref(cmd.id);
            sphd_pending_free(p);
            return sphd_err_set(e, SPHD_E_INTERNAL, NULL, "cannot reach the job's worker");
        }
        p->next = d->particle_waits;
        d->particle_waits = p;
        return 1;
    }
    if (!fields && j->query_text) {
        r->raw = j->query_text; /* status queries come often: encoded once per change */
        return 0;
    }
    json_t *s = sphd_job_status(j);
    if (!s)
        return sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
    json_object_set(s, "diag", j->diag ? j->diag : json_null());
    if (j->result)
        json_object_set(s, "result", j->result);
    if (!fields) {
        j->query_text = json_dumps(s, JSON_COMPACT | JSON_REAL_PRECISION(12));
        if (j->query_text) {
            json_decref(s);
            r->raw = j->query_text;
            return 0;
        }
    }
    if (fields) { /* the unit tests' daemon, without threads */
        json_t *parts = sphd_particles(j->exec, j->c, fields, max, e);
        if (!parts) {
            json_decref(s);
            return -1;
        }
        json_object_set_new(s, "particles", parts);
    }
    *result = s;
    return 0;
}

static int op_list(sphd_request *r, json_t **result, sphd_err *e)
{
    (void)result;
    /* {"jobs":[STATUS,...]} from each job's encoded status, kept until the job changes */
    const char *sweep = json_string_value(json_object_get(r->args, "sweep"));
    if (sweep) {
        const sphd_job *j = r->d->jobs;
        while (j && strcmp(j->sweep, sweep) != 0)
            j = j->next;
        if (!j)
            return sphd_err_set(e, SPHD_E_NOT_FOUND, "/args/sweep", "no sweep '%.64s'", sweep);
    }
    size_t n = 16;
    for (sphd_job *j = r->d->jobs; j; j = j->next) {
        if (sweep && strcmp(j->sweep, sweep) != 0)
            continue;
        if (!j->status_text) {
            json_t *s = sphd_job_status(j);
            j->status_text = s ? json_dumps(s, JSON_COMPACT | JSON_REAL_PRECISION(12)) : NULL;
            json_decref(s);
            if (!j->status_text)
                return sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
        }
        n += strlen(j->status_text) + 1;
    }
    char *text = malloc(n);
    if (!text)
        return sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
    char *p = text;
    p += sprintf(p, "{\"jobs\":[");
    int first = 1;
    for (sphd_job *j = r->d->jobs; j; j = j->next) {
        if (sweep && strcmp(j->sweep, sweep) != 0)
            continue;
        p += sprintf(p, "%s%s", first ? "" : ",", j->status_text);
        first = 0;
    }
    strcpy(p, "]}");
    r->raw_owned = text;
    return 0;
}

static int op_shutdown(sphd_request *r, json_t **result, sphd_err *e)
{
    (void)result;
    sphd_daemon *d = r->d;
    sphd_pending *p = sphd_pending_copy(r->from);
    if (!p)
        return sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
    p->next = d->shutdown_waits;
    d->shutdown_waits = p;
    sphd_log("shutdown requested");
    d->stopping = 1;
    return 1; /* answered by the loop once every job is paused */
}

/* results, fetch and export read files: on the files thread when it runs (deferred reply),
 * else here (the unit tests' daemon has no threads) */
static int files_request(sphd_request *r, sphd_fcmd *cmd, json_t **result, sphd_err *e)
{
    cmd->job = r->job;
    if (r->d->files_started)
        return sphd_files_send(r->d, cmd, r->from, e);
    *result = sphd_files_do(cmd, e);
    free(cmd->file);
    return *result ? 0 : -1;
}

static int op_results(sphd_request *r, json_t **result, sphd_err *e)
{
    sphd_fcmd cmd = {.kind = SPHD_F_LIST,
                     .checksums = json_is_true(json_object_get(r->args, "checksums"))};
    return files_request(r, &cmd, result, e);
}

static int op_fetch(sphd_request *r, json_t **result, sphd_err *e)
{
    json_t *off_j = json_object_get(r->args, "offset"), *len_j = json_object_get(r->args, "length");
    json_int_t offset = off_j ? json_integer_value(off_j) : 0;
    json_int_t length = len_j ? json_integer_value(len_j) : SPHD_FETCH_DEFAULT;
    if (offset < 0)
        return sphd_err_set(e, SPHD_E_BAD_REQUEST, "/args/offset", "'offset' must be at least 0");
    if (length < 1 || length > SPHD_FETCH_MAX)
        return sphd_err_set(e, SPHD_E_BAD_REQUEST, "/args/length",
                            "'length' must be in [1, %ld] (bytes)", SPHD_FETCH_MAX);
    sphd_fcmd cmd = {.kind = SPHD_F_FETCH,
                     .file = strdup(json_string_value(json_object_get(r->args, "file"))),
                     .offset = (long long)offset,
                     .length = (long)length};
    if (!cmd.file)
        return sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
    return files_request(r, &cmd, result, e);
}

static int op_export(sphd_request *r, json_t **result, sphd_err *e)
{
    json_t *fmt = json_object_get(r->args, "format");
    const char *job = json_string_value(json_object_get(r->args, "job"));
    const char *sweep = json_string_value(json_object_get(r->args, "sweep"));
    if (!job == !sweep)
        return sphd_err_set(e, SPHD_E_BAD_REQUEST, job ? "/args/sweep" : "/args/job",
                            "export takes 'job' (its diagnostics) or 'sweep' (its table)%s",
                            job ? ", not both" : "");
    if (sweep) {
        const char *f = fmt ? json_string_value(fmt) : "csv";
        if (strcmp(f, "csv") != 0 && strcmp(f, "json") != 0)
            return sphd_err_set(e, SPHD_E_BAD_REQUEST, "/args/format",
                                "unknown format '%.32s' (known: csv, json)", f);
        /* a few numbers per job, from memory: no file is read */
        *result = sphd_sweep_table(r->d, sweep, strcmp(f, "csv") == 0, e);
        return *result ? 0 : -1;
    }
    if (fmt && strcmp(json_string_value(fmt), "csv") != 0)
        return sphd_err_set(e, SPHD_E_BAD_REQUEST, "/args/format",
                            "unknown format '%.32s' (known: csv)", json_string_value(fmt));
    if (!(r->job = sphd_job_find(r->d, job)))
        return sphd_err_set(e, SPHD_E_NOT_FOUND, "/args/job", "no job '%.64s'", job);
    sphd_fcmd cmd = {.kind = SPHD_F_EXPORT};
    return files_request(r, &cmd, result, e);
}

static int op_sweep(sphd_request *r, json_t **result, sphd_err *e)
{
    sphd_daemon *d = r->d;
    json_t *sid = json_object_get(r->args, "sweep"), *start_j = json_object_get(r->args, "start");
    const int start = start_j ? json_is_true(start_j) : 1;
    json_t *res = json_object_get(r->args, "resources");
    if (check_resources(d, res, e))
        return -1;
    json_t *params = NULL;
    json_t *cases =
        sphd_sweep_expand(json_object_get(r->args, "case"), json_object_get(r->args, "set"),
                          json_object_get(r->args, "vary"), &params, e);
    if (!cases)
        return -1;
    const size_t n = json_array_size(cases);
    char sweep[SPHD_JOB_ID_MAX - 8] = "";
    /* the files the cases name: every one a combination names, and no other */
    sphd_inputs in;
    unsigned char used[SPH_INPUT_MAX_COUNT] = {0};
    int rc = sphd_inputs_decode(json_object_get(r->args, "files"), &in, e);
    for (size_t i = 0; rc == 0 && i < n; i++)
        rc = sphd_inputs_match(json_array_get(cases, i), &in, used, e);
    if (rc == 0)
        rc = sphd_inputs_unused(&in, used, e);
    if (rc == 0 && sid) {
        if (strlen(json_string_value(sid)) >= sizeof sweep ||
            !sphd_job_id_ok(json_string_value(sid)))
            rc = sphd_err_set(e, SPHD_E_BAD_REQUEST, "/args/sweep",
                              "sweep id '%.64s' is not usable: use 1-%zu letters, digits, '.', "
                              "'_' or '-', not starting with '.' (its jobs are ID-0, ID-1, ...)",
                              json_string_value(sid), sizeof sweep - 1);
        else
            snprintf(sweep, sizeof sweep, "%s", json_string_value(sid));
    } else if (rc == 0) {
        /* NAME-sN, unused in memory and on disk */
        const char *name = json_string_value(json_object_get(json_array_get(cases, 0), "name"));
        for (long k = 1;; k++) {
            snprintf(sweep, sizeof sweep, "%.30s-s%ld",
                     name && sphd_job_id_ok(name) ? name : "sweep", k);
            char id[SPHD_JOB_ID_MAX + 32], dir[SPHD_PATH_MAX + 128];
            snprintf(id, sizeof id, "%s-0", sweep);
            snprintf(dir, sizeof dir, "%s/jobs/%s", d->opts.state_dir, id);
            if (!sphd_job_find(d, id) && access(dir, F_OK) != 0)
                break;
        }
    }
    /* all or nothing: every id free (or the same job again), every case valid, room for all */
    size_t fresh = 0;
    for (size_t i = 0; rc == 0 && i < n; i++) {
        char id[SPHD_JOB_ID_MAX + 32];
        snprintf(id, sizeof id, "%s-%zu", sweep, i);
        sphd_job *j = sphd_job_find(d, id);
        if (j && !json_equal(j->case_json, json_array_get(cases, i)))
            rc = sphd_err_set(e, SPHD_E_CONFLICT, "/args/sweep",
                              "job '%s' exists with a different case; choose another sweep id", id);
        else if (j && !sphd_inputs_same(j->dir, json_array_get(cases, i), &in))
            rc = sphd_err_set(e, SPHD_E_CONFLICT, "/args/files",
                              "job '%s' exists with the same case but other files (their bytes "
                              "differ); choose another sweep id",
                              id);
        fresh += !j;
    }
    if (rc == 0 && d->njobs_active + (long)fresh > d->opts.max_jobs)
        rc = sphd_err_set(e, SPHD_E_BUSY, NULL,
                          "the sweep's %zu new jobs do not fit: sphd holds %d of at most %d jobs "
                          "(--max-jobs)",
                          fresh, d->njobs_active, d->opts.max_jobs);
    /* each combination's meshes are read as its job will read them, from the files written
     * to a scratch directory in the state directory: a mesh that does not read (or does not
     * fit the combination's domain) refuses the sweep before any job is made */
    char scratch[SPHD_PATH_MAX + 64] = "";
    if (rc == 0 && in.n > 0) {
        snprintf(scratch, sizeof scratch, "%s/.sweep-check.XXXXXX", d->opts.state_dir);
        if (!mkdtemp(scratch)) {
            rc = sphd_err_set(e, SPHD_E_INTERNAL, NULL, "cannot create %s: %s", scratch,
                              strerror(errno));
            scratch[0] = '\0';
        }
    }
    for (size_t i = 0; rc == 0 && i < n; i++) {
        sph_case *tmp = calloc(1, sizeof *tmp);
        sph_error err;
        sph_error_clear(&err);
        const json_t *ci = json_array_get(cases, i);
        char files[SPHD_PATH_MAX + 96];
        int bad = !tmp ? 0 : sph_case_from_json(ci, tmp, &err) != 0;
        if (tmp && !bad && scratch[0]) {
            if (sphd_inputs_write(scratch, ci, &in, e) != 0 ||
                sphd_inputs_dir(scratch, files, sizeof files) != 0)
                rc = -1;
            else
                bad = sph_case_load_files(tmp, files, NULL, &err) != 0;
            sphd_inputs_remove(scratch, ci);
        }
        if (rc) {
            /* e says why */
        } else if (!tmp) {
            rc = sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
        } else if (bad) {
            char *p = json_dumps(json_array_get(params, i), JSON_COMPACT | JSON_REAL_PRECISION(12));
            rc = sphd_err_set(e, SPHD_E_INVALID_CASE, err.path, "combination %zu %s: %s", i,
                              p ? p : "", err.message);
            free(p);
        } else if (sph_case_is_sim(tmp)) {
            long nf = 0, nb = 0;
            const double bytes = sph_sim_estimate_bytes(&tmp->sim, &nf, &nb);
            if (bytes > tmp->sim.max_bytes)
                rc = sphd_err_set(e, SPHD_E_TOO_LARGE, "/dx",
                                  "combination %zu needs about %.0f MB (%ld fluid and %ld "
                                  "boundary particles), more than the %.0f MB allowed",
                                  i, bytes / 1e6, nf, nb, tmp->sim.max_bytes / 1e6);
        }
        sph_case_clear(tmp);
        free(tmp);
    }
    if (scratch[0])
        rmdir(scratch);
    json_t *jobs = rc == 0 ? json_array() : NULL;
    if (rc == 0 && !jobs)
        rc = sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
    sphd_job **made = rc == 0 ? calloc(n, sizeof *made) : NULL;
    size_t nmade = 0;
    if (rc == 0 && !made)
        rc = sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
    for (size_t i = 0; rc == 0 && i < n; i++) {
        char id[SPHD_JOB_ID_MAX + 32];
        snprintf(id, sizeof id, "%s-%zu", sweep, i);
        sphd_job *j = sphd_job_find(d, id);
        const int created = !j;
        if (!j) {
            j = sphd_job_submit(d, id, json_array_get(cases, i), start, sweep,
                                json_array_get(params, i), res, &in, e);
            if (j && j->slurm && start) { /* one Slurm array for them all, below */
                j->held = 1;
                made[nmade++] = j;
            }
        }
        if (!j) { /* the disk: the jobs made so far stay */
            rc = -1;
            break;
        }
        json_array_append_new(jobs, json_boolean(created)); /* the status comes below */
    }
    json_decref(cases);
    json_decref(params);
    sphd_inputs_free(&in);
    if (nmade > 0) {
        sphd_err ae;
        if (sphd_jobs_start_array(d, made, nmade, sweep, &ae) != 0 && rc == 0) {
            *e = ae;
            rc = -1;
        }
    }
    free(made);
    if (rc) {
        json_decref(jobs);
        return rc;
    }
    for (size_t i = 0; i < json_array_size(jobs); i++) {
        char id[SPHD_JOB_ID_MAX + 32];
        snprintf(id, sizeof id, "%s-%zu", sweep, i);
        json_t *s = sphd_job_status(sphd_job_find(d, id));
        if (s)
            json_object_set(s, "created", json_array_get(jobs, i));
        json_array_set_new(jobs, i, s ? s : json_null());
    }
    *result = json_pack("{s:s, s:I, s:o}", "sweep", sweep, "count", (json_int_t)n, "jobs", jobs);
    sphd_jobs_schedule(d);
    return *result ? 0 : sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
}

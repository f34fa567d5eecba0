/*
 * `sphd --runner ENDPOINT --job-dir DIR`: one job on a cluster node, started by Slurm (the batch
 * script sphd writes). It reads the job's case from DIR (the state directory, shared by the
 * daemon and the nodes), connects back to the daemon on a DEALER whose routing id is the job's
 * id, says hello, waits for the daemon's `run`, and runs the job exactly as a local worker does
 * (sphd_run_job, the same messages; sphd_link.c) until it ends, pauses (a checkpoint, then the
 * runner exits and so does the Slurm job), stops or reaches a step target. ZeroMQ reconnects by
 * itself: a daemon killed and restarted on the same endpoint hears from the runner again.
 */
#include "sphd.h"
#include "sphd_daemon.h"

#include "sph_case.h"
#include "sph_json.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zmq.h>

/* One Z85 key (40 characters) from DIR/NAME into z85. Returns 0 or -1 (said on stderr). */
static int read_key(const char *dir, const char *name, char z85[41])
{
    char path[SPHD_PATH_MAX + 32];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "r");
    char buf[64] = "";
    size_t n = f ? fread(buf, 1, sizeof buf - 1, f) : 0;
    if (f)
        fclose(f);
    while (n > 0 && (buf[n - 1] == '\n' || buf[n - 1] == ' ' || buf[n - 1] == '\r'))
        n--;
    buf[n] = '\0';
    if (n != 40) {
        fprintf(stderr, "sphd --runner: %s: %s\n", path,
                f ? "not one Z85 key of 40 characters" : strerror(errno));
        return -1;
    }
    memcpy(z85, buf, 41);
    return 0;
}

/* CURVE on the runner's socket with the key pair sphd left in keys (STATE/runner). */
static int curve_client(void *sock, const char *keys)
{
    char server[41], pub[41], secret[41];
    if (read_key(keys, "server.pub", server) || read_key(keys, "runner.pub", pub) ||
        read_key(keys, "runner.key", secret))
        return -1;
    int rc = zmq_setsockopt(sock, ZMQ_CURVE_SERVERKEY, server, 40) != 0 ||
                     zmq_setsockopt(sock, ZMQ_CURVE_PUBLICKEY, pub, 40) != 0 ||
                     zmq_setsockopt(sock, ZMQ_CURVE_SECRETKEY, secret, 40) != 0
                 ? -1
                 : 0;
    memset(secret, 0, sizeof secret);
    if (rc)
        fprintf(stderr, "sphd --runner: cannot set the CURVE keys: %s\n", zmq_strerror(errno));
    return rc;
}

int sphd_runner_main(const char *endpoint, const char *dir, const char *keys, int threads,
                     double ckpt_interval, int diag_rate, double wait_s)
{
    static sphd_job job; /* big (paths): not on the stack */
    static sphd_daemon d;
    const char *base = strrchr(dir, '/');
    base = base ? base + 1 : dir;
    if (!*base || strlen(base) >= sizeof job.id || strlen(dir) >= sizeof job.dir) {
        fprintf(stderr, "sphd --runner: '%s' is not a job directory\n", dir);
        return SPHD_EX_USAGE;
    }
    snprintf(job.id, sizeof job.id, "%s", base);
    snprintf(job.dir, sizeof job.dir, "%s", dir);
    char path[SPHD_PATH_MAX + 16];
    snprintf(path, sizeof path, "%s/case.json", dir);
    json_error_t jerr;
    json_t *case_json = json_load_file(path, 0, &jerr);
    static sph_case c;
    sph_error err;
    sph_error_clear(&err);
    /* the files the case names are in the job's files/ (written by sphd on submit) */
    char files[SPHD_PATH_MAX + 16];
    if (!case_json || sph_case_from_json(case_json, &c, &err) ||
        (sphd_inputs_dir(dir, files, sizeof files) == 0 &&
         sph_case_load_files(&c, files, NULL, &err) != 0)) {
        fprintf(stderr, "sphd --runner: %s: %s\n", path, case_json ? err.message : jerr.text);
        json_decref(case_json);
        sph_case_clear(&c);
        return SPHD_EX_DATAERR;
    }
    json_decref(case_json);
    job.c = &c;
    job.worker = -1;
    d.opts.threads = threads > 0 ? threads : 1;
    d.opts.diag_rate = diag_rate;
    d.opts.ckpt_interval = ckpt_interval;
    atomic_init(&d.busy, 0);
    sphd_worker w = {.d = &d, .index = 0};

    /* the Slurm job, as sphd names it: ARRAY_TASK for a task of an array */
    char slurm_job[48] = "";
    const char *aj = getenv("SLURM_ARRAY_JOB_ID"), *at = getenv("SLURM_ARRAY_TASK_ID");
    if (aj && at)
        snprintf(slurm_job, sizeof slurm_job, "%.20s_%.20s", aj, at);
    else if (getenv("SLURM_JOB_ID"))
        snprintf(slurm_job, sizeof slurm_job, "%.40s", getenv("SLURM_JOB_ID"));
    /* routing id JOB@SLURMJOB: two runs of one job (a stray one) are told apart */
    char rid[SPHD_JOB_ID_MAX + 64];
    snprintf(rid, sizeof rid, "%s@%s", job.id, slurm_job);
    void *ctx = zmq_ctx_new();
    void *sock = ctx ? zmq_socket(ctx, ZMQ_DEALER) : NULL;
    int linger = 30000, hwm = 100000;
    if (!sock || zmq_setsockopt(sock, ZMQ_ROUTING_ID, rid, strlen(rid)) != 0 ||
        zmq_setsockopt(sock, ZMQ_LINGER, &linger, sizeof linger) != 0 ||
        zmq_setsockopt(sock, ZMQ_SNDHWM, &hwm, sizeof hwm) != 0 ||
        (keys && curve_client(sock, keys) != 0) || zmq_connect(sock, endpoint) != 0) {
        fprintf(stderr, "sphd --runner: cannot connect to %s: %s\n", endpoint, zmq_strerror(errno));
        if (sock)
            zmq_close(sock);
        if (ctx)
            zmq_ctx_term(ctx);
        return SPHD_EX_UNAVAILABLE;
    }
    char host[256] = "";
    gethostname(host, sizeof host - 1);
    json_t *hello = json_pack("{s:s, s:s, s:s, s:I}", "job", job.id, "slurm_job", slurm_job, "host",
                              host, "pid", (json_int_t)getpid());
    char *text = hello ? json_dumps(hello, JSON_COMPACT) : NULL;
    json_decref(hello);
    if (!text || zmq_send(sock, "hello", 5, ZMQ_SNDMORE) < 0 ||
        zmq_send(sock, text, strlen(text), 0) < 0) {
        free(text);
        fprintf(stderr, "sphd --runner: cannot say hello to %s\n", endpoint);
        zmq_close(sock);
        zmq_ctx_term(ctx);
        return SPHD_EX_UNAVAILABLE;
    }
    free(text);
    sphd_log("runner: job %s on %s, waiting for the daemon at %s", job.id, host, endpoint);

    sphd_link link = {.sock = sock, .wire = 1, .job = &job};
    int timeout_ms = 1000, rc = SPHD_EX_UNAVAILABLE;
    zmq_setsockopt(sock, ZMQ_RCVTIMEO, &timeout_ms, sizeof timeout_ms);
    const double t0 = sphd_mono();
    while (sphd_mono() - t0 < wait_s) {
        sphd_wcmd cmd;
        int n = sphd_link_recv(&link, &cmd, 1);
        if (n < 0 && errno != EAGAIN)
            break;
        if (n <= 0)
            continue;
        if (cmd.kind == SPHD_W_QUIT) {
            rc = 0;
            break;
        }
        if (cmd.kind == SPHD_W_PARTICLES) {
            json_decref(cmd.fields);
            json_decref(cmd.status);
            json_decref(cmd.id);
            continue;
        }
        if (cmd.kind != SPHD_W_RUN)
            continue; /* a pause or stop before the run: the daemon cancels the Slurm job */
        timeout_ms = 0;
        zmq_setsockopt(sock, ZMQ_RCVTIMEO, &timeout_ms, sizeof timeout_ms);
        sphd_log("runner: job %s runs%s", job.id, job.resume ? " (from its checkpoint)" : "");
        sphd_run_job(&w, &link, &cmd);
        rc = 0;
        break;
    }
    if (rc == SPHD_EX_UNAVAILABLE)
        fprintf(stderr, "sphd --runner: no word from the daemon at %s in %g s\n", endpoint, wait_s);
    zmq_close(sock); /* lingers until the end has left */
    zmq_ctx_term(ctx);
    return rc;
}

/*
 * The Slurm executor's calls to Slurm: sbatch (one job, or one array for a sweep), scancel and
 * squeue, run as programs (Slurm's own command line is its stable interface), and the check of a
 * job's `resources`. Slurm places, queues and accounts; sphd only asks.
 *
 * The daemon makes these calls on a thread of its own (sphd_slurm_start): a slow or hung
 * slurmctld never holds up the socket loop.
 */
#include "sphd.h"
#include "sphd_daemon.h"

#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zmq.h>

extern char **environ;

#define OUT_MAX 65536

int sphd_slurm_call(char *const argv[], char *out, size_t outn, char *err, size_t errn)
{
    int po[2], pe[2];
    if (pipe(po) != 0)
        return -1;
    if (pipe(pe) != 0) {
        close(po[0]);
        close(po[1]);
        return -1;
    }
    for (int i = 0; i < 2; i++) { /* not inherited by other children */
        fcntl(po[i], F_SETFD, FD_CLOEXEC);
        fcntl(pe[i], F_SETFD, FD_CLOEXEC);
    }
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_adddup2(&fa, po[1], 1);
    posix_spawn_file_actions_adddup2(&fa, pe[1], 2);
    pid_t pid;
    int rc = posix_spawnp(&pid, argv[0], &fa, NULL, argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    close(po[1]);
    close(pe[1]);
    if (rc != 0) {
        close(po[0]);
        close(pe[0]);
        errno = rc;
        return -1;
    }
    size_t no = 0, ne = 0;
    struct pollfd fds[2] = {{.fd = po[0], .events = POLLIN}, {.fd = pe[0], .events = POLLIN}};
    int open_fds = 2;
    while (open_fds > 0) {
        const int pr = poll(fds, 2, 60000);
        if (pr < 0 && errno == EINTR)
            continue;
        if (pr <= 0) { /* a minute without a word: it hangs */
            kill(pid, SIGKILL);
            break;
        }
        for (int i = 0; i < 2; i++) {
            if (fds[i].fd < 0 || !(fds[i].revents & (POLLIN | POLLHUP | POLLERR)))
                continue;
            char buf[4096];
            ssize_t k = read(fds[i].fd, buf, sizeof buf);
            if (k <= 0) {
                close(fds[i].fd);
                fds[i].fd = -1;
                open_fds--;
                continue;
            }
            char *dst = i == 0 ? out : err;
            size_t cap = i == 0 ? outn : errn, *len = i == 0 ? &no : &ne;
            for (ssize_t j = 0; j < k && *len + 1 < cap; j++)
                dst[(*len)++] = buf[j];
        }
    }
    for (int i = 0; i < 2; i++)
        if (fds[i].fd >= 0)
            close(fds[i].fd);
    if (outn)
        out[no < outn ? no : outn - 1] = '\0';
    if (errn)
        err[ne < errn ? ne : errn - 1] = '\0';
    int status;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
        ;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

/* The last non-empty line of s, trimmed (sbatch puts the reason there). */
static void last_line(const char *s, char *dst, size_t n)
{
    const char *end = s + strlen(s);
    while (end > s && (end[-1] == '\n' || end[-1] == ' '))
        end--;
    const char *start = end;
    while (start > s && start[-1] != '\n')
        start--;
    snprintf(dst, n, "%.*s", (int)(end - start), start);
}

int sphd_slurm_available(char *why, size_t n)
{
    char out[256], err[1024];
    char *argv[] = {"sbatch", "--version", NULL};
    int rc = sphd_slurm_call(argv, out, sizeof out, err, sizeof err);
    if (rc == 0)
        return 0;
    if (rc < 0)
        snprintf(why, n,
                 "cannot run sbatch (%s): install Slurm's client commands (Debian: "
                 "slurm-client) on the daemon's machine, or run without --executor slurm",
                 strerror(errno));
    else
        snprintf(why, n, "sbatch --version failed: %s", err);
    return -1;
}

/* ---- resources ---- */

/* sbatch options a job may add (`resources.sbatch`): placing and accounting only; the rest
 * (output, chdir, array, job name, wrap) is sphd's. */
static const char *const allowed_opts[] = {"--mem=",
                                           "--mem-per-cpu=",
                                           "--constraint=",
                                           "--qos=",
                                           "--exclusive",
                                           "--nodelist=",
                                           "--exclude=",
                                           "--gres=",
                                           "--reservation=",
                                           "--comment=",
                                           "--nice=",
                                           "--mail-type=",
                                           "--mail-user=",
                                           "--begin=",
                                           "--deadline=",
                                           "--licenses=",
                                           NULL};

int sphd_resources_check(const json_t *res, const char *where, sphd_err *e)
{
    static const char *const keys[] = {"executor", "threads", "time_limit", "partition",
                                       "account",  "sbatch",  "retries",    NULL};
    const char *k;
    json_t *v;
    char path[128];
    json_object_foreach((json_t *)res, k, v)
    {
        int known = 0;
        for (int i = 0; keys[i]; i++)
            known |= strcmp(k, keys[i]) == 0;
        snprintf(path, sizeof path, "%s/%.48s", where, k);
        if (!known)
            return sphd_err_set(e, SPHD_E_BAD_REQUEST, path,
                                "unknown resources field '%.48s' (known: executor, threads, "
                                "time_limit, partition, account, sbatch, retries)",
                                k);
        if (strcmp(k, "executor") == 0) {
            const char *s = json_string_value(v);
            if (!s || (strcmp(s, "local") != 0 && strcmp(s, "slurm") != 0))
                return sphd_err_set(e, SPHD_E_BAD_REQUEST, path,
                                    "'executor' is \"local\" or \"slurm\"");
        } else if (strcmp(k, "threads") == 0 || strcmp(k, "time_limit") == 0 ||
                   strcmp(k, "retries") == 0) {
            const long lo = strcmp(k, "retries") == 0 ? 0 : 1;
            const long hi = strcmp(k, "threads") == 0   ? 1024
                            : strcmp(k, "retries") == 0 ? 100
                                                        : 525600;
            if (!json_is_integer(v) || json_integer_value(v) < lo || json_integer_value(v) > hi)
                return sphd_err_set(e, SPHD_E_BAD_REQUEST, path,
                                    "'%s' is an integer from %ld to %ld%s", k, lo, hi,
                                    strcmp(k, "time_limit") == 0 ? " (minutes)" : "");
        } else if (strcmp(k, "partition") == 0 || strcmp(k, "account") == 0) {
            const char *s = json_string_value(v);
            if (!s || !*s || strlen(s) > 64 || strpbrk(s, " \t\n'\"\\;&|$`"))
                return sphd_err_set(e, SPHD_E_BAD_REQUEST, path,
                                    "'%s' is a Slurm name (1-64 characters, no spaces or quotes)",
                                    k);
        } else if (strcmp(k, "sbatch") == 0) {
            if (!json_is_array(v))
                return sphd_err_set(e, SPHD_E_BAD_REQUEST, path,
                                    "'sbatch' is an array of options like \"--mem=4G\"");
            size_t i;
            json_t *o;
            json_array_foreach(v, i, o)
            {
                snprintf(path, sizeof path, "%s/sbatch/%zu", where, i);
                const char *s = json_string_value(o);
                int ok = 0;
                for (int a = 0; s && allowed_opts[a]; a++) {
                    const size_t n = strlen(allowed_opts[a]);
                    ok |= allowed_opts[a][n - 1] == '='
                              ? strncmp(s, allowed_opts[a], n) == 0 && s[n] != '\0'
                              : strcmp(s, allowed_opts[a]) == 0;
                }
                if (!ok || strlen(s) > 256)
                    return sphd_err_set(
                        e, SPHD_E_BAD_REQUEST, path,
                        "sbatch option '%.64s' is not allowed; allowed: --mem=, --mem-per-cpu=, "
                        "--constraint=, --qos=, --exclusive, --nodelist=, --exclude=, --gres=, "
                        "--reservation=, --comment=, --nice=, --mail-type=, --mail-user=, "
                        "--begin=, --deadline=, --licenses=",
                        s ? s : "(not a string)");
            }
        }
    }
    return 0;
}

/* ---- sbatch, scancel, squeue ---- */

int sphd_slurm_submit(const sphd_daemon *d, const char *script, const char *name,
                      const char *out_pattern, const json_t *res, const char *array, char *id,
                      size_t idn, char *why, size_t whyn)
{
    char *argv[64];
    char opt[16][300];
    int n = 0, o = 0;
    argv[n++] = "sbatch";
    argv[n++] = "--parsable";
    snprintf(opt[o], sizeof opt[o], "--job-name=%s", name);
    argv[n++] = opt[o++];
    char *output = malloc(strlen(out_pattern) + 16);
    char *arr = array ? malloc(strlen(array) + 16) : NULL;
    if (!output || (array && !arr)) {
        free(output);
        free(arr);
        snprintf(why, whyn, "out of memory");
        return -1;
    }
    sprintf(output, "--output=%s", out_pattern);
    argv[n++] = output;
    const json_t *th = json_object_get(res, "threads");
    snprintf(opt[o], sizeof opt[o], "--cpus-per-task=%lld",
             th ? (long long)json_integer_value(th) : 1LL);
    argv[n++] = opt[o++];
    if (json_object_get(res, "time_limit")) {
        snprintf(opt[o], sizeof opt[o], "--time=%lld",
                 (long long)json_integer_value(json_object_get(res, "time_limit")));
        argv[n++] = opt[o++];
    }
    if (json_object_get(res, "partition")) {
        snprintf(opt[o], sizeof opt[o], "--partition=%s",
                 json_string_value(json_object_get(res, "partition")));
        argv[n++] = opt[o++];
    }
    if (json_object_get(res, "account")) {
        snprintf(opt[o], sizeof opt[o], "--account=%s",
                 json_string_value(json_object_get(res, "account")));
        argv[n++] = opt[o++];
    }
    if (arr) {
        sprintf(arr, "--array=%s", array);
        argv[n++] = arr;
    }
    size_t i;
    json_t *s;
    json_array_foreach(json_object_get(res, "sbatch"), i, s)
    {
        if (n < 60)
            argv[n++] = (char *)json_string_value(s);
    }
    argv[n++] = (char *)script;
    argv[n] = NULL;
    (void)d;
    char out[512], err[4096];
    int rc = sphd_slurm_call(argv, out, sizeof out, err, sizeof err);
    const int call_errno = errno;
    free(output);
    free(arr);
    if (rc < 0) {
        snprintf(why, whyn, "cannot run sbatch: %s", strerror(call_errno));
        return -1;
    }
    if (rc != 0) {
        char line[1024];
        last_line(err, line, sizeof line);
        snprintf(why, whyn, "%s", line[0] ? line : "sbatch failed");
        return -1;
    }
    /* --parsable: "ID" or "ID;CLUSTER" */
    char *semi = strchr(out, ';');
    if (semi)
        *semi = '\0';
    char *nl = strchr(out, '\n');
    if (nl)
        *nl = '\0';
    if (!out[0]) {
        snprintf(why, whyn, "sbatch printed no job id");
        return -1;
    }
    snprintf(id, idn, "%s", out);
    return 0;
}

void sphd_slurm_cancel(const char *id)
{
    char out[256], err[1024];
    char *argv[] = {"scancel", (char *)id, NULL};
    if (sphd_slurm_call(argv, out, sizeof out, err, sizeof err) != 0)
        sphd_log("scancel %s: %s", id, err);
}

char *sphd_slurm_states(const char *ids)
{
    /* a few hundred ids per call (one argument must stay short), the answers joined */
    enum { PER_CALL = 400 };
    size_t cap = OUT_MAX, len = 0;
    char *all = malloc(cap), *out = malloc(OUT_MAX), *chunk = malloc(strlen(ids) + 1), err[1024];
    if (!all || !out || !chunk)
        goto fail;
    all[0] = '\0';
    for (const char *p = ids; *p;) {
        const char *q = p;
        for (int k = 0; *q && k < PER_CALL; k++) {
            q += strcspn(q, ",");
            if (*q && k + 1 < PER_CALL)
                q++;
        }
        memcpy(chunk, p, (size_t)(q - p));
        chunk[q - p] = '\0';
        p = *q == ',' ? q + 1 : q;
        /* -r: one line per array task, pending ones too; -t all: ended jobs that the controller
         * still remembers */
        char *argv[] = {"squeue", "-h", "-r", "-t", "all", "-o", "%i %T", "-j", chunk, NULL};
        int rc = sphd_slurm_call(argv, out, OUT_MAX, err, sizeof err);
        if (rc != 0) {
            /* squeue refuses a list whose jobs all left the controller's memory: none known */
            if (rc > 0 && strstr(err, "Invalid job id"))
                continue;
            sphd_log("squeue: %s", rc < 0 ? strerror(errno) : err);
            goto fail;
        }
        const size_t k = strlen(out);
        if (k + 1 >= OUT_MAX) { /* cut: the jobs past the cut would look gone */
            sphd_log("squeue: more output than %d bytes for %d jobs", OUT_MAX, PER_CALL);
            goto fail;
        }
        if (len + k + 1 > cap) {
            char *n = realloc(all, cap = 2 * (len + k + 1));
            if (!n)
                goto fail;
            all = n;
        }
        memcpy(all + len, out, k + 1);
        len += k;
    }
    free(out);
    free(chunk);
    return all;
fail:
    free(all);
    free(out);
    free(chunk);
    return NULL;
}

int sphd_slurm_script(const sphd_daemon *d, const char *path, const char *dir, const char *sweep,
                      char *why, size_t whyn)
{
    const char *q[] = {d->opts.exe, d->opts.runner_connect, d->opts.state_dir, dir, sweep};
    for (size_t i = 0; i < sizeof q / sizeof q[0]; i++)
        if (q[i] && strchr(q[i], '\'')) {
            snprintf(why, whyn, "'%s' holds a quote: not usable in a batch script", q[i]);
            return -1;
        }
    char text[5 * SPHD_PATH_MAX + 1024], jobdir[2 * SPHD_PATH_MAX + 64];
    if (dir)
        snprintf(jobdir, sizeof jobdir, "'%s'", dir);
    else
        snprintf(jobdir, sizeof jobdir, "'%s/jobs/%s-'\"$SLURM_ARRAY_TASK_ID\"", d->opts.state_dir,
                 sweep);
    char keys[SPHD_PATH_MAX + 32] = "";
    if (d->curve)
        snprintf(keys, sizeof keys, " --runner-keys '%s/runner'", d->opts.state_dir);
    char ckpt[64] = "";
    if (d->opts.ckpt_interval > 0)
        snprintf(ckpt, sizeof ckpt, " --checkpoint-interval %g", d->opts.ckpt_interval);
    snprintf(text, sizeof text,
             "#!/bin/sh\n"
             "# Written by sphd: runs %s%s on the node and connects back to the daemon.\n"
             "exec '%s' --runner '%s' --job-dir %s --threads \"${SLURM_CPUS_PER_TASK:-1}\" "
             "--diag-rate %d --runner-wait %g%s%s\n",
             dir ? "the job in " : "the jobs of sweep ", dir ? dir : sweep, d->opts.exe,
             d->opts.runner_connect, jobdir, d->opts.diag_rate, d->opts.runner_wait, ckpt, keys);
    if (sphd_write_atomic(path, text, strlen(text)) != 0 || chmod(path, 0755) != 0) {
        snprintf(why, whyn, "cannot write %s: %s", path, strerror(errno));
        return -1;
    }
    return 0;
}

/* ---- the Slurm thread: sbatch, scancel and squeue off the socket loop ---- */

#define SLURM_ENDPOINT "inproc://sphd-slurm"

static void *slurm_main(void *arg)
{
    sphd_daemon *d = arg;
    prctl(PR_SET_NAME, "sphd-slurm", 0, 0, 0);
    void *sock = sphd_pair_open(d->ctx, SLURM_ENDPOINT, 0);
    if (!sock)
        return NULL;
    for (;;) {
        sphd_scmd cmd;
        int n = zmq_recv(sock, &cmd, sizeof cmd, 0);
        if (n < 0 && errno == EINTR)
            continue;
        if (n != (int)sizeof cmd || cmd.kind == SPHD_S_QUIT) {
            sphd_sev bye = {.kind = SPHD_S_QUIT, .token = -1};
            sphd_pair_send(sock, &bye, sizeof bye);
            break;
        }
        sphd_sev ev = {.kind = cmd.kind, .token = cmd.token};
        if (cmd.kind == SPHD_S_SUBMIT)
            ev.rc = sphd_slurm_submit(d, cmd.arg, cmd.name, cmd.out, cmd.res, cmd.array, ev.id,
                                      sizeof ev.id, ev.why, sizeof ev.why);
        else if (cmd.kind == SPHD_S_CANCEL)
            sphd_slurm_cancel(cmd.arg);
        else if (cmd.kind == SPHD_S_STATES)
            ev.rc = (ev.lines = sphd_slurm_states(cmd.arg)) ? 0 : -1;
        free(cmd.arg);
        free(cmd.name);
        free(cmd.out);
        free(cmd.array);
        json_decref(cmd.res);
        if (cmd.kind != SPHD_S_CANCEL && sphd_pair_send(sock, &ev, sizeof ev) != 0)
            free(ev.lines);
    }
    zmq_close(sock);
    return NULL;
}

int sphd_slurm_start(sphd_daemon *d)
{
    d->slurm = sphd_pair_open(d->ctx, SLURM_ENDPOINT, 1);
    if (!d->slurm)
        return -1;
    int hwm = 1000000; /* the loop never waits for the Slurm thread */
    zmq_setsockopt(d->slurm, ZMQ_SNDHWM, &hwm, sizeof hwm);
    int rc = pthread_create(&d->slurm_thread, NULL, slurm_main, d);
    if (rc != 0) {
        sphd_log("cannot start the Slurm thread: %s", strerror(rc));
        return -1;
    }
    d->slurm_started = 1;
    return 0;
}

static void scmd_free(sphd_scmd *c)
{
    free(c->arg);
    free(c->name);
    free(c->out);
    free(c->array);
    json_decref(c->res);
}

long sphd_slurm_send(sphd_daemon *d, sphd_scmd *cmd)
{
    cmd->token = ++d->next_token;
    int rc;
    do
        rc = d->slurm_started ? zmq_send(d->slurm, cmd, sizeof *cmd, ZMQ_DONTWAIT) : -1;
    while (rc < 0 && errno == EINTR);
    if (rc < 0) {
        sphd_log("the Slurm thread is %s: a %s is dropped", d->slurm_started ? "behind" : "gone",
                 cmd->kind == SPHD_S_SUBMIT   ? "sbatch"
                 : cmd->kind == SPHD_S_CANCEL ? "scancel"
                                              : "squeue");
        scmd_free(cmd);
        return -1;
    }
    return cmd->token;
}

int sphd_slurm_recv(sphd_daemon *d, sphd_sev *ev)
{
    int n;
    do
        n = zmq_recv(d->slurm, ev, sizeof *ev, ZMQ_DONTWAIT);
    while (n < 0 && errno == EINTR);
    return n == (int)sizeof *ev;
}

void sphd_slurm_stop(sphd_daemon *d)
{
    if (d->slurm_started) {
        sphd_scmd q = {.kind = SPHD_S_QUIT};
        int wait_ms = 65000; /* a call in flight ends within its own 60 s bound */
        zmq_setsockopt(d->slurm, ZMQ_RCVTIMEO, &wait_ms, sizeof wait_ms);
        int joined = 0;
        if (sphd_pair_send(d->slurm, &q, sizeof q) == 0) {
            for (;;) {
                sphd_sev ev;
                int n = zmq_recv(d->slurm, &ev, sizeof ev, 0);
                if (n < 0 && errno == EINTR)
                    continue;
                if (n != (int)sizeof ev)
                    break;
                free(ev.lines);
                if (ev.token == -1) {
                    joined = 1;
                    break;
                }
            }
        }
        if (joined)
            pthread_join(d->slurm_thread, NULL);
        else
            pthread_detach(d->slurm_thread);
        d->slurm_started = 0;
    }
    if (d->slurm) {
        zmq_close(d->slurm);
        d->slurm = NULL;
    }
}

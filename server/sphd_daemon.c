/*
 * The socket loop: one thread owns the control ROUTER, the stream PUB, the inproc PAIRs to the
 * workers and the read end of the signal self-pipe. It never runs solver work: it parses requests,
 * hands jobs to workers and publishes their events.
 */
#include "sphd.h"
#include "sphd_daemon.h"
#include "sphd_http.h"

#include "sph_events.h"
#include "sphd_curve.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>
#include <zmq.h>

#define PUB_HWM         10000 /* events queued per subscriber before the PUB drops */
#define ROUTER_HWM      10000
#define FINAL_LINGER_MS 200 /* last replies (shutdown) get this long to leave */

/* The write end of the signal self-pipe: the only global mutable state. */
static volatile sig_atomic_t sig_pipe_w = -1;

/* ---- one request ---- */

#define SPHD_TRANSPORT_FACTOR 8 /* ZMQ_MAXMSGSIZE = this x --max-msg-size */

static void handle_request(sphd_daemon *d)
{
    zmq_msg_t parts[2 * SPHD_MAX_ENVELOPE];
    int n = 0, more = 1, dropped = 0;
    while (more) {
        zmq_msg_t m;
        zmq_msg_init(&m);
        if (zmq_msg_recv(&m, d->router, ZMQ_DONTWAIT) < 0) {
            zmq_msg_close(&m);
            if (errno == EINTR)
                continue;
            break; /* EAGAIN: nothing (more) to read */
        }
        more = zmq_msg_more(&m);
        if (n < 2 * SPHD_MAX_ENVELOPE)
            parts[n++] = m;
        else {
            zmq_msg_close(&m);
            dropped = 1;
        }
    }
    if (n == 0)
        return;
    if (d->curve) {
        /* a connection authenticated before its key was revoked (SIGHUP) gets nothing more */
        const char *user = zmq_msg_gets(&parts[n - 1], "User-Id");
        if (!sphd_curve_authorised(d->curve, user)) {
            sphd_log("CURVE: dropped a request from revoked key %s", user ? user : "?");
            for (int i = 0; i < n; i++)
                zmq_msg_close(&parts[i]);
            return;
        }
    }
    /* Envelope: the identity, and up to an empty delimiter (REQ) when there is one. */
    int env = 1;
    for (int i = 1; i < n - 1 && i < SPHD_MAX_ENVELOPE; i++) {
        if (zmq_msg_size(&parts[i]) == 0) {
            env = i + 1;
            break;
        }
    }
    sphd_pending from = {.nframes = env, .id = NULL, .op = "?"};
    for (int i = 0; i < env; i++) {
        from.frame[i] = zmq_msg_data(&parts[i]);
        from.len[i] = zmq_msg_size(&parts[i]);
    }
    char *reply = NULL;
    sphd_err e;
    int refused = 1; /* refused unread: no id to echo */
    if (n - env != 1 || dropped) {
        sphd_err_set(&e, SPHD_E_BAD_REQUEST, NULL,
                     "a request is one frame holding one JSON object (got %d frames)", n - env);
    } else if ((long)zmq_msg_size(&parts[n - 1]) > d->opts.max_msg_size) {
        /* read (up to the transport's bound, SPHD_TRANSPORT_FACTOR times larger) and refused */
        sphd_err_set(&e, SPHD_E_TOO_LARGE, NULL,
                     "the request is %zu bytes, more than the %ld this sphd accepts "
                     "(--max-msg-size); send particle data and large cases in smaller pieces",
                     zmq_msg_size(&parts[n - 1]), d->opts.max_msg_size);
    } else {
        reply = sphd_dispatch(d, &from, zmq_msg_data(&parts[n - 1]), zmq_msg_size(&parts[n - 1]));
        refused = 0;
    }
    if (refused) {
        d->requests++;
        d->errors++;
        json_t *r = sphd_reply_new(NULL, NULL, &e);
        reply = r ? json_dumps(r, JSON_COMPACT) : NULL;
        json_decref(r);
    }
    if (reply)
        sphd_reply_text(d, &from, reply);
    for (int i = 0; i < n; i++)
        zmq_msg_close(&parts[i]);
}

static void handle_worker(sphd_daemon *d, sphd_worker *w)
{
    for (;;) {
        sphd_wev ev;
        int n = zmq_recv(w->pair, &ev, sizeof ev, ZMQ_DONTWAIT);
        if (n < 0) {
            if (errno == EINTR)
                continue;
            return;
        }
        if (n == (int)sizeof ev)
            sphd_jobs_on_worker(d, w, &ev);
    }
}

/* ---- signals ---- */

static void on_signal(int sig)
{
    int saved = errno;
    unsigned char c = (unsigned char)sig;
    if (sig_pipe_w >= 0 && write(sig_pipe_w, &c, 1) < 0) {
        /* the pipe is full: a signal is already pending */
    }
    errno = saved;
}

static int install_signals(int *rfd)
{
    int fds[2];
    if (pipe(fds) != 0)
        return -1;
    for (int i = 0; i < 2; i++) {
        fcntl(fds[i], F_SETFL, fcntl(fds[i], F_GETFL) | O_NONBLOCK);
        fcntl(fds[i], F_SETFD, FD_CLOEXEC);
    }
    sig_pipe_w = fds[1];
    *rfd = fds[0];
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    if (sigaction(SIGINT, &sa, NULL) != 0 || sigaction(SIGTERM, &sa, NULL) != 0 ||
        sigaction(SIGHUP, &sa, NULL) != 0)
        return -1;
    signal(SIGPIPE, SIG_IGN);
    return 0;
}

/* ---- paths, locks ---- */

/* Creates dir 0700 if missing; refuses a directory that others can open or that is not ours. */
static int private_dir(const char *dir)
{
    if (sphd_mkdirs(dir) != 0) {
        sphd_log("cannot create %s: %s", dir, strerror(errno));
        return -1;
    }
    struct stat st;
    if (lstat(dir, &st) != 0 || !S_ISDIR(st.st_mode)) {
        sphd_log("%s is not a directory", dir);
        return -1;
    }
    if (st.st_uid != getuid()) {
        sphd_log("%s belongs to another user: refusing to put sockets there", dir);
        return -1;
    }
    if ((st.st_mode & 077) != 0 && chmod(dir, 0700) != 0) {
        sphd_log("cannot make %s private: %s", dir, strerror(errno));
        return -1;
    }
    return 0;
}

static int endpoint_dir(const char *ep)
{
    const char *path = sph_ipc_path(ep);
    if (!path)
        return 0;
    char dir[SPHD_PATH_MAX];
    snprintf(dir, sizeof dir, "%s", path);
    char *slash = strrchr(dir, '/');
    if (!slash || slash == dir)
        return 0;
    *slash = '\0';
    char rt[SPHD_PATH_MAX];
    if (sph_runtime_dir(rt, sizeof rt) == 0 && strcmp(rt, dir) == 0)
        return private_dir(dir);
    if (sphd_mkdirs(dir) != 0) {
        sphd_log("cannot create %s: %s", dir, strerror(errno));
        return -1;
    }
    return 0;
}

/* An ipc bind silently takes the socket over from a live server: take a lock next to the socket
 * (flock, released by the kernel when the holder dies) and refuse when another sphd holds it. */
static int take_lock(sphd_daemon *d, const char *lockpath, const char *what)
{
    int fd = open(lockpath, O_RDWR | O_CREAT | O_CLOEXEC, 0600);
    if (fd < 0) {
        sphd_log("cannot open lock file %s: %s", lockpath, strerror(errno));
        return -1;
    }
    if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
        char pid[32] = "";
        ssize_t n = pread(fd, pid, sizeof pid - 1, 0);
        pid[n > 0 ? n : 0] = '\0';
        pid[strcspn(pid, "\n")] = '\0';
        if (pid[0])
            fprintf(stderr,
                    "sphd: another sphd (pid %s) is already serving %s (lock %s is held); stop "
                    "it first ('sphctl shutdown') or choose another --listen, --publish or "
                    "--state-dir\n",
                    pid, what, lockpath);
        else
            fprintf(stderr,
                    "sphd: another sphd is already serving %s (lock %s is held); stop it first "
                    "('sphctl shutdown') or choose another --listen, --publish or --state-dir\n",
                    what, lockpath);
        close(fd);
        return 1;
    }
    char pid[32];
    int len = snprintf(pid, sizeof pid, "%ld\n", (long)getpid());
    if (ftruncate(fd, 0) != 0 || pwrite(fd, pid, (size_t)len, 0) != len)
        sphd_log("cannot write %s: %s", lockpath, strerror(errno));
    (void)d;
    return fd;
}

/* ---- the daemon ---- */

static int setup_socket_opts(void *s, const char *name, int hwm_opt, int hwm)
{
    int zero = 0;
    if (zmq_setsockopt(s, ZMQ_LINGER, &zero, sizeof zero) != 0 ||
        zmq_setsockopt(s, hwm_opt, &hwm, sizeof hwm) != 0) {
        sphd_log("cannot set options of the %s socket: %s", name, zmq_strerror(errno));
        return -1;
    }
    return 0;
}

/* The stream PUB: options, CURVE, bound. Returns it or NULL (logged). */
static void *open_stream(sphd_daemon *d)
{
    void *pub = zmq_socket(d->ctx, ZMQ_PUB);
    if (!pub || setup_socket_opts(pub, "stream", ZMQ_SNDHWM, PUB_HWM) ||
        (d->curve && sphd_curve_server(d->curve, pub) != 0)) {
        sphd_log("cannot create the stream socket: %s", zmq_strerror(errno));
        if (pub)
            zmq_close(pub);
        return NULL;
    }
    return pub;
}

/* SIGHUP: the authorised keys are read again. When some were revoked, the stream socket is made
 * anew, so that every subscriber connects and authenticates again (a PUB cannot drop one of
 * them); subscribers see the events they missed meanwhile as a gap. */
static void reload_keys(sphd_daemon *d)
{
    if (!d->curve) {
        sphd_log("SIGHUP: nothing to reload (no --curve)");
        return;
    }
    if (sphd_curve_reload(d->curve) <= 0)
        return;
    void *pub = open_stream(d);
    if (!pub)
        return;
    zmq_unbind(d->pub, d->opts.publish);
    zmq_close(d->pub);
    for (int tries = 0;; tries++) {
        if (zmq_bind(pub, d->opts.publish) == 0)
            break;
        if (errno != EADDRINUSE || tries >= 200) {
            sphd_log("cannot bind the stream endpoint %s again: %s; events are not published "
                     "until a restart",
                     d->opts.publish, zmq_strerror(errno));
            break;
        }
        struct timespec ts = {0, 10 * 1000 * 1000};
        nanosleep(&ts, NULL);
    }
    d->pub = pub;
    sphd_log("CURVE: the stream's subscribers reconnect and authenticate again");
}

static int bind_or_explain(void *s, const char *ep, const char *what)
{
    if (zmq_bind(s, ep) == 0)
        return 0;
    int e = errno;
    if (e == EADDRINUSE) {
        fprintf(stderr, "sphd: the %s endpoint %s is in use (another sphd is running there?)\n",
                what, ep);
        return -2;
    }
    fprintf(stderr, "sphd: cannot bind the %s endpoint %s: %s\n", what, ep, zmq_strerror(e));
    return -1;
}

static void finish_shutdown_replies(sphd_daemon *d)
{
    json_t *paused = json_array();
    for (sphd_job *j = d->jobs; j; j = j->next)
        if (!sphd_job_state_final(j->state))
            json_array_append_new(paused, json_string(j->id));
    while (d->shutdown_waits) {
        sphd_pending *p = d->shutdown_waits;
        d->shutdown_waits = p->next;
        sphd_reply(d, p, json_pack("{s:b, s:O}", "stopping", 1, "kept", paused), NULL);
        sphd_pending_free(p);
    }
    json_decref(paused);
}

/* Pauses every running job (once), records the others. */
/* --executor slurm: sbatch must run here, and the runners' ROUTER is bound; the address the
 * nodes connect to defaults to this host's name and the bound port. Returns 0, or -3 (said). */
static int open_runners(sphd_daemon *d)
{
    char why[512];
    if (sphd_slurm_available(why, sizeof why) != 0) {
        sphd_log("--executor slurm: %s", why);
        return -3;
    }
    ssize_t n = readlink("/proc/self/exe", d->opts.exe, sizeof d->opts.exe - 1);
    if (n <= 0) {
        sphd_log("--executor slurm: cannot find this sphd's path: %s", strerror(errno));
        return -3;
    }
    d->opts.exe[n] = '\0';
    int one = 1, hwm = 100000;
    char keys[SPHD_PATH_MAX + 16];
    snprintf(keys, sizeof keys, "%s/runner", d->opts.state_dir);
    if (d->curve && sphd_curve_runner_keys(d->curve, keys) != 0)
        return -3;
    d->runners = zmq_socket(d->ctx, ZMQ_ROUTER);
    if (!d->runners || zmq_setsockopt(d->runners, ZMQ_ROUTER_HANDOVER, &one, sizeof one) != 0 ||
        zmq_setsockopt(d->runners, ZMQ_RCVHWM, &hwm, sizeof hwm) != 0 ||
        (d->curve && sphd_curve_runners_server(d->curve, d->runners) != 0) ||
        zmq_bind(d->runners, d->opts.runner_listen) != 0) {
        sphd_log("--runner-listen %s: cannot bind: %s", d->opts.runner_listen, zmq_strerror(errno));
        return -3;
    }
    if (!d->opts.runner_connect[0]) {
        char last[SPH_ENDPOINT_MAX] = "", host[256] = "localhost";
        size_t len = sizeof last;
        zmq_getsockopt(d->runners, ZMQ_LAST_ENDPOINT, last, &len);
        gethostname(host, sizeof host - 1);
        const char *port = strrchr(last, ':');
        snprintf(d->opts.runner_connect, sizeof d->opts.runner_connect, "tcp://%.200s%s", host,
                 port ? port : ":7617");
    }
    sphd_log("Slurm executor: runners connect to %s%s", d->opts.runner_connect,
             d->curve ? " with CURVE (the runner key pair in STATE/runner)" : "");
    return 0;
}

static void begin_stopping(sphd_daemon *d)
{
    for (sphd_job *j = d->jobs; j; j = j->next) {
        if (j->worker == SPHD_WORKER_REMOTE) {
            sphd_job_record(d, j, 1);       /* runs on in Slurm; found again after a restart */
            sphd_jobs_answer_waiters(d, j); /* pause/stop/queries: their status as it is */
        } else if (j->state == SPHD_JOB_RUNNING && !j->pause_requested && !j->stop_requested) {
            sphd_wcmd cmd = {.kind = SPHD_W_PAUSE, .job = j};
            if (sphd_worker_send(&d->workers[j->worker], &cmd) == 0)
                j->pause_requested = 1;
        } else if (!sphd_job_state_final(j->state) && j->state != SPHD_JOB_RUNNING) {
            sphd_job_record(d, j, 1);
        }
    }
}

static int loop(sphd_daemon *d)
{
    /* control, signals, each worker, the files thread, the ZAP handler (--curve), the runners
     * and the Slurm thread (--executor slurm) */
    const int nitems = 3 + d->nworkers + (d->curve != NULL) + 2 * (d->runners != NULL);
    zmq_pollitem_t *items = calloc((size_t)nitems, sizeof *items);
    if (!items)
        return -1;
    items[0] = (zmq_pollitem_t){.socket = d->router, .events = ZMQ_POLLIN};
    items[1] = (zmq_pollitem_t){.fd = d->sigfd, .events = ZMQ_POLLIN};
    for (int i = 0; i < d->nworkers; i++)
        items[2 + i] = (zmq_pollitem_t){.socket = d->workers[i].pair, .events = ZMQ_POLLIN};
    zmq_pollitem_t *files_item = &items[2 + d->nworkers];
    *files_item = (zmq_pollitem_t){.socket = d->files, .events = ZMQ_POLLIN};
    zmq_pollitem_t *zap_item = d->curve ? &items[3 + d->nworkers] : NULL;
    if (zap_item)
        *zap_item =
            (zmq_pollitem_t){.socket = sphd_curve_zap_socket(d->curve), .events = ZMQ_POLLIN};
    zmq_pollitem_t *runners_item = d->runners ? &items[3 + d->nworkers + (d->curve != NULL)] : NULL;
    if (runners_item) {
        *runners_item = (zmq_pollitem_t){.socket = d->runners, .events = ZMQ_POLLIN};
        runners_item[1] = (zmq_pollitem_t){.socket = d->slurm, .events = ZMQ_POLLIN};
    }
    int stop_begun = 0;
    for (;;) {
        if (d->stopping && !stop_begun) {
            begin_stopping(d);
            stop_begun = 1;
        }
        if (d->stopping && atomic_load(&d->busy) == 0)
            break;
        int rc = zmq_poll(items, nitems, d->runners ? 1000 : -1);
        if (rc < 0) {
            if (errno == EINTR)
                continue;
            sphd_log("poll: %s", zmq_strerror(errno));
            free(items);
            return -1;
        }
        if (items[1].revents & ZMQ_POLLIN) {
            unsigned char sig;
            while (read(d->sigfd, &sig, 1) == 1) {
                if (sig == SIGHUP) {
                    reload_keys(d);
                    continue;
                }
                if (!d->stopping)
                    sphd_log("%s: pausing the jobs and exiting",
                             sig == SIGINT ? "SIGINT" : "SIGTERM");
                d->stopping = 1;
            }
        }
        for (int i = 0; i < d->nworkers; i++)
            if (items[2 + i].revents & ZMQ_POLLIN)
                handle_worker(d, &d->workers[i]);
        if (files_item->revents & ZMQ_POLLIN)
            sphd_files_on_answer(d); /* a job whose particles were read may run: below */
        if (zap_item && (zap_item->revents & ZMQ_POLLIN))
            sphd_curve_on_zap(d->curve);
        if (runners_item && (runners_item->revents & ZMQ_POLLIN))
            sphd_remote_on_message(d);
        if (runners_item && (runners_item[1].revents & ZMQ_POLLIN))
            sphd_remote_on_slurm(d);
        if (d->runners && !d->stopping)
            sphd_remote_poll(d);
        if (items[0].revents & ZMQ_POLLIN) {
            /* a bounded batch, so the workers' events are never starved */
            for (int k = 0; k < 256; k++) {
                int ev = 0;
                size_t len = sizeof ev;
                if (zmq_getsockopt(d->router, ZMQ_EVENTS, &ev, &len) != 0 || !(ev & ZMQ_POLLIN))
                    break;
                handle_request(d);
            }
        }
        sphd_jobs_schedule(d); /* once per turn, whatever freed a worker or queued a job */
    }
    free(items);
    return 0;
}

int sphd_daemon_main(const sphd_opts *opts)
{
    sphd_daemon *d = calloc(1, sizeof *d);
    if (!d)
        return SPHD_EX_SOFTWARE;
    d->opts = *opts;
    d->sigfd = -1;
    d->lockfd = -1;
    d->started_at = sphd_now();
    atomic_init(&d->busy, 0);
    int rc = SPHD_EX_SOFTWARE, locks[3] = {-1, -1, -1};
    sphd_http *http = NULL;

    /* Directories and locks before any bind: a second sphd must not steal the sockets. */
    char jobs_dir[SPHD_PATH_MAX + 8];
    snprintf(jobs_dir, sizeof jobs_dir, "%s/jobs", d->opts.state_dir);
    if (endpoint_dir(d->opts.listen) || endpoint_dir(d->opts.publish) ||
        sphd_mkdirs(jobs_dir) != 0) {
        if (errno)
            sphd_log("cannot prepare %s: %s", jobs_dir, strerror(errno));
        rc = SPHD_EX_CANTCREAT;
        goto out;
    }
    const char *eps[3] = {d->opts.listen, d->opts.publish, NULL};
    char lockpaths[3][SPHD_PATH_MAX + 16];
    snprintf(lockpaths[2], sizeof lockpaths[2], "%s/sphd.lock", d->opts.state_dir);
    for (int i = 0; i < 3; i++) {
        const char *path = i < 2 ? sph_ipc_path(eps[i]) : lockpaths[2];
        if (!path)
            continue;
        if (i < 2 && snprintf(lockpaths[i], sizeof lockpaths[i], "%s.lock", path) >=
                         (int)sizeof lockpaths[i]) {
            sphd_log("endpoint path too long: %s", path);
            rc = SPHD_EX_USAGE;
            goto out;
        }
        locks[i] = take_lock(d, lockpaths[i], i < 2 ? eps[i] : d->opts.state_dir);
        if (locks[i] < 0 || locks[i] == 1) {
            rc = locks[i] == 1 ? SPHD_EX_TEMPFAIL : SPHD_EX_CANTCREAT;
            locks[i] = -1;
            goto out;
        }
    }
    if (install_signals(&d->sigfd) != 0) {
        sphd_log("cannot install signal handlers: %s", strerror(errno));
        goto out;
    }
    d->ctx = zmq_ctx_new();
    if (!d->ctx) {
        sphd_log("cannot create the ZeroMQ context: %s", zmq_strerror(errno));
        goto out;
    }
    /* the request threads on one CPU (sphd_sched.c): ZeroMQ's before its first socket */
    int request_cpu = sphd_sched_pick_cpu(d->opts.request_cpu);
    if (sphd_sched_zmq_threads(d->ctx, request_cpu) != 0) {
        sphd_log("note: cannot keep the ZeroMQ threads on CPU %d: %s", request_cpu,
                 zmq_strerror(errno));
        request_cpu = SPHD_CPU_ANY;
    }
    if (d->opts.curve_dir[0]) {
        /* the ZAP handler is there before the sockets bind: no client is let in unchecked */
        if (!(d->curve = sphd_curve_load(d->opts.curve_dir))) {
            rc = SPHD_EX_CONFIG;
            goto out;
        }
        if (sphd_curve_start(d->curve, d->ctx) != 0)
            goto out;
    }
    d->router = zmq_socket(d->ctx, ZMQ_ROUTER);
    d->pub = open_stream(d);
    int one = 1;
    /* the transport drops (and disconnects) only far larger messages: those just over the limit
     * are read and answered with too_large */
    int64_t maxmsg = (int64_t)d->opts.max_msg_size * SPHD_TRANSPORT_FACTOR;
    if (!d->router || !d->pub || setup_socket_opts(d->router, "control", ZMQ_SNDHWM, ROUTER_HWM) ||
        (d->curve && sphd_curve_server(d->curve, d->router) != 0) ||
        zmq_setsockopt(d->router, ZMQ_ROUTER_MANDATORY, &one, sizeof one) != 0 ||
        zmq_setsockopt(d->router, ZMQ_MAXMSGSIZE, &maxmsg, sizeof maxmsg) != 0) {
        sphd_log("cannot create the sockets: %s", zmq_strerror(errno));
        goto out;
    }
    int brc = bind_or_explain(d->router, d->opts.listen, "control");
    if (brc == 0)
        brc = bind_or_explain(d->pub, d->opts.publish, "stream");
    if (brc == 0 && d->opts.executor_slurm && (brc = open_runners(d)) == -3) {
        rc = SPHD_EX_UNAVAILABLE;
        goto out;
    }
    if (brc != 0) {
        rc = brc == -2 ? SPHD_EX_TEMPFAIL : SPHD_EX_UNAVAILABLE;
        goto out;
    }
    if (sphd_workers_start(d) != 0 || sphd_files_start(d) != 0 ||
        (d->runners && sphd_slurm_start(d) != 0))
        goto out;
    if (d->opts.http[0]) { /* the dashboard: a client of the sockets bound above */
        char url[320];
        sph_error herr;
        sph_error_clear(&herr);
        http = sphd_http_start(d->opts.http, d->ctx, d->opts.listen, d->opts.publish,
                               d->opts.state_dir, d->opts.max_msg_size, url, sizeof url, &herr);
        if (!http) {
            fprintf(stderr, "sphd: %s\n", herr.message);
            rc = herr.code == SPH_ERR_INVALID ? SPHD_EX_USAGE : SPHD_EX_UNAVAILABLE;
            goto out;
        }
        sphd_log("dashboard on %s%s", url,
                 sphd_http_needs_token(http) ? " (its token: http.token in the state directory)"
                                             : "");
    }
    /* the loop joins the ZeroMQ threads' CPU after the workers start, so that they and their
     * OpenMP threads keep every CPU (sphd_sched.c) */
    if (sphd_sched_pin_self(request_cpu) != 0) {
        sphd_log("note: cannot keep the socket loop on CPU %d: %s", request_cpu, strerror(errno));
        request_cpu = SPHD_CPU_ANY;
    }
    char sched_what[32] = "on any CPU";
    if (request_cpu >= 0)
        snprintf(sched_what, sizeof sched_what, "on CPU %d", request_cpu);
    sphd_jobs_recover(d);
    sphd_jobs_schedule(d);
    sphd_log("listening on %s, publishing on %s, state in %s, %d threads, at most %d jobs, "
             "request threads %s",
             d->opts.listen, d->opts.publish, d->opts.state_dir, d->opts.threads, d->opts.max_jobs,
             sched_what);
    if (loop(d) == 0)
        rc = SPHD_EX_OK;
    finish_shutdown_replies(d);
    for (sphd_job *j = d->jobs; j; j = j->next)
        if (!sphd_job_state_final(j->state))
            sphd_job_record(d, j, 1);
    sphd_log("stopped");
out:
    sphd_http_stop(http); /* its connections' sockets close before the context ends */
    sphd_files_stop(d);   /* its last answers go out before the sockets close */
    sphd_slurm_stop(d);
    if (d->workers)
        sphd_workers_stop(d);
    if (d->router) {
        /* the last replies (to `shutdown`) get a short, bounded time to leave */
        int linger = FINAL_LINGER_MS;
        zmq_setsockopt(d->router, ZMQ_LINGER, &linger, sizeof linger);
        zmq_close(d->router);
    }
    if (d->pub)
        zmq_close(d->pub);
    if (d->runners)
        zmq_close(d->runners);
    sphd_curve_free(d->curve);
    /* our sockets' files go with us (we hold their locks, so they are ours) */
    for (int i = 0; i < 2; i++) {
        const char *path = sph_ipc_path(i ? d->opts.publish : d->opts.listen);
        if (path && locks[i] >= 0)
            unlink(path);
    }
    if (d->ctx) {
        while (zmq_ctx_term(d->ctx) != 0 && errno == EINTR)
            ;
    }
    sphd_jobs_free(d);
    for (int i = 0; i < 3; i++)
        if (locks[i] >= 0)
            close(locks[i]);
    if (d->sigfd >= 0) {
        close(d->sigfd);
        close(sig_pipe_w);
        sig_pipe_w = -1;
    }
    while (d->shutdown_waits) {
        sphd_pending *p = d->shutdown_waits;
        d->shutdown_waits = p->next;
        sphd_pending_free(p);
    }
    while (d->particle_waits) {
        sphd_pending *p = d->particle_waits;
        d->particle_waits = p->next;
        sphd_pending_free(p);
    }
    free(d);
    return rc;
}

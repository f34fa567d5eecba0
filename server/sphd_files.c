/*
 * The files thread: `results`, `fetch` and `export` read a job's files here, not on the socket
 * thread, so that a checksum over gigabytes of snapshots or a CSV export of a long series never
 * holds up the other clients' requests. The loop checks a request's arguments, keeps its
 * envelope (sphd_pending, with a token) and sends the work over inproc://sphd-files; the answer
 * comes back as a sphd_fev with the same token. Requests are served one at a time, in order.
 * What the thread reads of a job (its id, directory and case) never changes once the job
 * exists, and a job is not forgotten while the thread serves a request on it (job->readers).
 * A `query` with fields of a paused job reads its idle executor here too (job->exec_readers:
 * meanwhile the job is not run and its executor not freed), or, for a job that has none here
 * (on the Slurm executor, or taken up after a restart), its latest checkpoint; the thread
 * encodes the reply.
 */
#include "sphd_daemon.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <zmq.h>

#define FILES_ENDPOINT "inproc://sphd-files"

json_t *sphd_files_do(const sphd_fcmd *cmd, sphd_err *e)
{
    switch (cmd->kind) {
    case SPHD_F_LIST:
        return sphd_results_list(cmd->job, cmd->checksums, e);
    case SPHD_F_FETCH:
        return sphd_results_fetch(cmd->job, cmd->file, cmd->offset, cmd->length, e);
    case SPHD_F_EXPORT:
        return sphd_results_export_csv(cmd->job, e);

    default:
        sphd_err_set(e, SPHD_E_INTERNAL, NULL, "unknown files request");
        return NULL;
    }
}

/* The executor of a job from its latest checkpoint (read only here), or NULL. */
static sphd_exec *checkpoint_exec(const sphd_fcmd *cmd)
{
    sph_error err;
    sph_error_clear(&err);
    int fell_back = 0;
    return sphd_exec_resume(cmd->job->c, cmd->job->dir, &fell_back, &err);
}

static char *no_checkpoint_reply(sphd_fcmd *cmd)
{
    sphd_err e;
    sphd_err_set(&e, SPHD_E_BAD_STATE, "/args/fields",
                 "job %s has no checkpoint yet: its particles are made when it first runs",
                 cmd->job->id);
    json_t *reply = sphd_reply_new(cmd->id, NULL, &e);
    json_decref(cmd->id);
    json_decref(cmd->status);
    char *text = reply ? json_dumps(reply, JSON_COMPACT) : NULL;
    json_decref(reply);
    return text;
}

static void *files_main(void *arg)
{
    sphd_daemon *d = arg;
    prctl(PR_SET_NAME, "sphd-files", 0, 0, 0);
    void *sock = sphd_pair_open(d->ctx, FILES_ENDPOINT, 0);
    if (!sock)
        return NULL;
    for (;;) {
        sphd_fcmd cmd;
        int n = zmq_recv(sock, &cmd, sizeof cmd, 0);
        if (n < 0 && errno == EINTR)
            continue;
        if (n != (int)sizeof cmd || cmd.kind == SPHD_F_QUIT) {
            sphd_fev bye = {.token = -1}; /* after every answer: the loop may stop reading */
            sphd_pair_send(sock, &bye, sizeof bye);
            break;
        }
        sphd_fev ev = {.token = cmd.token, .job = cmd.job};
        if (cmd.kind == SPHD_F_PARTICLES) {
            ev.exec_read = 1;
            sphd_exec *x = cmd.exec;
            if (!x) /* a paused job of the Slurm executor: its particles are in its checkpoint */
                x = checkpoint_exec(&cmd);
            ev.text =
                x ? sphd_particles_reply(x, cmd.job->c, cmd.fields, cmd.max, cmd.status, cmd.id)
                  : no_checkpoint_reply(&cmd);
            if (x && x != cmd.exec)
                sphd_exec_free(x);
            json_decref(cmd.fields);
            if (!ev.text)
                sphd_err_set(&ev.err, SPHD_E_INTERNAL, NULL, "out of memory");
        } else {
            ev.body = sphd_files_do(&cmd, &ev.err);
        }
        free(cmd.file);
        if (sphd_pair_send(sock, &ev, sizeof ev) != 0) {
            sphd_log("files thread: cannot answer: %s", zmq_strerror(errno));
            json_decref(ev.body);
            free(ev.text);
        }
    }
    zmq_close(sock);
    return NULL;
}

int sphd_files_start(sphd_daemon *d)
{
    d->files = sphd_pair_open(d->ctx, FILES_ENDPOINT, 1);
    if (!d->files)
        return -1;
    int rc = pthread_create(&d->files_thread, NULL, files_main, d);
    if (rc != 0) {
        sphd_log("cannot start the files thread: %s", strerror(rc));
        return -1;
    }
    d->files_started = 1;
    return 0;
}

int sphd_files_send(sphd_daemon *d, sphd_fcmd *cmd, const sphd_pending *from, sphd_err *e)
{
    sphd_pending *p = sphd_pending_copy(from);
    if (!p) {
        free(cmd->file);
        return sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
    }
    cmd->token = p->token = ++d->next_token;
    if (sphd_pair_send(d->files, cmd, sizeof *cmd) != 0) {
        free(cmd->file);
        json_decref(cmd->fields);
        json_decref(cmd->status);
        json_decref(cmd->id);
        sphd_pending_free(p);
        return sphd_err_set(e, SPHD_E_INTERNAL, NULL, "cannot reach the files thread: %s",
                            zmq_strerror(errno));
    }
    p->next = d->file_waits;
    d->file_waits = p;
    cmd->job->readers++;
    if (cmd->kind == SPHD_F_PARTICLES)
        cmd->job->exec_readers++;
    return 1;
}

/* Replies to the answers the files thread sent; with wait, blocks until its last (token -1).
 * Returns 1 once that last answer came. */
static int take_answers(sphd_daemon *d, int wait)
{
    for (;;) {
        sphd_fev ev;
        int n = zmq_recv(d->files, &ev, sizeof ev, wait ? 0 : ZMQ_DONTWAIT);
        if (n < 0) {
            if (errno == EINTR)
                continue;
            return 0;
        }
        if (n != (int)sizeof ev)
            continue;
        if (ev.token == -1)
            return 1;
        sphd_job *j = ev.job;
        if (j) {
            j->readers--;
            if (ev.exec_read && --j->exec_readers == 0 && sphd_job_state_final(j->state)) {
                sphd_exec_free(j->exec); /* stopped while it was read */
                j->exec = NULL;
            }
        }
        sphd_pending *p = sphd_pending_take(&d->file_waits, ev.token);
        if (!p) {
            json_decref(ev.body);
            free(ev.text);
            continue;
        }
        if (ev.text)
            sphd_reply_text(d, p, ev.text);
        else
            sphd_reply(d, p, ev.body, ev.body ? NULL : &ev.err);
        sphd_pending_free(p);
    }
}

void sphd_files_on_answer(sphd_daemon *d)
{
    take_answers(d, 0);
}

void sphd_files_stop(sphd_daemon *d)
{
    if (d->files_started) {
        /* the thread answers what it was sent before the quit, then says so and ends */
        sphd_fcmd q = {.kind = SPHD_F_QUIT};
        int wait_ms = 60000; /* a thread that died early never says its last */
        zmq_setsockopt(d->files, ZMQ_RCVTIMEO, &wait_ms, sizeof wait_ms);
        if (sphd_pair_send(d->files, &q, sizeof q) == 0 && take_answers(d, 1))
            pthread_join(d->files_thread, NULL);
        else
            pthread_detach(d->files_thread);
        d->files_started = 0;
    }
    if (d->files) {
        zmq_close(d->files);
        d->files = NULL;
    }
    while (d->file_waits) { /* never answered (the thread failed): free them */
        sphd_pending *p = d->file_waits;
        d->file_waits = p->next;
        sphd_pending_free(p);
    }
}

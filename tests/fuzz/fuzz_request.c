/*
 * Fuzz target: the request envelope and the dispatcher's argument checking (sphd_dispatch, the
 * command table), on a daemon that has a PUB socket but no workers (jobs stay queued), as
 * tests/unit/test_commands.c drives it. Input: up to 8 requests, one per line, dispatched in
 * order (so a submit can be followed by requests about its job); the state is reset after each
 * input. Every request that is answered at once must get a reply that is one JSON object.
 */
#include "fuzz_util.h"

#include "sphd_daemon.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zmq.h>

#define MAX_REQUESTS 8

static void free_list(sphd_pending **list)
{
    while (*list) {
        sphd_pending *p = *list;
        *list = p->next;
        sphd_pending_free(p);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static void *ctx, *pub;
    if (!ctx) {
        ctx = zmq_ctx_new();
        pub = ctx ? zmq_socket(ctx, ZMQ_PUB) : NULL;
        if (!pub || zmq_bind(pub, "inproc://fuzz-stream") != 0)
            abort();
    }
    sphd_daemon *d = calloc(1, sizeof *d);
    if (!d)
        return 0;
    snprintf(d->opts.state_dir, sizeof d->opts.state_dir, "%s", sph_fuzz_dir());
    snprintf(d->opts.publish, sizeof d->opts.publish, "inproc://fuzz-stream");
    d->opts.threads = 1;
    d->opts.max_jobs = 3;
    d->opts.max_msg_size = 1 << 20;
    d->opts.diag_rate = 50;
    d->ctx = ctx;
    d->pub = pub;
    d->started_at = sphd_now();
    atomic_init(&d->busy, 0);

    const char *p = (const char *)data, *end = p + size;
    for (int k = 0; k < MAX_REQUESTS && p < end; k++) {
        const char *nl = memchr(p, '\n', (size_t)(end - p));
        size_t len = nl ? (size_t)(nl - p) : (size_t)(end - p);
        unsigned char ident[5] = {0, 0x6b, 0x8b, 0x45, (unsigned char)k};
        sphd_pending from = {.nframes = 1, .op = "?"};
        from.frame[0] = ident;
        from.len[0] = sizeof ident;
        char *reply = sphd_dispatch(d, &from, p, len);
        if (reply) {
            json_t *r = json_loads(reply, 0, NULL);
            if (!json_is_object(r) || !json_object_get(r, "ok"))
                abort(); /* every reply is one JSON object with "ok" */
            json_decref(r);
            free(reply);
        }
        p += len + (nl != NULL);
    }
    free_list(&d->shutdown_waits);
    free_list(&d->particle_waits);
    free_list(&d->file_waits);
    int had_jobs = d->jobs != NULL;
    sphd_jobs_free(d);
    free(d);
    if (had_jobs)
        sph_fuzz_empty(sph_fuzz_dir());
    return 0;
}

/*
 * Fuzz target: the job journal reader, as sphd takes its jobs up again after a restart
 * (sphd_jobs_recover: the journal's records replayed, job.json, the state, seq and reason taken
 * from them). One job directory holds a fixed valid case.json and, from the input, journal.jsonl
 * and, after a NUL byte when there is one, job.json.
 */
#include "fuzz_util.h"

#include "sphd.h"
#include "sphd_daemon.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <zmq.h>

static const char case_text[] =
    "{\"name\":\"ks\",\"method\":\"kernel_study\",\"domain\":{\"min\":[0],\"max\":[6]},"
    "\"particles\":11,\"kernels\":[{\"type\":\"cubic_spline\"}]}";

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static void *ctx, *pub;
    if (!ctx) {
        ctx = zmq_ctx_new();
        pub = ctx ? zmq_socket(ctx, ZMQ_PUB) : NULL;
        if (!pub || zmq_bind(pub, "inproc://fuzz-stream") != 0)
            abort();
    }
    const char *root = sph_fuzz_dir();
    char job[512];
    snprintf(job, sizeof job, "%s/jobs/j1", root);
    if (sphd_mkdirs(job) != 0 || sph_fuzz_write(job, "case.json", case_text, strlen(case_text)))
        abort();
    const char *nul = memchr(data, '\0', size);
    size_t jlen = nul ? (size_t)(nul - (const char *)data) : size;
    sph_fuzz_write(job, "journal.jsonl", data, jlen);
    if (nul)
        sph_fuzz_write(job, "job.json", nul + 1, size - jlen - 1);

    sphd_daemon *d = calloc(1, sizeof *d);
    if (!d)
        return 0;
    snprintf(d->opts.state_dir, sizeof d->opts.state_dir, "%s", root);
    d->opts.threads = 1;
    d->opts.max_jobs = 4;
    d->opts.max_msg_size = 1 << 20;
    d->ctx = ctx;
    d->pub = pub;
    sphd_jobs_recover(d);
    for (sphd_job *j = d->jobs; j; j = j->next) {
        json_t *s = sphd_job_status(j);
        json_decref(s);
    }
    sphd_jobs_free(d);
    free(d);
    sph_fuzz_empty(root);
    return 0;
}

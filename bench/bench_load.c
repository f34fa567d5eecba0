/*
 * bench_load: request latency of sphd under load, and what the load costs the running jobs.
 *
 *     bench_load --endpoint EP [--clients 32] [--seconds 10] [--quiet-seconds 5] [--rate R] JOB...
 *
 * With the given jobs running in sphd, measures their progress (steps/s, and particle-steps/s
 * when the job has particles) for --quiet-seconds without load, then for --seconds while
 * --clients threads each send status queries (`query` of a job, and every 8th a `list`) in a
 * closed loop over their own DEALER socket (as fast as replies come, or paced at R requests per
 * second per client with --rate), then quiet again. Prints requests/s, latency
 * percentiles (p50, p90, p99, max) and the jobs' slowdown. Figures, never pass/fail.
 */
#include <errno.h>
#include <getopt.h>
#include <jansson.h>
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <zmq.h>

#define MAX_JOBS 16

typedef struct bench {
    const char *endpoint;
    const char *jobs[MAX_JOBS];
    int njobs;
    int clients;
    double seconds, quiet;
    double rate; /* requests per second per client; 0: closed loop, no pause */
    void *ctx;
    atomic_int go, stop;
    atomic_long errors;
} bench;

typedef struct client {
    bench *b;
    int index;
    double *lat; /* seconds */
    size_t n, cap;
    long replies;
} client;

static double mono(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void *open_dealer(bench *b)
{
    void *s = zmq_socket(b->ctx, ZMQ_DEALER);
    int zero = 0;
    if (!s || zmq_setsockopt(s, ZMQ_LINGER, &zero, sizeof zero) != 0 ||
        zmq_connect(s, b->endpoint) != 0) {
        fprintf(stderr, "bench_load: cannot connect to %s: %s\n", b->endpoint, zmq_strerror(errno));
        exit(69);
    }
    return s;
}

/* One request, one reply (5 s at most). Returns the reply (new ref) or NULL. */
static json_t *rpc(void *s, const char *text)
{
    if (zmq_send(s, text, strlen(text), 0) < 0)
        return NULL;
    zmq_pollitem_t it = {.socket = s, .events = ZMQ_POLLIN};
    if (zmq_poll(&it, 1, 5000) <= 0)
        return NULL;
    zmq_msg_t m;
    zmq_msg_init(&m);
    if (zmq_msg_recv(&m, s, 0) < 0) {
        zmq_msg_close(&m);
        return NULL;
    }
    json_t *r = json_loadb(zmq_msg_data(&m), zmq_msg_size(&m), 0, NULL);
    zmq_msg_close(&m);
    return r;
}

static void sleep_s(double s)
{
    struct timespec ts = {(time_t)s, (long)((s - (double)(time_t)s) * 1e9)};
    while (nanosleep(&ts, &ts) != 0 && errno == EINTR)
        ;
}

static void *client_main(void *arg)
{
    client *c = arg;
    bench *b = c->b;
    void *s = open_dealer(b);
    char req[2][MAX_JOBS][256];
    for (int j = 0; j < b->njobs; j++) {
        snprintf(req[0][j], sizeof req[0][j],
                 "{\"v\":1,\"id\":\"c%d\",\"op\":\"query\",\"args\":{\"job\":\"%s\"}}", c->index,
                 b->jobs[j]);
        snprintf(req[1][j], sizeof req[1][j], "{\"v\":1,\"id\":\"c%d\",\"op\":\"list\"}", c->index);
    }
    while (!atomic_load(&b->go))
        sleep_s(0.0001);
    long k = 0;
    const double period = b->rate > 0 ? 1.0 / b->rate : 0;
    double next = mono() + period * c->index / b->clients; /* staggered */
    while (!atomic_load(&b->stop)) {
        if (period > 0) {
            double now = mono();
            if (next > now)
                sleep_s(next - now);
            next += period;
        }
        const char *text = req[k % 8 == 7][k % b->njobs];
        k++;
        double t0 = mono();
        json_t *r = rpc(s, text);
        double dt = mono() - t0;
        if (!r || !json_is_true(json_object_get(r, "ok"))) {
            atomic_fetch_add(&b->errors, 1);
            json_decref(r);
            if (!r) { /* a lost reply: start over on a new socket */
                zmq_close(s);
                s = open_dealer(b);
            }
            continue;
        }
        json_decref(r);
        if (c->n == c->cap) {
            c->cap = c->cap ? 2 * c->cap : 4096;
            c->lat = realloc(c->lat, c->cap * sizeof *c->lat);
            if (!c->lat)
                exit(70);
        }
        c->lat[c->n++] = dt;
    }
    zmq_close(s);
    return NULL;
}

typedef struct sample {
    double wall;
    long steps[MAX_JOBS];
    double t[MAX_JOBS];
    char state[MAX_JOBS][16];
} sample;

static long particles_of(void *s, const char *job)
{
    char text[512];
    snprintf(text, sizeof text,
             "{\"v\":1,\"id\":\"p\",\"op\":\"query\",\"args\":{\"job\":\"%s\",\"fields\":[\"id\"],"
             "\"max\":1}}",
             job);
    json_t *r = rpc(s, text);
    json_t *p =
        json_object_get(json_object_get(json_object_get(r, "result"), "particles"), "total");
    long n = json_is_integer(p) ? (long)json_integer_value(p) : 0;
    json_decref(r);
    return n;
}

static void take_sample(bench *b, void *s, sample *out)
{
    out->wall = mono();
    for (int j = 0; j < b->njobs; j++) {
        char text[256];
        snprintf(text, sizeof text,
                 "{\"v\":1,\"id\":\"s\",\"op\":\"query\",\"args\":{\"job\":\"%s\"}}", b->jobs[j]);
        json_t *r = rpc(s, text);
        json_t *res = json_object_get(r, "result");
        json_t *p = json_object_get(res, "progress");
        out->steps[j] = (long)json_integer_value(json_object_get(p, "steps"));
        json_t *t = json_object_get(p, "t");
        out->t[j] = json_is_number(t) ? json_number_value(t) : NAN;
        const char *st = json_string_value(json_object_get(res, "state"));
        snprintf(out->state[j], sizeof out->state[j], "%s", st ? st : "?");
        json_decref(r);
    }
}

/* Steps per second of each job between two samples; their sum into *total. */
static void rates(bench *b, const sample *a, const sample *z, double *r, double *total)
{
    *total = 0;
    for (int j = 0; j < b->njobs; j++) {
        r[j] = (double)(z->steps[j] - a->steps[j]) / (z->wall - a->wall);
        *total += r[j];
    }
}

static int cmp_double(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return a < b ? -1 : a > b;
}

int main(int argc, char **argv)
{
    bench b = {.clients = 32, .seconds = 10, .quiet = 5};
    static const struct option lo[] = {{"endpoint", required_argument, NULL, 'e'},
                                       {"clients", required_argument, NULL, 'c'},
                                       {"seconds", required_argument, NULL, 's'},
                                       {"quiet-seconds", required_argument, NULL, 'q'},
                                       {"rate", required_argument, NULL, 'r'},
                                       {"help", no_argument, NULL, 'h'},
                                       {NULL, 0, NULL, 0}};
    int o;
    b.endpoint = getenv("SPHD_ENDPOINT");
    while ((o = getopt_long(argc, argv, "h", lo, NULL)) != -1) {
        switch (o) {
        case 'e':
            b.endpoint = optarg;
            break;
        case 'c':
            b.clients = atoi(optarg);
            break;
        case 's':
            b.seconds = atof(optarg);
            break;
        case 'q':
            b.quiet = atof(optarg);
            break;
        case 'r':
            b.rate = atof(optarg);
            break;
        default:
            fprintf(o == 'h' ? stdout : stderr,
                    "Usage: bench_load --endpoint EP [--clients 32] [--seconds 10] "
                    "[--quiet-seconds 5] [--rate R] JOB...\n");
            return o == 'h' ? 0 : 64;
        }
    }
    for (; optind < argc && b.njobs < MAX_JOBS; optind++)
        b.jobs[b.njobs++] = argv[optind];
    if (!b.endpoint || b.njobs == 0 || b.clients < 1 || b.clients > 1024 || !(b.seconds > 0)) {
        fprintf(stderr, "bench_load: needs --endpoint (or SPHD_ENDPOINT) and at least one JOB\n");
        return 64;
    }
    b.ctx = zmq_ctx_new();
    void *s = open_dealer(&b);
    long particles[MAX_JOBS];
    for (int j = 0; j < b.njobs; j++)
        particles[j] = particles_of(s, b.jobs[j]);

    sample q0, q1, l0, l1, q2, q3;
    double rq[MAX_JOBS], rl[MAX_JOBS], rq2[MAX_JOBS], tq, tl, tq2;
    take_sample(&b, s, &q0);
    sleep_s(b.quiet);
    take_sample(&b, s, &q1);

    client *cl = calloc((size_t)b.clients, sizeof *cl);
    pthread_t *th = calloc((size_t)b.clients, sizeof *th);
    for (int i = 0; i < b.clients; i++) {
        cl[i] = (client){.b = &b, .index = i};
        pthread_create(&th[i], NULL, client_main, &cl[i]);
    }
    sleep_s(0.2); /* all connected */
    take_sample(&b, s, &l0);
    atomic_store(&b.go, 1);
    sleep_s(b.seconds);
    atomic_store(&b.stop, 1);
    take_sample(&b, s, &l1);
    for (int i = 0; i < b.clients; i++)
        pthread_join(th[i], NULL);
    const double load_wall = l1.wall - l0.wall;

    take_sample(&b, s, &q2);
    sleep_s(b.quiet);
    take_sample(&b, s, &q3);

    size_t n = 0;
    for (int i = 0; i < b.clients; i++)
        n += cl[i].n;
    double *all = malloc((n ? n : 1) * sizeof *all);
    size_t k = 0;
    for (int i = 0; i < b.clients; i++) {
        memcpy(all + k, cl[i].lat, cl[i].n * sizeof *all);
        k += cl[i].n;
        free(cl[i].lat);
    }
    qsort(all, n, sizeof *all, cmp_double);
#define PCT(p) (n ? 1e3 * all[(size_t)((p) / 100.0 * (double)(n - 1))] : NAN)
    printf("sphd load test: %d clients, %.1f s, %d job(s) running, ", b.clients, load_wall,
           b.njobs);
    if (b.rate > 0)
        printf("each client paced at %.0f requests/s\n", b.rate);
    else
        printf("closed loop (each client sends as soon as it has its reply)\n");
    printf("  requests      %zu ok, %ld failed\n", n, atomic_load(&b.errors));
    printf("  throughput    %.0f requests/s\n", (double)n / load_wall);
    printf("  latency (ms)  p50 %.3f  p90 %.3f  p99 %.3f  max %.3f\n", PCT(50), PCT(90), PCT(99),
           n ? 1e3 * all[n - 1] : NAN);
    rates(&b, &q0, &q1, rq, &tq);
    rates(&b, &l0, &l1, rl, &tl);
    rates(&b, &q2, &q3, rq2, &tq2);
    for (int j = 0; j < b.njobs; j++) {
        double quiet = 0.5 * (rq[j] + rq2[j]);
        printf("  job %-16s quiet %.1f steps/s, loaded %.1f steps/s", b.jobs[j], quiet, rl[j]);
        if (particles[j] > 0)
            printf(" (%ld particles: %.3g vs %.3g particle-steps/s)", particles[j],
                   quiet * (double)particles[j], rl[j] * (double)particles[j]);
        printf(", slowed %.1f%%%s\n", quiet > 0 ? 100.0 * (1 - rl[j] / quiet) : NAN,
               strcmp(q3.state[j], "running") ? " (NOT running all along: extend the job)" : "");
    }
    double quiet_total = 0.5 * (tq + tq2);
    if (fabs(tq - tq2) > 0.1 * quiet_total)
        printf("  note: the quiet phases before and after differ by %.0f%% (%.1f vs %.1f steps/s): "
               "something else uses the CPUs, the slowdown is not reliable\n",
               100.0 * fabs(tq - tq2) / quiet_total, tq, tq2);
    printf("  all jobs      quiet %.1f steps/s, loaded %.1f steps/s: slowed %.1f%%\n", quiet_total,
           tl, quiet_total > 0 ? 100.0 * (1 - tl / quiet_total) : NAN);
    free(all);
    free(cl);
    free(th);
    zmq_close(s);
    zmq_ctx_term(b.ctx);
    return 0;
}

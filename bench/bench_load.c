/*
 * bench_load: request latency of sphd under load, and what the load costs the running jobs.
 *
 *     bench_load --endpoint EP [--clients 32] [--seconds 10] [--rounds 5] [--quiet-seconds 2]
 *                [--rates 10,100,0] [--cpu N|auto|any] JOB...
 *
 * With the given jobs running in sphd, it alternates quiet phases (no requests) with loaded
 * ones. In a loaded phase --clients connections (one DEALER socket each, all driven from this
 * one thread so that the load generator itself costs little CPU) send status queries (`query`
 * of a job, and every 8th a `list`), each client paced at RATE requests/s, or for rate 0 in a
 * closed loop (a client sends as soon as it has its reply). Each rate gets --rounds loaded
 * phases of --seconds/--rounds seconds, the rates taking turns, every loaded phase between two
 * quiet ones: the jobs' speed drifts (a shared machine, a flow that evolves), and a short
 * loaded phase compared with the quiet phases on either side sees little of the drift.
 *
 * Prints per rate: requests/s, latency percentiles (p50, p90, p99, max), how much the jobs
 * slowed (the median over the rounds of 1 - loaded steps/s over the mean of the neighbouring
 * quiet phases), and where the CPU went, from /proc when sphd runs on this machine: the solver
 * threads, sphd's socket loop, its ZeroMQ I/O thread, the load generator, everything else.
 * --cpu N pins the load generator (and its I/O thread) to CPU N, as sphd keeps its own request
 * threads on one CPU. Figures, never pass/fail.
 */
#define _GNU_SOURCE /* memmem */
#include <dirent.h>
#include <errno.h>
#include <getopt.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <zmq.h>

#include "sphd_daemon.h" /* sphd_sched_request_threads */

#define MAX_JOBS    16
#define MAX_RATES   8
#define MAX_CLIENTS 1024

typedef struct bench {
    const char *endpoint;
    const char *jobs[MAX_JOBS];
    int njobs;
    int clients;
    double seconds, quiet;
    double rates[MAX_RATES]; /* requests per second per client; 0: closed loop */
    int nrates;
    void *ctx;
    long sphd_pid;
} bench;

static void sleep_s(double s)
{
    if (s <= 0)
        return;
    struct timespec ts = {(time_t)s, (long)((s - (double)(time_t)s) * 1e9)};
    while (nanosleep(&ts, &ts) != 0 && errno == EINTR)
        ;
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

/* ---- CPU accounting from /proc ---------------------------------------------------------- */

/* solver threads, sphd's request threads (socket loop, ZeroMQ), the load generator, the rest */
enum { CPU_SOLVER, CPU_SPHD, CPU_GEN, CPU_OTHER, CPU_N };
typedef struct cpu {
    double s[CPU_N]; /* CPU seconds since some origin */
    double wall;
} cpu;

/* The run time (schedstat) of process PID's threads ("self" or a number): the solver threads'
 * (named sphd-worker-N) added to *solver, all the others' to *rest. */
static int read_threads(const char *pid, double *solver, double *rest)
{
    char path[300];
    snprintf(path, sizeof path, "/proc/%s/task", pid);
    DIR *dir = opendir(path);
    if (!dir)
        return -1;
    struct dirent *e;
    while ((e = readdir(dir)) != NULL) {
        if (e->d_name[0] == '.')
            continue;
        char comm[64] = "", p[600];
        unsigned long long ns = 0;
        snprintf(p, sizeof p, "%s/%s/comm", path, e->d_name);
        FILE *f = fopen(p, "r");
        if (!f)
            continue;
        if (!fgets(comm, sizeof comm, f))
            comm[0] = '\0';
        fclose(f);
        snprintf(p, sizeof p, "%s/%s/schedstat", path, e->d_name);
        f = fopen(p, "r");
        if (!f)
            continue;
        if (fscanf(f, "%llu", &ns) != 1)
            ns = 0;
        fclose(f);
        *(strncmp(comm, "sphd-worker", 11) ? rest : solver) += 1e-9 * (double)ns;
    }
    closedir(dir);
    return 0;
}

static void cpu_read(bench *b, cpu *c)
{
    memset(c, 0, sizeof *c);
    c->wall = sphd_mono();
    if (b->sphd_pid > 0) {
        char pid[32];
        snprintf(pid, sizeof pid, "%ld", b->sphd_pid);
        read_threads(pid, &c->s[CPU_SOLVER], &c->s[CPU_SPHD]);
    }
    double none = 0;
    read_threads("self", &none, &c->s[CPU_GEN]);
    /* the whole machine: its busy time, less what the threads above used */
    FILE *f = fopen("/proc/stat", "r");
    unsigned long long v[10] = {0};
    if (f) {
        if (fscanf(f, "cpu %llu %llu %llu %llu %llu %llu %llu %llu", &v[0], &v[1], &v[2], &v[3],
                   &v[4], &v[5], &v[6], &v[7]) != 8)
            memset(v, 0, sizeof v);
        fclose(f);
    }
    const double tick = 1.0 / (double)sysconf(_SC_CLK_TCK);
    const double busy = (double)(v[0] + v[1] + v[2] + v[5] + v[6] + v[7]) * tick;
    c->s[CPU_OTHER] = busy - (c->s[CPU_SOLVER] + c->s[CPU_SPHD] + c->s[CPU_GEN]);
}

/* ---- the jobs' progress ----------------------------------------------------------------- */

typedef struct sample {
    double wall;
    long steps[MAX_JOBS];
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

static long pid_of(void *s)
{
    json_t *r = rpc(s, "{\"v\":1,\"id\":\"h\",\"op\":\"hello\"}");
    json_t *p = json_object_get(json_object_get(r, "result"), "pid");
    long pid = json_is_integer(p) ? (long)json_integer_value(p) : 0;
    json_decref(r);
    return pid;
}

static void take_sample(bench *b, void *s, sample *out)
{
    out->wall = sphd_mono();
    for (int j = 0; j < b->njobs; j++) {
        char text[256];
        snprintf(text, sizeof text,
                 "{\"v\":1,\"id\":\"s\",\"op\":\"query\",\"args\":{\"job\":\"%s\"}}", b->jobs[j]);
        json_t *r = rpc(s, text);
        json_t *res = json_object_get(r, "result");
        out->steps[j] =
            (long)json_integer_value(json_object_get(json_object_get(res, "progress"), "steps"));
        const char *st = json_string_value(json_object_get(res, "state"));
        snprintf(out->state[j], sizeof out->state[j], "%s", st ? st : "?");
        json_decref(r);
    }
}

/* ---- one phase -------------------------------------------------------------------------- */

typedef struct conn {
    void *s;
    int busy;
    double sent, next;
    long k;
} conn;

typedef struct phase {
    double rate; /* < 0: quiet */
    sample a, z;
    cpu ca, cz;
    double steps_per_s; /* all jobs */
} phase;

typedef struct result { /* one rate, over its rounds */
    double *lat;        /* seconds */
    size_t n, cap;
    long errors;
    char first_error[160];
    double wall;
} result;

static void lat_push(result *r, double dt)
{
    if (r->n == r->cap) {
        r->cap = r->cap ? 2 * r->cap : 65536;
        r->lat = realloc(r->lat, r->cap * sizeof *r->lat);
        if (!r->lat)
            exit(70);
    }
    r->lat[r->n++] = dt;
}

static void fail(result *r, const char *what, size_t len)
{
    r->errors++;
    if (!r->first_error[0])
        snprintf(r->first_error, sizeof r->first_error, "%.*s", (int)(len < 150 ? len : 150), what);
}

static int cmp_double(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return a < b ? -1 : a > b;
}

/* The load for `seconds`: all clients from this thread, over one zmq_poll of the sockets that
 * await a reply (zmq_poll costs per item). */
static void run_load(bench *b, conn *c, double rate, double seconds, result *r, char (*req)[256],
                     int nreq)
{
    const int n = b->clients;
    zmq_pollitem_t items[MAX_CLIENTS];
    int who[MAX_CLIENTS];
    const double period = rate > 0 ? 1.0 / rate : 0;
    const double t0 = sphd_mono(), t_stop = t0 + seconds;
    for (int i = 0; i < n; i++)
        c[i].next = t0 + period * i / n; /* staggered */
    for (;;) {
        double now = sphd_mono();
        int busy = 0;
        double wake = now + 0.1;
        for (int i = 0; i < n; i++) {
            if (!c[i].busy && now < t_stop && c[i].next <= now) {
                const char *text = req[c[i].k % 8 == 7 ? nreq - 1 : (int)(c[i].k % (nreq - 1))];
                c[i].k++;
                c[i].sent = sphd_mono();
                if (zmq_send(c[i].s, text, strlen(text), 0) < 0) {
                    fail(r, zmq_strerror(errno), strlen(zmq_strerror(errno)));
                    continue;
                }
                c[i].busy = 1;
                if (period > 0)
                    c[i].next += period;
            }
            if (c[i].busy && now - c[i].sent > 5.0) { /* a lost reply: a new socket */
                fail(r, "no reply in 5 s", 15);
                zmq_close(c[i].s);
                c[i].s = open_dealer(b);
                c[i].busy = 0;
            }
            if (c[i].busy) {
                items[busy] = (zmq_pollitem_t){.socket = c[i].s, .events = ZMQ_POLLIN};
                who[busy++] = i;
            } else if (now < t_stop && c[i].next < wake) {
                wake = c[i].next;
            }
        }
        if (now >= t_stop && busy == 0)
            break;
        long ms = (long)ceil(1e3 * (wake - now));
        if (zmq_poll(items, busy, ms < 0 ? 0 : ms) <= 0)
            continue;
        for (int k = 0; k < busy; k++) {
            if (!(items[k].revents & ZMQ_POLLIN))
                continue;
            const int i = who[k];
            zmq_msg_t m;
            zmq_msg_init(&m);
            if (zmq_msg_recv(&m, c[i].s, ZMQ_DONTWAIT) < 0) {
                zmq_msg_close(&m);
                continue;
            }
            const double dt = sphd_mono() - c[i].sent;
            c[i].busy = 0;
            const char *data = zmq_msg_data(&m);
            const size_t len = zmq_msg_size(&m);
            if (memmem(data, len, "\"ok\":true", 9))
                lat_push(r, dt);
            else
                fail(r, data, len);
            zmq_msg_close(&m);
        }
    }
    r->wall += sphd_mono() - t0;
}

static void run_phase(bench *b, void *s, phase *ph, conn *c, double seconds, result *r,
                      char (*req)[256], int nreq)
{
    take_sample(b, s, &ph->a);
    cpu_read(b, &ph->ca);
    if (ph->rate < 0)
        sleep_s(seconds);
    else
        run_load(b, c, ph->rate, seconds, r, req, nreq);
    cpu_read(b, &ph->cz);
    take_sample(b, s, &ph->z);
    long steps = 0;
    for (int j = 0; j < b->njobs; j++)
        steps += ph->z.steps[j] - ph->a.steps[j];
    ph->steps_per_s = (double)steps / (ph->z.wall - ph->a.wall);
}

static double cpu_used(const phase *ph, int k) /* CPU seconds */
{
    return ph->cz.s[k] - ph->ca.s[k];
}

static int parse_rates(bench *b, const char *arg)
{
    b->nrates = 0;
    char *copy = strdup(arg), *save = NULL;
    for (char *t = strtok_r(copy, ",", &save); t; t = strtok_r(NULL, ",", &save)) {
        char *end;
        double r = strtod(t, &end);
        if (*end || !(r >= 0) || b->nrates == MAX_RATES) {
            free(copy);
            return -1;
        }
        b->rates[b->nrates++] = r;
    }
    free(copy);
    return b->nrates > 0 ? 0 : -1;
}

static void usage(FILE *f)
{
    fprintf(f,
            "Usage: bench_load --endpoint EP [--clients 32] [--seconds 10] [--rounds 5]\n"
            "                  [--quiet-seconds 2] [--rates 10,100,0] [--cpu N|auto|any] JOB...\n"
            "  --rates R,...  requests/s per client, one series of loaded phases per rate; "
            "0 = closed loop\n"
            "  --seconds S    loaded time per rate, split over --rounds phases\n"
            "  --cpu N        pin the load generator (this thread and its I/O thread) to CPU N;\n"
            "                 auto: the last CPU it may use (where sphd keeps its request\n"
            "                 threads); any: not pinned (the default)\n");
}

int main(int argc, char **argv)
{
    bench b = {.clients = 32, .seconds = 10, .quiet = 2};
    int rounds = 5, cpu = SPHD_CPU_ANY;
    parse_rates(&b, "10,100,0");
    static const struct option lo[] = {{"endpoint", required_argument, NULL, 'e'},
                                       {"clients", required_argument, NULL, 'c'},
                                       {"seconds", required_argument, NULL, 's'},
                                       {"rounds", required_argument, NULL, 'n'},
                                       {"quiet-seconds", required_argument, NULL, 'q'},
                                       {"rates", required_argument, NULL, 'r'},
                                       {"rate", required_argument, NULL, 'r'},
                                       {"cpu", required_argument, NULL, 'p'},
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
        case 'n':
            rounds = atoi(optarg);
            break;
        case 'q':
            b.quiet = atof(optarg);
            break;
        case 'r':
            if (parse_rates(&b, optarg) != 0) {
                fprintf(stderr, "bench_load: --rates takes requests/s per client, comma "
                                "separated, 0 for a closed loop (e.g. 10,100,0)\n");
                return 64;
            }
            break;
        case 'p':
            cpu = !strcmp(optarg, "auto")  ? SPHD_CPU_AUTO
                  : !strcmp(optarg, "any") ? SPHD_CPU_ANY
                                           : atoi(optarg);
            break;
        case 'h':
            usage(stdout);
            return 0;
        default:
            usage(stderr);
            return 64;
        }
    }
    for (; optind < argc && b.njobs < MAX_JOBS; optind++)
        b.jobs[b.njobs++] = argv[optind];
    if (!b.endpoint || b.njobs == 0 || b.clients < 1 || b.clients > MAX_CLIENTS ||
        !(b.seconds > 0) || !(b.quiet > 0) || rounds < 1 || rounds > 100) {
        usage(stderr);
        return 64;
    }
    b.ctx = zmq_ctx_new();
    /* the generator as sphd keeps its own request threads (sphd_sched.c): this thread and the
     * ZeroMQ threads on one CPU */
    char sched_what[48] = "";
    if (cpu != SPHD_CPU_ANY) {
        cpu = sphd_sched_pick_cpu(cpu);
        if (cpu < 0 || sphd_sched_zmq_threads(b.ctx, cpu) != 0 || sphd_sched_pin_self(cpu) != 0) {
            fprintf(stderr, "bench_load: --cpu: cannot run on that CPU\n");
            return 64;
        }
        snprintf(sched_what, sizeof sched_what, "on CPU %d", cpu);
    }
    void *s = open_dealer(&b);
    b.sphd_pid = pid_of(s);
    char proc[64];
    snprintf(proc, sizeof proc, "/proc/%ld/task", b.sphd_pid);
    if (b.sphd_pid > 0 && access(proc, R_OK) != 0)
        b.sphd_pid = 0; /* another machine (or namespace): no per-thread figures */
    long particles = 0;
    for (int j = 0; j < b.njobs; j++)
        particles += particles_of(s, b.jobs[j]);

    char req[MAX_JOBS + 1][256];
    for (int j = 0; j < b.njobs; j++)
        snprintf(req[j], sizeof req[j],
                 "{\"v\":1,\"id\":\"c\",\"op\":\"query\",\"args\":{\"job\":\"%s\"}}", b.jobs[j]);
    snprintf(req[b.njobs], sizeof req[b.njobs], "{\"v\":1,\"id\":\"c\",\"op\":\"list\"}");
    conn *c = calloc((size_t)b.clients, sizeof *c);
    result *res = calloc((size_t)b.nrates, sizeof *res);
    /* Q L Q L ... Q, the rates taking turns */
    const int nload = b.nrates * rounds, nph = 2 * nload + 1;
    phase *ph = calloc((size_t)nph, sizeof *ph);
    if (!c || !res || !ph)
        return 70;
    for (int i = 0; i < b.clients; i++)
        c[i].s = open_dealer(&b);
    sleep_s(0.3); /* all connected */
    for (int i = 0; i < nph; i++) {
        const int k = (i / 2) % b.nrates;
        ph[i].rate = i % 2 ? b.rates[k] : -1;
        run_phase(&b, s, &ph[i], c, i % 2 ? b.seconds / rounds : b.quiet, &res[k], req,
                  b.njobs + 1);
    }

    printf("sphd load test: %d clients (one DEALER socket each, driven from one thread%s%s), "
           "%d job(s) of %ld particles in all; per rate %d loaded phases of %.1f s, each "
           "between quiet phases of %.1f s\n",
           b.clients, sched_what[0] ? " " : "", sched_what, b.njobs, particles, rounds,
           b.seconds / rounds, b.quiet);
    printf("%-12s %7s %7s %7s %7s %7s %8s %7s", "load", "req/s", "p50 ms", "p90 ms", "p99 ms",
           "max ms", "slowed", "range");
    if (b.sphd_pid > 0)
        printf(" | CPU %% of a core: solver  sphd loop+zmq  generator  other | solver lost"
               "  sphd us/req");
    printf("\n");
    double quiet_cpu[CPU_N] = {0}, quiet_wall = 0;
    for (int i = 0; i < nph; i += 2) {
        for (int k = 0; k < CPU_N; k++)
            quiet_cpu[k] += cpu_used(&ph[i], k);
        quiet_wall += ph[i].cz.wall - ph[i].ca.wall;
    }
    double steps_lo = INFINITY, steps_hi = 0;
    int stale = 0;
    for (int i = 0; i < nph; i++) {
        if (ph[i].rate < 0) {
            steps_lo = fmin(steps_lo, ph[i].steps_per_s);
            steps_hi = fmax(steps_hi, ph[i].steps_per_s);
        }
        for (int j = 0; j < b.njobs; j++)
            if (strcmp(ph[i].z.state[j], "running"))
                stale = 1;
    }
    if (b.sphd_pid > 0) {
        printf("%-12s %7s %7s %7s %7s %7s %8s %7s | %27.1f %13.1f %10.1f %6.1f\n", "quiet", "-",
               "-", "-", "-", "-", "-", "-", 100 * quiet_cpu[CPU_SOLVER] / quiet_wall,
               100 * quiet_cpu[CPU_SPHD] / quiet_wall, 100 * quiet_cpu[CPU_GEN] / quiet_wall,
               100 * quiet_cpu[CPU_OTHER] / quiet_wall);
    }
    for (int k = 0; k < b.nrates; k++) {
        result *r = &res[k];
        double slow[100];
        int ns = 0;
        double cpu_l[CPU_N] = {0}, wall_l = 0;
        for (int i = 1; i < nph; i += 2) {
            if ((i / 2) % b.nrates != k)
                continue;
            const double quiet = 0.5 * (ph[i - 1].steps_per_s + ph[i + 1].steps_per_s);
            slow[ns++] = 100.0 * (1 - ph[i].steps_per_s / quiet);
            for (int m = 0; m < CPU_N; m++)
                cpu_l[m] += cpu_used(&ph[i], m);
            wall_l += ph[i].cz.wall - ph[i].ca.wall;
        }
        qsort(slow, (size_t)ns, sizeof *slow, cmp_double);
        qsort(r->lat, r->n, sizeof *r->lat, cmp_double);
        char name[32];
        if (b.rates[k] == 0)
            snprintf(name, sizeof name, "closed loop");
        else
            snprintf(name, sizeof name, "%g/s each", b.rates[k]);
        const double n = (double)r->n;
#define PCT(q) (r->n ? 1e3 * r->lat[(size_t)((q) / 100.0 * (n - 1))] : NAN)
        const double median = ns % 2 ? slow[ns / 2] : 0.5 * (slow[ns / 2 - 1] + slow[ns / 2]);
        char range[32];
        snprintf(range, sizeof range, "%.0f..%.0f", slow[0], slow[ns - 1]);
        printf("%-12s %7.0f %7.3f %7.3f %7.3f %7.3f %7.1f%% %7s", name, n / r->wall, PCT(50),
               PCT(90), PCT(99), r->n ? 1e3 * r->lat[r->n - 1] : NAN, median, range);
        if (b.sphd_pid > 0) {
            double sphd = cpu_l[CPU_SPHD];
            double sphd_quiet = quiet_cpu[CPU_SPHD] / quiet_wall;
            const double solver = cpu_l[CPU_SOLVER] / wall_l;
            printf(" | %27.1f %13.1f %10.1f %6.1f | %10.1f%% %12.1f", 100 * solver,
                   100 * sphd / wall_l, 100 * cpu_l[CPU_GEN] / wall_l,
                   100 * cpu_l[CPU_OTHER] / wall_l,
                   100 * (1 - solver / (quiet_cpu[CPU_SOLVER] / quiet_wall)),
                   r->n ? 1e6 * (sphd - sphd_quiet * wall_l) / n : NAN);
        }
        printf("\n");
        if (r->errors)
            printf("  %ld failed requests; the first: %s\n", r->errors, r->first_error);
    }
    printf("jobs' speed in the quiet phases: %.0f to %.0f steps/s (slowed: median over the "
           "rounds, range: the rounds' lowest and highest, in %%)\n",
           steps_lo, steps_hi);
    if (b.sphd_pid > 0)
        printf("solver lost: the CPU time the solver threads lost against the quiet phases, "
               "which the machine's drift does not blur\n");
    if (stale)
        printf("note: a job was NOT running all along: give the jobs a later time.end\n");
    for (int k = 0; k < b.nrates; k++)
        free(res[k].lat);
    for (int i = 0; i < b.clients; i++)
        zmq_close(c[i].s);
    free(res);
    free(ph);
    free(c);
    zmq_close(s);
    zmq_ctx_term(b.ctx);
    return 0;
}

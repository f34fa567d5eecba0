/* sphd: the simulation daemon. This file parses the command line and picks the mode. */
#include "sphd.h"
#include "sphd_daemon.h"
#include "sphd_h5_util.h"

#include "sph_endpoint.h"
#include "sph_sim.h"

#include <ctype.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char usage_text[] =
    "Usage: sphd [OPTIONS]                 run the daemon (foreground, logs to stderr)\n"
    "       sphd --run CASE.json [OPTIONS] run one case in the foreground, no socket\n"
    "\n"
    "Batch mode (--run):\n"
    "  --run FILE         the case file to run; events are printed as JSON Lines on stdout\n"
    "  --out DIR          where outputs go (default: out/JOB)\n"
    "  --set PATH=VALUE   override one field of the case by its dotted path, e.g.\n"
    "                     --set dx=0.004 --set kernel.type=cubic_spline (repeatable); the value\n"
    "                     is parsed as JSON where it parses, else taken as a string\n"
    "  --id JOB           the job id (default: the case's name)\n"
    "  --resume           continue from the checkpoint in the output directory (after a crash or\n"
    "                     a kill); starts from the beginning when there is none, or when it\n"
    "                     cannot be read (another version's: it is kept as checkpoint.unreadable)\n"
    "  --threads N        OpenMP threads for the solver (default: all cores)\n"
    "\n"
    "Both modes:\n"
    "  --checkpoint-interval S  wall-clock seconds between checkpoints of a running simulation\n"
    "                     (default 60; checkpoints are also written after every snapshot and\n"
    "                     when a job pauses)\n"
    "\n"
    "Daemon mode:\n"
    "  --listen ENDPOINT  control socket (default ipc://$XDG_RUNTIME_DIR/sphd/control)\n"
    "  --publish ENDPOINT event stream (default ipc://$XDG_RUNTIME_DIR/sphd/stream)\n"
    "  --state-dir DIR    jobs and outputs (default $XDG_STATE_HOME/sphd)\n"
    "  --threads N        threads for all jobs together: at most N jobs run at once, the\n"
    "                     others wait in the queue (default: the number of CPUs)\n"
    "  --max-jobs N       jobs held at once (queued, running, paused; default 64); a submit\n"
    "                     beyond is refused as busy\n"
    "  --max-msg-size B   largest request in bytes (default 16777216 = 16 MiB; K, M, G\n"
    "                     suffixes); a larger one is refused with too_large (one over 8 times\n"
    "                     the limit is dropped by the transport, unanswered)\n"
    "  --diag-rate N      at most N diag events per second per job on the stream (default 50)\n"
    "  --curve DIR        CURVE authentication and encryption on both sockets: DIR/server.key\n"
    "                     is the server's secret key (Z85, mode 600; 'sphctl keygen --out\n"
    "                     DIR/server' makes it and DIR/server.pub, the key clients need), and\n"
    "                     DIR/clients/ holds the authorised clients' public keys, one file\n"
    "                     each; SIGHUP reads clients/ again (a removed key is refused at once)\n"
    "  --insecure         allow a non-loopback tcp:// endpoint without CURVE keys\n"
    "  --http HOST:PORT   serve the web dashboard there (off by default; 127.0.0.1:8080 for\n"
    "                     this machine only; any other address needs the token sphd keeps in\n"
    "                     STATE/http.token, sent as the header X-Sphd-Token; not with --curve)\n"
    "  --request-cpu CPU  the CPU that the socket loop and the ZeroMQ I/O thread share\n"
    "                     (default 'auto': the last CPU sphd may use; 'any': not pinned): a\n"
    "                     request then passes between them without waking another CPU, which\n"
    "                     halves its cost when jobs keep every CPU busy (solver threads are\n"
    "                     never pinned)\n"
    "  --worker-nice N    the solver threads' nice value above sphd's own (0 to 19, default 5):\n"
    "                     requests then preempt a busy solver thread at once (p99 0.2 ms\n"
    "                     instead of 2.5 ms with the CPUs full); 0 gives the jobs the same\n"
    "                     priority as every other program\n"
    "\n"
    "  --executor slurm   run jobs as Slurm batch jobs (a job's resources.executor \"local\"\n"
    "                     keeps it here): each runs 'sphd --runner' on a node, in the job's\n"
    "                     directory, which must be on storage the nodes share (--state-dir)\n"
    "  --runner-listen EP where the runners connect (default tcp://*:7617)\n"
    "  --runner-connect EP the same as the nodes reach it (default tcp://HOSTNAME:PORT)\n"
    "                     (with --curve the runners use CURVE too: a key pair of theirs\n"
    "                     that sphd keeps in STATE/runner)\n"
    "  --runner-wait S    a runner that hears nothing from the daemon for S seconds after\n"
    "                     it starts gives up (default 120; the job is then submitted again)\n"
    "\n"
    "Runner mode (started by Slurm; not by hand):\n"
    "  --runner EP --job-dir DIR  run the job in DIR for the daemon at EP\n"
    "  --runner-keys DIR  CURVE with the key pair sphd keeps in DIR (STATE/runner)\n"
    "\n"
    "  -h, --help         this text\n"
    "  --version          print the version\n"
    "\n"
    "Exit codes (--run): 0 the job is done, 1 it failed, 64 usage, 65 invalid case,\n"
    "66 case file not found, 73 cannot create the output directory, 75 interrupted by\n"
    "SIGINT or SIGTERM (a checkpoint was written: --resume continues).\n"
    "Exit codes (daemon): 0 stopped cleanly (SIGINT, SIGTERM or 'sphctl shutdown'), 64 usage,\n"
    "69 cannot bind an endpoint, 73 cannot create a directory, 75 another sphd already serves\n"
    "the endpoints or the state directory, 78 the --curve keys are missing or unsafe.\n";

/* Parses a positive count with an optional K, M or G suffix (powers of 1024). */
static int parse_size(const char *s, long lo, long hi, long *out)
{
    char *end;
    long v = strtol(s, &end, 10);
    long mul = 1;
    if (*end == 'K' || *end == 'k')
        mul = 1L << 10, end++;
    else if (*end == 'M' || *end == 'm')
        mul = 1L << 20, end++;
    else if (*end == 'G' || *end == 'g')
        mul = 1L << 30, end++;
    if (*end || end == s || v < 0 || v > hi / mul || v * mul < lo)
        return -1;
    *out = v * mul;
    return 0;
}

/* --NAME COUNT: a number from lo to hi (K, M, G suffixes allowed); says what is wrong. */
static int count_opt(const char *name, const char *arg, long lo, long hi, long *out)
{
    if (isdigit((unsigned char)*arg) && parse_size(arg, lo, hi, out) == 0)
        return 0;
    fprintf(stderr, "sphd: --%s takes a number from %ld to %ld, not '%s'\n", name, lo, hi, arg);
    return -1;
}

static int daemon_defaults(sphd_opts *o)
{
    if (!o->listen[0] && sph_default_control_endpoint(o->listen, sizeof o->listen))
        return -1;
    if (!o->publish[0] && sph_default_stream_endpoint(o->publish, sizeof o->publish))
        return -1;
    if (!o->state_dir[0]) {
        const char *xdg = getenv("XDG_STATE_HOME"), *home = getenv("HOME");
        int n;
        if (xdg && *xdg)
            n = snprintf(o->state_dir, sizeof o->state_dir, "%s/sphd", xdg);
        else if (home && *home)
            n = snprintf(o->state_dir, sizeof o->state_dir, "%s/.local/state/sphd", home);
        else
            return -1;
        if (n < 0 || (size_t)n >= sizeof o->state_dir)
            return -1;
    }
    if (o->threads <= 0) {
        long n = sysconf(_SC_NPROCESSORS_ONLN);
        o->threads = n > 0 ? (int)(n > 1024 ? 1024 : n) : 1;
    }
    return 0;
}

static int check_endpoint(const char *ep, const char *opt, int insecure, int curve)
{
    if (strncmp(ep, "ipc://", 6) != 0 && strncmp(ep, "tcp://", 6) != 0) {
        fprintf(stderr, "sphd: %s takes an ipc:// or tcp:// endpoint, not '%s'\n", opt, ep);
        return -1;
    }
    if (sph_tcp_is_loopback(ep) == 0 && !curve) {
        if (!insecure) {
            fprintf(stderr,
                    "sphd: %s %s is reachable from other machines: that needs CURVE keys "
                    "(--curve DIR, see the README's 'Remote use'); or use a loopback address "
                    "(tcp://127.0.0.1:PORT), an ipc:// endpoint, or --insecure on a trusted "
                    "network\n",
                    opt, ep);
            return -1;
        }
        fprintf(stderr, "sphd: warning: %s %s accepts unauthenticated clients (--insecure)\n", opt,
                ep);
    }
    return 0;
}

int main(int argc, char **argv)
{
    enum {
        OPT_RUN = 256,
        OPT_OUT,
        OPT_SET,
        OPT_ID,
        OPT_THREADS,
        OPT_VERSION,
        OPT_LISTEN,
        OPT_PUBLISH,
        OPT_STATE,
        OPT_MAXJOBS,
        OPT_RESUME,
        OPT_CKPT,
        OPT_MAXMSG,
        OPT_DIAGRATE,
        OPT_INSECURE,
        OPT_HTTP,
        OPT_CURVE,
        OPT_REQCPU,
        OPT_WNICE,
        OPT_EXECUTOR,
        OPT_RLISTEN,
        OPT_RCONNECT,
        OPT_RUNNER,
        OPT_JOBDIR,
        OPT_RWAIT,
        OPT_RKEYS
    };
    sph_core_init(); /* before any thread */
    static const struct option longopts[] = {
        {"run", required_argument, NULL, OPT_RUN},
        {"out", required_argument, NULL, OPT_OUT},
        {"set", required_argument, NULL, OPT_SET},
        {"id", required_argument, NULL, OPT_ID},
        {"resume", no_argument, NULL, OPT_RESUME},
        {"checkpoint-interval", required_argument, NULL, OPT_CKPT},
        {"threads", required_argument, NULL, OPT_THREADS},
        {"listen", required_argument, NULL, OPT_LISTEN},
        {"publish", required_argument, NULL, OPT_PUBLISH},
        {"state-dir", required_argument, NULL, OPT_STATE},
        {"max-jobs", required_argument, NULL, OPT_MAXJOBS},
        {"max-msg-size", required_argument, NULL, OPT_MAXMSG},
        {"diag-rate", required_argument, NULL, OPT_DIAGRATE},
        {"insecure", no_argument, NULL, OPT_INSECURE},
        {"http", required_argument, NULL, OPT_HTTP},
        {"curve", required_argument, NULL, OPT_CURVE},
        {"request-cpu", required_argument, NULL, OPT_REQCPU},
        {"worker-nice", required_argument, NULL, OPT_WNICE},
        {"executor", required_argument, NULL, OPT_EXECUTOR},
        {"runner-listen", required_argument, NULL, OPT_RLISTEN},
        {"runner-connect", required_argument, NULL, OPT_RCONNECT},
        {"runner", required_argument, NULL, OPT_RUNNER},
        {"job-dir", required_argument, NULL, OPT_JOBDIR},
        {"runner-wait", required_argument, NULL, OPT_RWAIT},
        {"runner-keys", required_argument, NULL, OPT_RKEYS},
        {"help", no_argument, NULL, 'h'},
        {"version", no_argument, NULL, OPT_VERSION},
        {NULL, 0, NULL, 0},
    };
    const char *runner_ep = NULL, *job_dir = NULL, *runner_keys = NULL;
    sphd_h5_init();
    sphd_run_opts run = {0};
    sphd_opts dopts = {.max_jobs = 64,
                       .max_msg_size = 16L << 20,
                       .diag_rate = 50,
                       .request_cpu = SPHD_CPU_AUTO,
                       .worker_nice = 5};
    int daemon_only = 0;
    int opt;
    while ((opt = getopt_long(argc, argv, "h", longopts, NULL)) != -1) {
        switch (opt) {
        case OPT_RUN:
            run.case_file = optarg;
            break;
        case OPT_OUT:
            run.out_dir = optarg;
            break;
        case OPT_SET:
            if (run.nsets >= SPHD_MAX_SETS) {
                fprintf(stderr, "sphd: at most %d --set options\n", SPHD_MAX_SETS);
                return SPHD_EX_USAGE;
            }
            run.sets[run.nsets++] = optarg;
            break;
        case OPT_ID:
            run.job = optarg;
            break;
        case OPT_RESUME:
            run.resume = 1;
            break;
        case OPT_CKPT: {
            char *end;
            double v = strtod(optarg, &end);
            if (*end || !(v >= 0.01 && v <= 1e6)) {
                fprintf(stderr,
                        "sphd: --checkpoint-interval takes seconds from 0.01 to 1e6, not '%s'\n",
                        optarg);
                return SPHD_EX_USAGE;
            }
            run.ckpt_interval = v;
            dopts.ckpt_interval = v;
            break;
        }
        case OPT_THREADS: {
            char *end;
            long n = strtol(optarg, &end, 10);
            if (*end || n < 1 || n > 1024) {
                fprintf(stderr, "sphd: --threads takes a number from 1 to 1024, not '%s'\n",
                        optarg);
                return SPHD_EX_USAGE;
            }
            run.threads = (int)n;
            dopts.threads = (int)n;
            break;
        }
        case OPT_LISTEN:
        case OPT_PUBLISH:
        case OPT_STATE: {
            char *dst = opt == OPT_LISTEN    ? dopts.listen
                        : opt == OPT_PUBLISH ? dopts.publish
                                             : dopts.state_dir;
            size_t cap = opt == OPT_STATE ? sizeof dopts.state_dir : sizeof dopts.listen;
            if (!*optarg || strlen(optarg) >= cap) {
                fprintf(stderr, "sphd: the value of --%s is empty or too long\n",
                        opt == OPT_LISTEN    ? "listen"
                        : opt == OPT_PUBLISH ? "publish"
                                             : "state-dir");
                return SPHD_EX_USAGE;
            }
            snprintf(dst, cap, "%s", optarg);
            daemon_only = 1;
            break;
        }
        case OPT_MAXJOBS: {
            long n;
            if (count_opt("max-jobs", optarg, 1, 100000, &n))
                return SPHD_EX_USAGE;
            dopts.max_jobs = (int)n;
            daemon_only = 1;
            break;
        }
        case OPT_MAXMSG: {
            long n;
            if (parse_size(optarg, 1024, 1L << 32, &n)) {
                fprintf(stderr,
                        "sphd: --max-msg-size takes a size from 1K to 4G (e.g. 16M), not '%s'\n",
                        optarg);
                return SPHD_EX_USAGE;
            }
            dopts.max_msg_size = n;
            daemon_only = 1;
            break;
        }
        case OPT_DIAGRATE: {
            long n;
            if (count_opt("diag-rate", optarg, 1, 1000000, &n))
                return SPHD_EX_USAGE;
            dopts.diag_rate = (int)n;
            daemon_only = 1;
            break;
        }
        case OPT_REQCPU: {
            long n;
            if (!strcmp(optarg, "auto")) {
                dopts.request_cpu = SPHD_CPU_AUTO;
            } else if (!strcmp(optarg, "any")) {
                dopts.request_cpu = SPHD_CPU_ANY;
            } else if (parse_size(optarg, 0, 4095, &n) == 0 && isdigit((unsigned char)*optarg) &&
                       sphd_sched_cpu_usable((int)n)) {
                dopts.request_cpu = (int)n;
            } else {
                fprintf(stderr,
                        "sphd: --request-cpu takes 'auto', 'any' or the number of a CPU that "
                        "sphd may run on (see nproc, taskset -p $$), not '%s'\n",
                        optarg);
                return SPHD_EX_USAGE;
            }
            daemon_only = 1;
            break;
        }
        case OPT_WNICE: {
            long n;
            if (count_opt("worker-nice", optarg, 0, 19, &n))
                return SPHD_EX_USAGE;
            dopts.worker_nice = (int)n;
            daemon_only = 1;
            break;
        }
        case OPT_CURVE:
            if (!*optarg || strlen(optarg) >= sizeof dopts.curve_dir) {
                fputs("sphd: the value of --curve is empty or too long\n", stderr);
                return SPHD_EX_USAGE;
            }
            snprintf(dopts.curve_dir, sizeof dopts.curve_dir, "%s", optarg);
            daemon_only = 1;
            break;
        case OPT_INSECURE:
            dopts.insecure = 1;
            daemon_only = 1;
            break;
        case OPT_HTTP:
            if (!*optarg || strlen(optarg) >= sizeof dopts.http) {
                fputs("sphd: the value of --http is empty or too long\n", stderr);
                return SPHD_EX_USAGE;
            }
            snprintf(dopts.http, sizeof dopts.http, "%s", optarg);
            daemon_only = 1;
            break;
        case OPT_EXECUTOR:
            if (strcmp(optarg, "slurm") != 0 && strcmp(optarg, "local") != 0) {
                fprintf(stderr, "sphd: --executor is local or slurm, not '%s'\n", optarg);
                return SPHD_EX_USAGE;
            }
            dopts.executor_slurm = strcmp(optarg, "slurm") == 0;
            daemon_only = 1;
            break;
        case OPT_RLISTEN:
        case OPT_RCONNECT: {
            char *dst = opt == OPT_RLISTEN ? dopts.runner_listen : dopts.runner_connect;
            if (strncmp(optarg, "tcp://", 6) != 0 || strlen(optarg) >= SPH_ENDPOINT_MAX) {
                fprintf(stderr, "sphd: --runner-%s takes a tcp:// endpoint, not '%s'\n",
                        opt == OPT_RLISTEN ? "listen" : "connect", optarg);
                return SPHD_EX_USAGE;
            }
            snprintf(dst, SPH_ENDPOINT_MAX, "%s", optarg);
            daemon_only = 1;
            break;
        }
        case OPT_RUNNER:
            runner_ep = optarg;
            break;
        case OPT_JOBDIR:
            job_dir = optarg;
            break;
        case OPT_RKEYS:
            runner_keys = optarg;
            break;
        case OPT_RWAIT: {
            char *end;
            double v = strtod(optarg, &end);
            if (*end || !(v >= 1 && v <= 86400)) {
                fprintf(stderr, "sphd: --runner-wait takes seconds from 1 to 86400, not '%s'\n",
                        optarg);
                return SPHD_EX_USAGE;
            }
            dopts.runner_wait = v;
            break;
        }
        case 'h':
            fputs(usage_text, stdout);
            return SPHD_EX_OK;
        case OPT_VERSION:
            printf("sphd %s\n", SPH_VERSION);
            return SPHD_EX_OK;
        default:
            fputs("Try 'sphd --help'.\n", stderr);
            return SPHD_EX_USAGE;
        }
    }
    if (optind < argc) {
        fprintf(stderr, "sphd: unexpected argument '%s'\nTry 'sphd --help'.\n", argv[optind]);
        return SPHD_EX_USAGE;
    }
    if (runner_ep || job_dir) {
        if (!runner_ep || !job_dir) {
            fputs("sphd: --runner and --job-dir go together\n", stderr);
            return SPHD_EX_USAGE;
        }
        return sphd_runner_main(runner_ep, job_dir, runner_keys, dopts.threads, dopts.ckpt_interval,
                                dopts.diag_rate ? dopts.diag_rate : 50,
                                dopts.runner_wait > 0 ? dopts.runner_wait : 120);
    }
    if (run.case_file) {
        if (daemon_only) {
            fputs("sphd: --listen, --publish, --state-dir, --max-jobs, --max-msg-size, "
                  "--diag-rate, --request-cpu, --worker-nice, --curve and --insecure are for the "
                  "daemon, "
                  "not "
                  "--run\n",
                  stderr);
            return SPHD_EX_USAGE;
        }
        return sphd_run(&run);
    }
    if (run.out_dir || run.nsets || run.job || run.resume) {
        fputs("sphd: --out, --set, --id and --resume go with --run\nTry 'sphd --help'.\n", stderr);
        return SPHD_EX_USAGE;
    }
    if (daemon_defaults(&dopts) != 0) {
        fputs("sphd: cannot work out the default endpoints or state directory (is HOME set?); "
              "give --listen, --publish and --state-dir\n",
              stderr);
        return SPHD_EX_USAGE;
    }
    if (check_endpoint(dopts.listen, "--listen", dopts.insecure, dopts.curve_dir[0] != 0) ||
        check_endpoint(dopts.publish, "--publish", dopts.insecure, dopts.curve_dir[0] != 0))
        return SPHD_EX_USAGE;
    if (strcmp(dopts.listen, dopts.publish) == 0) {
        fputs("sphd: --listen and --publish must differ\n", stderr);
        return SPHD_EX_USAGE;
    }
    if (dopts.http[0] && dopts.curve_dir[0]) {
        fputs("sphd: --http does not go with --curve in this version (the dashboard talks to sphd "
              "as a client without keys)\n",
              stderr);
        return SPHD_EX_USAGE;
    }
    if (dopts.runner_wait <= 0)
        dopts.runner_wait = 120;
    if (!dopts.runner_listen[0])
        snprintf(dopts.runner_listen, sizeof dopts.runner_listen, "tcp://*:7617");
    /* the runners' socket is a tcp endpoint like the others: CURVE or loopback or --insecure */
    if (dopts.executor_slurm && check_endpoint(dopts.runner_listen, "--runner-listen",
                                               dopts.insecure, dopts.curve_dir[0] != 0))
        return SPHD_EX_USAGE;
    return sphd_daemon_main(&dopts);
}

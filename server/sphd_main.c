/* sphd: the simulation daemon. This file parses the command line and picks the mode. */
#include "sphd.h"

#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
    "                     a kill); starts from the beginning when there is none\n"
    "  --threads N        OpenMP threads for the solver (default: all cores)\n"
    "\n"
    "Daemon mode:\n"
    "  --listen ENDPOINT  control socket (default ipc://$XDG_RUNTIME_DIR/sphd/control)\n"
    "  --publish ENDPOINT event stream (default ipc://$XDG_RUNTIME_DIR/sphd/stream)\n"
    "  --state-dir DIR    jobs and outputs (default $XDG_STATE_HOME/sphd)\n"
    "  --threads N        threads for all jobs together\n"
    "  --max-jobs N       jobs held at once\n"
    "\n"
    "  -h, --help         this text\n"
    "  --version          print the version\n"
    "\n"
    "Exit codes (--run): 0 the job is done, 1 it failed, 64 usage, 65 invalid case,\n"
    "66 case file not found, 73 cannot create the output directory.\n";

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
        OPT_RESUME
    };
    static const struct option longopts[] = {
        {"run", required_argument, NULL, OPT_RUN},
        {"out", required_argument, NULL, OPT_OUT},
        {"set", required_argument, NULL, OPT_SET},
        {"id", required_argument, NULL, OPT_ID},
        {"resume", no_argument, NULL, OPT_RESUME},
        {"threads", required_argument, NULL, OPT_THREADS},
        {"listen", required_argument, NULL, OPT_LISTEN},
        {"publish", required_argument, NULL, OPT_PUBLISH},
        {"state-dir", required_argument, NULL, OPT_STATE},
        {"max-jobs", required_argument, NULL, OPT_MAXJOBS},
        {"help", no_argument, NULL, 'h'},
        {"version", no_argument, NULL, OPT_VERSION},
        {NULL, 0, NULL, 0},
    };
    sphd_run_opts run = {0};
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
        case OPT_THREADS: {
            char *end;
            long n = strtol(optarg, &end, 10);
            if (*end || n < 1 || n > 1024) {
                fprintf(stderr, "sphd: --threads takes a number from 1 to 1024, not '%s'\n",
                        optarg);
                return SPHD_EX_USAGE;
            }
            run.threads = (int)n;
            break;
        }
        case OPT_LISTEN:
        case OPT_PUBLISH:
        case OPT_STATE:
        case OPT_MAXJOBS:
            break;
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
    if (run.case_file)
        return sphd_run(&run);
    /* TODO(issue 4): the daemon (control ROUTER, stream PUB, job manager). */
    fprintf(stderr, "sphd: daemon mode is not in this build yet; run a case with "
                    "'sphd --run CASE.json'\n");
    return SPHD_EX_UNAVAILABLE;
}

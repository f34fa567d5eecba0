/* sphctl: the client of sphd. */
#include <stdio.h>
#include <string.h>

#define SPHCTL_EX_USAGE       64
#define SPHCTL_EX_UNAVAILABLE 69

static const char usage_text[] =
    "Usage: sphctl [--endpoint ENDPOINT] [--json] COMMAND ...\n"
    "\n"
    "Commands: ping, submit FILE [--id ID] [--watch], status [JOB], list, watch JOB,\n"
    "          step JOB N, pause JOB, resume JOB, stop JOB, query JOB, shutdown\n"
    "\n"
    "This build has no daemon yet: run cases with 'sphd --run CASE.json'.\n";

int main(int argc, char **argv)
{
    if (argc > 1 && (strcmp(argv[1], "-h") == 0 || strcmp(argv[1], "--help") == 0)) {
        fputs(usage_text, stdout);
        return 0;
    }
    if (argc > 1 && strcmp(argv[1], "--version") == 0) {
        printf("sphctl %s\n", SPH_VERSION);
        return 0;
    }
    /* TODO(issue 4): the client commands. */
    fputs("sphctl: the daemon protocol is not in this build yet; use 'sphd --run CASE.json'\n",
          stderr);
    return argc > 1 ? SPHCTL_EX_UNAVAILABLE : SPHCTL_EX_USAGE;
}

/*
 * Where sphd's request threads run.
 *
 * A request passes twice between libzmq's I/O thread and the socket loop (in, then the reply
 * out). When the two share one CPU each hand-over is a local wake-up; otherwise it is an
 * interrupt to another CPU, which on a virtual machine costs a trip through the hypervisor.
 * Measured with bench/load.sh (2 jobs filling 2 CPUs, 32 clients at 10 requests/s each):
 * sphd's CPU per request about halves, and the jobs keep more of theirs. The solver threads
 * are never pinned. (A shorter scheduler slice for these threads, Linux 6.12's sched_setattr
 * hint, was tried too: it cost CPU and did not lower the latency, so it is not used.)
 *
 * The solver threads run a few nice levels below the rest of sphd (--worker-nice, default 5).
 * When a request wakes a thread of sphd's on a CPU that a solver thread holds, the kernel then
 * switches at once instead of at the solver's next tick (4 ms at HZ=250): bench/load.sh measured
 * p99 0.2 ms instead of 2.5 ms at 320 requests/s, the same CPU for the jobs. A request thread
 * can only take the CPU it uses, so the jobs lose nothing to an idle daemon; they do yield more
 * to other programs on the machine (at nice 5, a quarter of a CPU against a busy nice-0 program).
 */
#define _GNU_SOURCE /* sched_setaffinity */
#include "sphd_daemon.h"

#include <errno.h>
#include <sched.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>
#include <zmq.h>

int sphd_sched_cpu_usable(int cpu)
{
    cpu_set_t mask;
    return cpu >= 0 && cpu < CPU_SETSIZE && sched_getaffinity(0, sizeof mask, &mask) == 0 &&
           CPU_ISSET(cpu, &mask);
}

int sphd_sched_pick_cpu(int want)
{
    if (want == SPHD_CPU_ANY)
        return SPHD_CPU_ANY;
    cpu_set_t mask;
    if (want == SPHD_CPU_AUTO && sched_getaffinity(0, sizeof mask, &mask) == 0) {
        for (int c = CPU_SETSIZE - 1; c >= 0; c--) /* the last: CPU 0 takes more interrupts */
            if (CPU_ISSET(c, &mask))
                return c;
    }
    if (sphd_sched_cpu_usable(want))
        return want;
    errno = EINVAL;
    return SPHD_CPU_ANY;
}

int sphd_sched_zmq_threads(void *ctx, int cpu)
{
    if (cpu < 0)
        return 0;
    /* libzmq pins each thread it starts (I/O, reaper) before anything else */
    return zmq_ctx_set(ctx, ZMQ_THREAD_AFFINITY_CPU_ADD, cpu);
}

int sphd_sched_pin_self(int cpu)
{
    if (cpu < 0)
        return 0;
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(cpu, &one);
    return sched_setaffinity(0, sizeof one, &one);
}

int sphd_sched_lower_self(int by)
{
    if (by <= 0)
        return 0;
    const id_t tid = (id_t)syscall(SYS_gettid); /* on Linux, nice is per thread */
    errno = 0;
    int now = getpriority(PRIO_PROCESS, tid);
    if (now == -1 && errno != 0)
        return -1;
    int to = now + by > 19 ? 19 : now + by;
    return setpriority(PRIO_PROCESS, tid, to);
}

/* sphd's request threads (sphd_sched.c): 'auto' picks the last CPU the process may use; a CPU
 * it may not use is refused; the ZeroMQ threads a context starts after the call, and the
 * calling thread, end up on the CPU asked for, while a thread started before keeps every CPU;
 * 'any' changes nothing. */
#define _GNU_SOURCE /* sched_getaffinity */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "sphd_daemon.h"

#include <dirent.h>
#include <pthread.h>
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <zmq.h>

static cpu_set_t all; /* the process's CPUs at the start */

/* The ids of this process's threads named ZMQbg/IO/N (libzmq names them once running). */
static int io_threads(long *tid, int cap)
{
    int n = 0;
    DIR *d = opendir("/proc/self/task");
    assert_non_null(d);
    struct dirent *e;
    while ((e = readdir(d)) != NULL && n < cap) {
        char path[300], comm[32] = "";
        snprintf(path, sizeof path, "/proc/self/task/%s/comm", e->d_name);
        FILE *f = fopen(path, "r");
        if (!f)
            continue;
        if (!fgets(comm, sizeof comm, f))
            comm[0] = '\0';
        fclose(f);
        if (!strncmp(comm, "ZMQbg/IO/", 9))
            tid[n++] = atol(e->d_name);
    }
    closedir(d);
    return n;
}

/* Waits (up to 5 s) until the context's I/O thread has started and named itself: libzmq sets
 * a thread's CPUs before its name. */
static int wait_io_threads(long *tid, int cap)
{
    for (int i = 0; i < 500; i++) {
        int n = io_threads(tid, cap);
        if (n > 0)
            return n;
        struct timespec ts = {0, 10 * 1000 * 1000};
        nanosleep(&ts, NULL);
    }
    return 0;
}

static pthread_mutex_t mu = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t cv = PTHREAD_COND_INITIALIZER;
static int checked;
static cpu_set_t early_mask;

/* A thread started before the call: it looks at itself once the main thread says so. */
static void *early(void *arg)
{
    (void)arg;
    pthread_mutex_lock(&mu);
    while (checked == 0)
        pthread_cond_wait(&cv, &mu);
    sched_getaffinity(0, sizeof early_mask, &early_mask);
    checked = 2;
    pthread_cond_broadcast(&cv);
    pthread_mutex_unlock(&mu);
    return NULL;
}

static void assert_only_cpu(long tid, int cpu)
{
    cpu_set_t m;
    assert_int_equal(sched_getaffinity((pid_t)tid, sizeof m, &m), 0);
    assert_int_equal(CPU_COUNT(&m), 1);
    assert_true(CPU_ISSET(cpu, &m));
}

static void test_pick(void **state)
{
    (void)state;
    int last = -1, first = -1, outside = -1;
    for (int c = 0; c < CPU_SETSIZE; c++) {
        if (CPU_ISSET(c, &all)) {
            last = c;
            if (first < 0)
                first = c;
        } else {
            outside = c; /* every machine has fewer than CPU_SETSIZE CPUs */
        }
    }
    assert_true(first >= 0 && outside >= 0);
    assert_int_equal(sphd_sched_pick_cpu(SPHD_CPU_AUTO), last);
    assert_int_equal(sphd_sched_pick_cpu(first), first);
    assert_int_equal(sphd_sched_pick_cpu(SPHD_CPU_ANY), SPHD_CPU_ANY);
    assert_int_equal(sphd_sched_pick_cpu(outside), SPHD_CPU_ANY);
    assert_int_equal(sphd_sched_cpu_usable(first), 1);
    assert_int_equal(sphd_sched_cpu_usable(outside), 0);
    assert_int_equal(sphd_sched_cpu_usable(-3), 0);
    assert_int_equal(sphd_sched_cpu_usable(CPU_SETSIZE), 0);
}

static void test_pinned(void **state)
{
    (void)state;
    pthread_t th;
    assert_int_equal(pthread_create(&th, NULL, early, NULL), 0);
    const int cpu = sphd_sched_pick_cpu(SPHD_CPU_AUTO);
    void *ctx = zmq_ctx_new();
    assert_int_equal(sphd_sched_zmq_threads(ctx, cpu), 0);
    void *s = zmq_socket(ctx, ZMQ_DEALER); /* the first socket starts the I/O thread */
    assert_non_null(s);
    assert_int_equal(sphd_sched_pin_self(cpu), 0);
    assert_only_cpu(0, cpu);
    long tid[16];
    const int n = wait_io_threads(tid, 16);
    assert_true(n >= 1);
    for (int i = 0; i < n; i++)
        assert_only_cpu(tid[i], cpu);

    pthread_mutex_lock(&mu);
    checked = 1;
    pthread_cond_broadcast(&cv);
    while (checked != 2)
        pthread_cond_wait(&cv, &mu);
    pthread_mutex_unlock(&mu);
    pthread_join(th, NULL);
    assert_true(CPU_EQUAL(&early_mask, &all));

    zmq_close(s);
    zmq_ctx_term(ctx);
    assert_int_equal(sched_setaffinity(0, sizeof all, &all), 0);
}

static void test_any_changes_nothing(void **state)
{
    (void)state;
    void *ctx = zmq_ctx_new();
    assert_int_equal(sphd_sched_zmq_threads(ctx, SPHD_CPU_ANY), 0);
    void *s = zmq_socket(ctx, ZMQ_DEALER);
    assert_int_equal(sphd_sched_pin_self(SPHD_CPU_ANY), 0);
    cpu_set_t m;
    assert_int_equal(sched_getaffinity(0, sizeof m, &m), 0);
    assert_true(CPU_EQUAL(&m, &all));
    long tid[16];
    const int n = wait_io_threads(tid, 16);
    assert_true(n >= 1);
    for (int i = 0; i < n; i++) {
        assert_int_equal(sched_getaffinity((pid_t)tid[i], sizeof m, &m), 0);
        assert_true(CPU_EQUAL(&m, &all));
    }
    zmq_close(s);
    zmq_ctx_term(ctx);
}

int main(void)
{
    if (sched_getaffinity(0, sizeof all, &all) != 0)
        return 1;
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pick),
        cmocka_unit_test(test_any_changes_nothing),
        cmocka_unit_test(test_pinned),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

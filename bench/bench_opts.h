/*
 * bench_opts: the benchmarks' "--name value" options after their positional arguments, read by
 * one table instead of a strcmp chain in each main(). Header-only (the benchmarks are separate
 * programs).
 */
#ifndef BENCH_OPTS_H
#define BENCH_OPTS_H

#include <stdlib.h>
#include <string.h>

typedef enum { BENCH_OPT_DOUBLE, BENCH_OPT_INT, BENCH_OPT_TEXT } bench_opt_kind;

typedef struct bench_opt {
    const char *name; /* with its dashes: "--time" */
    bench_opt_kind kind;
    void *dst; /* double *, int * or const char ** */
} bench_opt;

/* Reads argv[first..] as pairs "--name value" into the table's destinations (ended by a NULL
 * name). Returns 0, or -1 on an unknown name or a name without a value (the caller prints its
 * usage). Values are not range-checked here. */
static inline int bench_options(int argc, char **argv, int first, const bench_opt *opts)
{
    for (int i = first; i < argc; i += 2) {
        const bench_opt *o = opts;
        while (o->name && strcmp(o->name, argv[i]) != 0)
            o++;
        if (!o->name || i + 1 >= argc)
            return -1;
        if (o->kind == BENCH_OPT_DOUBLE)
            *(double *)o->dst = atof(argv[i + 1]);
        else if (o->kind == BENCH_OPT_INT)
            *(int *)o->dst = atoi(argv[i + 1]);
        else
            *(const char **)o->dst = argv[i + 1];
    }
    return 0;
}

#endif

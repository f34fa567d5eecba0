/* sphd: internal interfaces of the daemon's modules. */
#ifndef SPHD_H
#define SPHD_H

#include <stddef.h>

/* sysexits.h codes used by sphd and sphctl (DESIGN.md section 3). */
#define SPHD_EX_OK          0
#define SPHD_EX_FAILED      1
#define SPHD_EX_USAGE       64
#define SPHD_EX_DATAERR     65
#define SPHD_EX_NOINPUT     66
#define SPHD_EX_UNAVAILABLE 69
#define SPHD_EX_SOFTWARE    70
#define SPHD_EX_CANTCREAT   73
#define SPHD_EX_TEMPFAIL    75
#define SPHD_EX_NOPERM      77
#define SPHD_EX_CONFIG      78

#define SPHD_MAX_SETS 64

typedef struct sphd_run_opts {
    const char *case_file; /* the case */
    const char *out_dir;   /* NULL: out/<job> */
    const char *job;       /* NULL: the case's name */
    const char *sets[SPHD_MAX_SETS];
    int nsets;
    int threads;          /* 0: OpenMP's default */
    int resume;           /* continue from the checkpoint in the out dir, if there is one */
    double ckpt_interval; /* wall-clock seconds between checkpoints; 0: the default */
} sphd_run_opts;

/* `sphd --run`: runs one case in the foreground, events as JSON Lines on stdout. Returns the
 * process exit code. */
int sphd_run(const sphd_run_opts *opts);

/* Writes len bytes to path atomically (temporary name, fsync, rename). Returns 0 or -1 (errno). */
int sphd_write_atomic(const char *path, const char *data, size_t len);

/* 1 when id is usable as a job id and file name: 1 to 63 letters, digits, '.', '_' or '-', not
 * starting with '.'. */
int sphd_job_id_ok(const char *id);

/* Writes j as indented JSON to dir/name atomically (sphd_write_atomic). Returns 0 or -1 (errno). */
struct json_t;
int sphd_write_json(const char *dir, const char *name, const struct json_t *j);

/* Removes the temporary files (NAME.tmp.PID) a crashed process left in dir: their writes never
 * completed, and the files they were to replace are intact. This process's own (PID) are left
 * alone: another thread may be writing one. Returns how many, or -1. */
int sphd_remove_stale_temps(const char *dir);

/* mkdir -p with mode 0700 for created directories. Returns 0 or -1 (errno). */
int sphd_mkdirs(const char *path);

#endif

/*
 * sph_error: errors as values. A caller-owned struct that never allocates (jansson's json_error_t
 * is the model). Core functions that can fail take a `sph_error *err` (may be NULL) and return a
 * non-zero code or NULL on failure after filling it in.
 */
#ifndef SPH_ERROR_H
#define SPH_ERROR_H

#include <stdarg.h>

/* Stable error codes. Their names (sph_error_code_name) are part of the wire protocol. */
typedef enum {
    SPH_OK = 0,
    SPH_ERR_INVALID,  /* invalid case or configuration: "invalid_case" */
    SPH_ERR_NOMEM,    /* out of memory or the job would need more than allowed: "too_large" */
    SPH_ERR_UNSTABLE, /* the simulation blew up (NaN, density collapse, escape): "unstable" */
    SPH_ERR_IO,       /* a file could not be read or written: "io_error" */
    SPH_ERR_INTERNAL  /* a bug: "internal" */
} sph_error_code;

#define SPH_ERROR_PATH_MAX 128
#define SPH_ERROR_TEXT_MAX 320

typedef struct sph_error {
    sph_error_code code;
    char path[SPH_ERROR_PATH_MAX];    /* JSON pointer of the offending field, "" if none */
    char message[SPH_ERROR_TEXT_MAX]; /* human text: what is wrong and what to do */
} sph_error;

/* Clears err (code SPH_OK, empty strings). err may be NULL. */
void sph_error_clear(sph_error *err);

/* Fills err with code, path (may be NULL) and a printf-style message; returns code. err may be
 * NULL, in which case only the code is returned. */
int sph_error_set(sph_error *err, sph_error_code code, const char *path, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

/* The stable snake_case name of a code, e.g. "invalid_case". Never NULL. */
const char *sph_error_code_name(sph_error_code code);

#endif

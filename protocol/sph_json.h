/*
 * sph_json: strict, path-aware access to JSON fields (jansson). Every failure names the offending
 * field as a JSON pointer ("/kernels/2/kappa") and says what was expected, so that a case file or a
 * request with a mistake gets an error a person can act on.
 */
#ifndef SPH_JSON_H
#define SPH_JSON_H

#include "sph_error.h"

#include <jansson.h>

/* Fails with SPH_ERR_INVALID naming the first key of obj not in `allowed` (NULL-terminated). */
int sph_json_check_keys(const json_t *obj, const char *base, const char *const *allowed,
                        sph_error *err);

/* Looks up obj[key] (borrowed, may be NULL when optional). Fails if it is required and missing. */
int sph_json_get(const json_t *obj, const char *base, const char *key, int required, json_t **out,
                 sph_error *err);

/* Typed getters: a missing optional field leaves *out untouched and returns 0. Numbers accept
 * integers and reals; integers must be integral. Bounds are inclusive. */
int sph_json_number(const json_t *obj, const char *base, const char *key, int required, double lo,
                    double hi, double *out, sph_error *err);
int sph_json_integer(const json_t *obj, const char *base, const char *key, int required, long lo,
                     long hi, long *out, sph_error *err);
int sph_json_string(const json_t *obj, const char *base, const char *key, int required,
                    const char **out, sph_error *err);
int sph_json_bool(const json_t *obj, const char *base, const char *key, int required, int *out,
                  sph_error *err);
/* An array of exactly n numbers (n = 0: any length up to max_n, stored in *count). */
int sph_json_vector(const json_t *obj, const char *base, const char *key, int required, int n,
                    double *out, sph_error *err);

/* Name of a JSON type for messages ("string", "number", ...). */
const char *sph_json_type_name(const json_t *v);

/* Applies one `--set PATH=VALUE` override to root: PATH is dotted (kernel.type, kernels.0.kappa),
 * VALUE is parsed as JSON where it parses, else taken as a string. Missing objects on the way are
 * created; array indices must exist. */
int sph_json_apply_set(json_t *root, const char *assignment, sph_error *err);

#endif

/*
 * sph_case: a case file (JSON, see protocol/PROTOCOL.md and protocol/schema/case.schema.json) to
 * the core's configuration. Strict: unknown fields, wrong types and out-of-range values are errors
 * that name the field by its JSON pointer.
 */
#ifndef SPH_CASE_H
#define SPH_CASE_H

#include "sph_config.h"
#include "sph_error.h"
#include "sph_study.h"

#include <jansson.h>

#define SPH_CASE_NAME_MAX 64

typedef enum {
    SPH_METHOD_KERNEL_STUDY = 0,
    SPH_METHOD_WCSPH,
    SPH_METHOD_MPS,
} sph_method;

typedef struct sph_case {
    char name[SPH_CASE_NAME_MAX]; /* the case's "name" */
    sph_method method;
    sph_study_config study; /* method == SPH_METHOD_KERNEL_STUDY */
    sph_config sim;         /* method == SPH_METHOD_WCSPH */
} sph_case;

/* Reads a case file into a new JSON object (*root, new reference). SPH_ERR_IO if the file cannot
 * be opened; SPH_ERR_INVALID if it is not a JSON object (message with line and column). */
int sph_case_load(const char *file, json_t **root, sph_error *err);

/* Validates root and fills out. root is borrowed. */
int sph_case_from_json(const json_t *root, sph_case *out, sph_error *err);

/* Case-file name of a method. */
const char *sph_method_name(sph_method m);

#endif

/*
 * sph_case_table: the fields of a simulation case file (wcsph, mps) as one declarative table.
 * Each row says where a field is (its JSON pointer), its type, the methods it applies to and for
 * which it is required, its bounds, names or default, a condition on another field, where the
 * value lands (sph_config or sph_output_config) and what it means. The same table parses and
 * validates a case (sph_case.c), fills the defaults, and is dumped (sph_case_fields_json) so that
 * a test holds the JSON Schema and PROTOCOL.md to it. A new case field is a new row.
 *
 * Arrays of objects (the bodies) are one SPH_CF_ARRAY row ("/bodies") and one row per field of
 * an element, whose path has the segment "*" where the index goes (the density of a body is the
 * row "/bodies", "*", "density" joined by slashes). Those rows are read for each element with the
 * index in their paths, conditions included (a condition on the shape reads the same element's).
 */
#ifndef SPH_CASE_TABLE_H
#define SPH_CASE_TABLE_H

#include "sph_case.h"

#include <stddef.h>

typedef enum {
    SPH_CF_OBJECT,  /* an object holding other rows (its fields are the rows below its path) */
    SPH_CF_TEXT,    /* a string read elsewhere (name, description, method) */
    SPH_CF_NUMBER,  /* a number in [lo, hi], stored as double */
    SPH_CF_INTEGER, /* an integral number in [lo, hi], stored as int or long (by size) */
    SPH_CF_ENUM,    /* a name from names, stored as int: values[k], or k without values */
    SPH_CF_VECTOR,  /* dim numbers in [lo, hi], stored as double[3] */
    SPH_CF_BOX,     /* {"min": [..], "max": [..]}, max > min, stored as sph_box */
    SPH_CF_NAMES,   /* an array of names from names, stored as an unsigned mask (bit values[k]) */
    SPH_CF_CUSTOM,  /* parsed by the row's parse() */
    SPH_CF_ARRAY,   /* an array of lo..hi objects; each element holds the element rows (below the
                     * segment "*"), whose destinations are relative to the element (element i at
                     * off + i stride) */
    SPH_CF_STRING,  /* a string of 1 to size - 1 characters, stored as char[size] */
} sph_case_ftype;

/* Where a row's value lands. */
enum { SPH_CF_CFG = 0, SPH_CF_OUT };

/* Method masks of the rows. */
#define SPH_CF_M(m)  (1u << (m))
#define SPH_CF_WCSPH SPH_CF_M(SPH_METHOD_WCSPH)
#define SPH_CF_MPS   SPH_CF_M(SPH_METHOD_MPS)
#define SPH_CF_SIMS  (SPH_CF_WCSPH | SPH_CF_MPS)

typedef struct sph_case_field {
    const char *path;         /* JSON pointer ("/physics/eos/c0"); parents come first */
    sph_case_ftype type;      /* how it is read */
    unsigned methods;         /* SPH_CF_M(method) for each method it applies to */
    unsigned required;        /* methods for which it must be given (when its object is) */
    const char *when;         /* NULL, or "/path=a|b": applies only while the enum row at
                               * /path (given or default) is a or b (an integer row: its value,
                               * e.g. "/dim=3") */
    double lo, hi;            /* inclusive bounds of numbers, integers, vector components */
    int lo_open;              /* numbers: lo itself is excluded (x > lo) */
    int hi_open;              /* numbers: hi itself is excluded (x < hi) */
    const char *const *names; /* enum and names: the accepted names, NULL-terminated */
    const int *values;        /* enum: value per name; names: mask bit per name (NULL: k, 1<<k) */
    int has_def;              /* 1 if absent means def */
    double def;               /* default: number, integer, or the enum's name index */
    unsigned def_mask;        /* names: default mask */
    int dst;                  /* SPH_CF_CFG or SPH_CF_OUT */
    size_t off, size;         /* offset and size of the destination member */
    size_t stride, count_off; /* arrays: element size, and where the element count (int) lands */
    /* SPH_CF_CUSTOM: reads v (present) at path into c / o. */
    int (*parse)(const json_t *v, const char *path, sph_config *c, sph_output_config *o,
                 sph_error *err);
    const char *doc; /* meaning, units; PROTOCOL.md says the same */
} sph_case_field;

/* The rows, terminated by a row with path NULL. */
extern const sph_case_field sph_case_fields[];

/* {"min": [..], "max": [..]} of dim components each, max > min, at path. */
int sph_case_parse_box(const json_t *v, const char *path, int dim, sph_box *b, sph_error *err);

/* Parses a simulation case of method m (root already checked to be an object) into c and o. */
int sph_case_parse_sim(const json_t *root, sph_method m, sph_config *c, sph_output_config *o,
                       sph_error *err);

/* The table as JSON (new reference): an array of {"path", "type", "methods": [...],
 * "required": [...], "when", "min" or "exclusive_min", "max" or "exclusive_max", "names",
 * "default", "doc"}. */
json_t *sph_case_fields_json(void);

/* The names a row of the table takes (an enum's or a list's), as a JSON array (new reference);
 * NULL when no row has that path or it names nothing. */
json_t *sph_case_field_names(const char *path);

#endif

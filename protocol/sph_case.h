/*
 * sph_case: a case file (JSON, see protocol/PROTOCOL.md and protocol/schema/case.schema.json) to
 * the core's configuration. Strict: unknown fields, wrong types and out-of-range values are errors
 * that name the field by its JSON pointer.
 */
#ifndef SPH_CASE_H
#define SPH_CASE_H

#include "sph_config.h"
#include "sph_mesh.h"
#include "sph_error.h"
#include "sph_study.h"

#include <jansson.h>

#define SPH_CASE_NAME_MAX 64

/* Particle snapshots (the case's "output"); the core knows nothing of them. */
enum {
    SPH_FIELD_POS = 1 << 0, /* always written, asked for or not (as id) */
    SPH_FIELD_VEL = 1 << 1,
    SPH_FIELD_RHO = 1 << 2,
    SPH_FIELD_P = 1 << 3,
    SPH_FIELD_TYPE = 1 << 4,
    SPH_FIELD_ID = 1 << 5, /* always written: accepted in a case, no switch */
    SPH_FIELD_MASS = 1 << 6,
};

/* Triggers (sph_triggers.h): a condition on a diagnostic series and what to do, once, at the
 * first diagnostic that meets it. */
#define SPH_TRIGGERS_MAX       16
#define SPH_TRIGGER_WHEN_MAX   96
#define SPH_TRIGGER_SERIES_MAX 64
typedef enum {
    SPH_TRIGGER_PAUSE = 0,
    SPH_TRIGGER_STOP,
    SPH_TRIGGER_CHECKPOINT,
    SPH_TRIGGER_SNAPSHOT
} sph_trigger_action;
typedef enum { SPH_TRIGGER_GT = 0, SPH_TRIGGER_GE, SPH_TRIGGER_LT, SPH_TRIGGER_LE } sph_trigger_op;
typedef struct sph_trigger {
    char when[SPH_TRIGGER_WHEN_MAX];     /* as the case gives it: "P1 > 5000" */
    char series[SPH_TRIGGER_SERIES_MAX]; /* the diag series: "P1", "front_x", "cyl.penetration" */
    sph_trigger_op op;
    double value;
    sph_trigger_action action;
} sph_trigger;

typedef struct sph_output_config {
    double every;    /* simulated time between snapshots [s]; 0: no snapshots */
    unsigned fields; /* SPH_FIELD_* mask; pos is always written */
    int compress;    /* 0 none, 1-9 deflate level (with shuffle) */
    int ntriggers;   /* the case's "triggers" */
    sph_trigger triggers[SPH_TRIGGERS_MAX];
    int nreflect;                       /* diagnostics.reflection: gauges, 0 or 2 to 8 */
    int reflect[SPH_CONFIG_MAX_GAUGES]; /* their indices in sim.gauges */
} sph_output_config;

typedef struct sph_case {
    char name[SPH_CASE_NAME_MAX]; /* the case's "name" */
    sph_method method;
    sph_study_config study;   /* method == SPH_METHOD_KERNEL_STUDY */
    sph_config sim;           /* a particle simulation (sph_case_is_sim) */
    sph_output_config output; /* a particle simulation */
    /* the surfaces of the geometry items (polygons, from the case; meshes, from
     * sph_case_load_files), owned: sph_case_clear frees them */
    sph_mesh *meshes[SPH_CONFIG_MAX_GEOMETRY];
    sph_wave_series *series; /* a wavemaker's series (sph_case_load_files), owned */
} sph_case;

/* Reads a case file into a new JSON object (*root, new reference). SPH_ERR_IO if the file cannot
 * be opened; SPH_ERR_INVALID if it is not a JSON object (message with line and column). */
int sph_case_load(const char *file, json_t **root, sph_error *err);

/* Validates root and fills out. root is borrowed. */
int sph_case_from_json(const json_t *root, sph_case *out, sph_error *err);

/* Frees what c owns (its surfaces) and clears the config's references to them; c may be a
 * zeroed struct. Every sph_case_from_json needs one once c is no longer used (a case without
 * geometry owns nothing, and then it is a no-op). */
void sph_case_clear(sph_case *c);

/* Reads the files c names, each relative to dir (the case file's directory; the job's files
 * directory in sphd): the mesh files of its geometry ("mesh": "FILE", within lim, NULL: the
 * defaults) and a wavemaker's series ("waves": {"type": "series", "file": "FILE"}), and points
 * the config at them. SPH_ERR_INVALID at the item's path (/geometry/K/mesh,
 * /wavemaker/waves/file) for a missing, unreadable, unknown-format, too large or broken file,
 * and for the checks that need the file (a mesh's place, a series' jumps and stroke). A case
 * that names no file: 0. */
int sph_case_load_files(sph_case *c, const char *dir, const sph_mesh_limits *lim, sph_error *err);

/* A wave series from text (rows "time, displacement", comma, semicolon, space or tab separated;
 * blank lines, lines from '#' and a first line that is no row skipped; times increasing): into
 * q (freed by sph_wave_series_free), or SPH_ERR_INVALID at /wavemaker/waves/file naming the
 * line (name: the file's, for the message). */
int sph_wave_series_parse(const char *text, size_t len, const char *name, sph_wave_series *q,
                          sph_error *err);
void sph_wave_series_free(sph_wave_series *q);

/* A line on the surface of geometry item k as read (a mesh: its file, triangles, vertices and the
 * degenerate triangles dropped) into buf; 0, or -1 when item k has no surface read. *warn is set
 * to 1 when something was dropped. */
int sph_case_mesh_note(const sph_case *c, int k, char *buf, size_t n, int *warn);

/* A file a case names: its name (borrowed from the case's JSON), the JSON pointer of the field
 * that names it, and what names it, for messages ("geometry item 2"). */
typedef struct sph_case_file {
    const char *name;
    char path[48];
    char what[48];
} sph_case_file;
#define SPH_CASE_FILES_MAX (SPH_CONFIG_MAX_GEOMETRY + 1) /* the meshes and a series */

/* The files a case (JSON, unchecked) names, in order: each geometry item's "mesh" string, then
 * a series wavemaker's "file", into files[0 .. max). Returns how many there are (more than max
 * possible). The one list sphctl sends and sphd expects, writes and reads (PROTOCOL.md 3.11). */
int sph_case_files(const json_t *root, sph_case_file *files, int max);

/* Steering (PROTOCOL.md 3.12): 0 if the case field at a dotted path (an assignment's left side,
 * "physics.viscosity.alpha") may change in a running job: the viscous term's coefficients,
 * delta-SPH's, gravity (or one of its components), the CFL number, the end time, the triggers,
 * the snapshots' period and the diagnostics' schedule. Else SPH_ERR_INVALID with the reason (err's
 * path left empty: the caller knows where the path was). */
int sph_case_steerable(const char *path, sph_error *err);

/* Case-file name of a method. */
const char *sph_method_name(sph_method m);

/* Case-file name of a viscous term (physics.viscosity.type; sph_config's visc). */
const char *sph_visc_name(int visc);

/* 1 if the case is a particle simulation run through the sim handle (sim and output hold it),
 * 0 for a kernel study. */
int sph_case_is_sim(const sph_case *c);

#endif

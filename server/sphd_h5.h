/*
 * sphd_h5: the job's result files (DESIGN.md section 6).
 *   - particle snapshots: one HDF5 file per output time, header attributes on the root group, one
 *     chunked (optionally deflate+shuffle compressed) dataset per field; written to a temporary
 *     name, flushed to disk, then renamed, so the latest file is never a partial one. With `pos`
 *     and `id` among the fields the file also has ParaView's own layout (VTKHDF 1.0, an
 *     unstructured grid of one vertex cell per particle) in the group /VTKHDF, whose arrays are
 *     hard links to the same datasets: only the cell offsets and types are new data. The group
 *     /rpdf holds the fluid's radial particle density function when the caller gives one (not
 *     per particle: the XDMF and VTKHDF do not name it);
 *   - an XDMF sidecar listing every snapshot as a temporal collection of polyvertex grids (the
 *     `id` dataset as their connectivity), so ParaView, VisIt and meshio open the whole run as a
 *     time series (rewritten atomically);
 *   - the diagnostics time series: one extendible table in one HDF5 file per job, written in SWMR
 *     mode so that it can be read while the job runs, with a row count written after each row.
 * The core knows nothing of this module: callers pass plain arrays.
 */
#ifndef SPHD_H5_H
#define SPHD_H5_H

#include "sph_error.h"

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

typedef enum { SPHD_H5_F32, SPHD_H5_F64, SPHD_H5_I8, SPHD_H5_I32, SPHD_H5_I64 } sphd_h5_type;

/* One particle field. Vector fields are given per component (structure of arrays) and stored as
 * an (n, 3) dataset, zero-padded beyond `ncomp`, so that 2D runs open in ParaView like 3D ones. */
typedef struct sphd_h5_field {
    const char *name;    /* dataset name: "pos", "vel", "rho", "p", "mass", "type", "id", ... */
    const char *units;   /* stored as the dataset's "units" attribute, e.g. "m", "kg/m^3" */
    sphd_h5_type type;   /* element type in memory and in the file */
    int ncomp;           /* 1 (scalar) or the vector's dimension (2 or 3) */
    const void *comp[3]; /* component arrays of n elements each */
} sphd_h5_field;

/* The fluid's radial particle density function (core/sph_rpdf.h), nbins values each. */
typedef struct sphd_h5_rpdf {
    int nbins;             /* bins, >= 1 */
    double qmax;           /* the bins cover q = r / h in [0, qmax) [1] */
    const double *q;       /* bin centres [1] */
    const double *count;   /* pairs of fluid particles per bin [1] */
    const double *density; /* relative to a uniform fluid at the initial spacing [1] */
} sphd_h5_rpdf;

typedef struct sphd_h5_header {
    double t;                 /* simulated time [s] */
    long step;                /* solver step */
    int dim;                  /* 1, 2 or 3 */
    double dx;                /* particle spacing [m] */
    const char *kernel;       /* kernel type name */
    const char *job;          /* job id */
    long n;                   /* particles in the file */
    long n_fluid;             /* of which fluid */
    long n_boundary;          /* of which fixed boundary */
    long n_body;              /* of which rigid-body */
    double mass;              /* particle mass [kg, or kg/m in 2D]; written when > 0 */
    double h;                 /* smoothing length [m]; written when > 0 */
    const sphd_h5_rpdf *rpdf; /* written as the group /rpdf; NULL: none */
} sphd_h5_header;

/* Writes a snapshot to `path` (via path.tmp + fsync + rename). compress: 0 none, 1-9 deflate level
 * (with shuffle). With fields "pos" and "id" (an integer type) it adds the /VTKHDF group, with
 * hdr->rpdf the /rpdf group (datasets q, count and density, not compressed). Returns
 * 0, or SPH_ERR_IO with err saying which file and why (disk full...). */
int sphd_h5_write_snapshot(const char *path, const sphd_h5_header *hdr, const sphd_h5_field *fields,
                           int nfields, int compress, sph_error *err);

/* The XDMF time series: one entry per snapshot written so far. */
typedef struct sphd_xdmf_entry {
    char file[256]; /* snapshot file name, relative to the .xmf */
    double t;       /* [s] */
    long step;
    long n; /* particles */
} sphd_xdmf_entry;

/* Rewrites `path` (atomically) describing every entry; fields as in the snapshots (names, types,
 * ncomp; the data pointers are not used). A field "id" becomes the polyvertex connectivity. */
int sphd_xdmf_write(const char *path, const sphd_xdmf_entry *entries, int nentries,
                    const sphd_h5_field *fields, int nfields, sph_error *err);

/* Diagnostics time series: one table, plus one dataset per column, SWMR (sphd_diagfile.c). */
typedef struct sphd_diagfile sphd_diagfile;

/* The most series a diagnostics file holds after "step": the fixed ones and 10 per rigid body. */
#define SPHD_DIAG_MAX_COLUMNS 128

/* A series after "step": its name, units ("m", "1" for counts) and whether it holds integers. */
typedef struct sphd_diag_column {
    const char *name;
    const char *units;
    int integer;
} sphd_diag_column;

/* Creates `path` with the given columns ("step" is always the first, int64), or, if it exists
 * and resume_step >= 0, rebuilds it with its rows up to step resume_step (a resumed job
 * continues its series). Returns NULL with err on failure. */
sphd_diagfile *sphd_diagfile_open(const char *path, const sphd_diag_column *columns, int ncolumns,
                                  long resume_step, sph_error *err);

/* Appends one row: step and ncolumns values (in the order of the columns; rounded in integer
 * columns). Flushed at once so SWMR readers see it, the row count last. */
int sphd_diagfile_append(sphd_diagfile *d, long step, const double *values, sph_error *err);

/* Rows written so far. */
long sphd_diagfile_rows(const sphd_diagfile *d);

/* Closes the file; close(NULL) is a no-op. */
void sphd_diagfile_close(sphd_diagfile *d);

/* Writes the diagnostics file at `path` as CSV (header line, one row per step) to `out`. Works
 * while the file is being written (opens it SWMR read-only; reads the rows `rows` counts) and on
 * files of earlier versions (one dataset per column only). */
int sphd_diagfile_export_csv(const char *path, FILE *out, sph_error *err);

#endif

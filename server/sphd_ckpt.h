/*
 * sphd_ckpt: checkpoint files. A checkpoint is a list of named binary sections (the case, the
 * solver's state, the integrator's state, ...) in one file, each section with a CRC-32, the
 * header and the whole file with their own, so a torn or corrupt file is detected on load.
 *
 * In a job directory the latest checkpoint is `checkpoint` and the one before it `checkpoint.prev`.
 * Writing goes to a temporary file, fsync'd, then the old latest becomes `.prev` and the new file
 * takes its name; the previous checkpoint is never touched before the new one is complete.
 * Loading takes the latest that verifies, and says when it had to fall back.
 */
#ifndef SPHD_CKPT_H
#define SPHD_CKPT_H

#include "sph_error.h"

#include <stddef.h>

#define SPHD_CKPT_NAME_MAX 32

typedef struct sphd_ckpt_section {
    const char *name; /* at most SPHD_CKPT_NAME_MAX - 1 characters */
    const void *data;
    size_t size; /* bytes */
} sphd_ckpt_section;

/* Writes a checkpoint into dir (see above). Returns 0 or SPH_ERR_IO (disk full, ...), in which
 * case the existing checkpoints are untouched. */
int sphd_ckpt_write(const char *dir, const sphd_ckpt_section *sections, int nsections,
                    sph_error *err);

typedef struct sphd_ckpt sphd_ckpt;

/* Loads the latest valid checkpoint of dir. *fell_back (may be NULL) is set to 1 when the latest
 * was missing or corrupt and the previous one was used; err->message then still says why (for a
 * log line). Returns NULL with SPH_ERR_IO when there is no valid checkpoint. */
sphd_ckpt *sphd_ckpt_load(const char *dir, int *fell_back, sph_error *err);

/* Renames dir's checkpoint files (the latest and the previous) to NAME.unreadable, for a run
 * that starts afresh where they could not be loaded: they are kept, not overwritten by its first
 * checkpoint. Returns how many were renamed. */
int sphd_ckpt_set_aside(const char *dir);

/* Verifies and loads one checkpoint file. */
sphd_ckpt *sphd_ckpt_load_file(const char *path, sph_error *err);

/* A section's bytes (borrowed, valid until sphd_ckpt_free), or NULL if absent. */
const void *sphd_ckpt_get(const sphd_ckpt *c, const char *name, size_t *size);

/* free(NULL) is a no-op. */
void sphd_ckpt_free(sphd_ckpt *c);

#endif

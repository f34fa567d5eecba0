/*
 * sph_inputs: the files a case names (its geometry items' "mesh", a wavemaker's series "file":
 * sph_case_files), as they travel with a job:
 * sphctl reads them next to the case file and sends them in `submit` and `sweep`
 * (args.files), sphd keeps them in the job's directory under files/ (PROTOCOL.md 3.11). The
 * limits and the rule for a name are here so that both sides agree.
 */
#ifndef SPH_INPUTS_H
#define SPH_INPUTS_H

#include "sph_config.h"

#include <stddef.h>

/* A name: at most this many bytes (the config keeps it in SPH_GEOMETRY_FILE_MAX with its NUL). */
#define SPH_INPUT_NAME_MAX (SPH_GEOMETRY_FILE_MAX - 1) /* 127 */
/* Bytes of one file, and of all the files of one request, before base64: 8 MiB of data is
 * about 10.7 MiB of base64, which leaves room for the case under sphd's default
 * --max-msg-size (16 MiB). */
#define SPH_INPUT_MAX_FILE  (8L << 20)
#define SPH_INPUT_MAX_TOTAL (8L << 20)
/* Files of one request (every geometry item may name one, and a wavemaker its series). */
#define SPH_INPUT_MAX_COUNT (SPH_CONFIG_MAX_GEOMETRY + 1)
/* The job directory's subdirectory that holds them. */
#define SPH_INPUT_DIR "files"

/* 0 when name is usable as a file a case names: a relative path of 1 to SPH_INPUT_NAME_MAX
 * bytes, components separated by single '/', none empty, none starting with '.' (so no '.' or
 * '..'), no control characters or '\\'. Else -1 and why (a sentence, n bytes) says what to
 * fix. */
int sph_input_name_check(const char *name, char *why, size_t n);

#endif

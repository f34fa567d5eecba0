/*
 * Helpers shared by the fuzz targets: a private scratch directory (on tmpfs when there is one)
 * that lives as long as the process, writing a file, and emptying a directory tree.
 */
#ifndef SPH_FUZZ_UTIL_H
#define SPH_FUZZ_UTIL_H

#include <stddef.h>
#include <stdint.h>

/* The process's scratch directory, created on first use (aborts when it cannot be). */
const char *sph_fuzz_dir(void);
/* Writes data to dir/name (replacing it). Returns 0 or -1. */
int sph_fuzz_write(const char *dir, const char *name, const void *data, size_t size);
/* Removes what is inside path (path itself stays). */
void sph_fuzz_empty(const char *path);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#endif

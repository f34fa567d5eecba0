/* sph_fileio: small file helpers that sphd and sphctl share (POSIX). */
#ifndef SPH_FILEIO_H
#define SPH_FILEIO_H

#include <stddef.h>
#include <sys/types.h>

/* mkdir -p: creates path and its missing parents with mode. An existing directory is fine; an
 * existing non-directory fails with ENOTDIR. Returns 0 or -1 (errno). */
int sph_mkdirs(const char *path, mode_t mode);

/* Writes all n bytes to fd, retrying on EINTR. Returns 0 or -1 (errno). */
int sph_write_all(int fd, const void *p, size_t n);

/* Replaces path atomically with len bytes of data: written to PATH.tmp.PID with mode, fsync'd,
 * renamed over path. On failure the temporary is removed and path is untouched. Returns 0 or -1
 * (errno). */
int sph_write_atomic(const char *path, const void *data, size_t len, mode_t mode);

#endif

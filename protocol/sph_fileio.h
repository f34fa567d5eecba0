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

/* Reads the regular file at path whole into a new buffer *data (the caller frees it) of *len
 * bytes, at most max: 0; -1 when it cannot be opened or is not a regular file (errno, 0 for not
 * regular), -2 when it holds more than max bytes (*len: its size), -3 out of memory, -4 on a read
 * error or when it changed while read (errno, 0 for changed). */
int sph_read_file(const char *path, size_t max, char **data, size_t *len);

#endif

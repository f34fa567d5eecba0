/* sph_fileio: small file helpers that sphd and sphctl share. */
#include "sph_fileio.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

static int mkdir_if_needed(const char *path, mode_t mode)
{
    if (mkdir(path, mode) == 0 || errno == EEXIST) {
        struct stat st;
        if (stat(path, &st) == 0 && S_ISDIR(st.st_mode))
            return 0;
        errno = ENOTDIR;
    }
    return -1;
}

int sph_mkdirs(const char *path, mode_t mode)
{
    char buf[4096];
    if (snprintf(buf, sizeof buf, "%s", path) >= (int)sizeof buf) {
        errno = ENAMETOOLONG;
        return -1;
    }
    for (char *p = buf + 1; *p; p++) {
        if (*p != '/' || p[-1] == '/')
            continue;
        *p = '\0';
        int rc = mkdir_if_needed(buf, mode);
        *p = '/';
        if (rc != 0)
            return -1;
    }
    return mkdir_if_needed(buf, mode);
}

int sph_write_all(int fd, const void *data, size_t n)
{
    const unsigned char *p = data;
    while (n > 0) {
        ssize_t w = write(fd, p, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w < 0)
            return -1;
        p += w;
        n -= (size_t)w;
    }
    return 0;
}

int sph_write_atomic(const char *path, const void *data, size_t len, mode_t mode)
{
    char tmp[4096];
    if (snprintf(tmp, sizeof tmp, "%s.tmp.%ld", path, (long)getpid()) >= (int)sizeof tmp) {
        errno = ENAMETOOLONG;
        return -1;
    }
    int fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, mode);
    if (fd < 0)
        return -1;
    int bad = sph_write_all(fd, data, len) != 0 || fsync(fd) != 0;
    int saved = errno;
    if (close(fd) != 0 && !bad) {
        bad = 1;
        saved = errno;
    }
    if (!bad && rename(tmp, path) != 0) {
        bad = 1;
        saved = errno;
    }
    if (bad) {
        unlink(tmp);
        errno = saved;
        return -1;
    }
    return 0;
}

int sph_read_file(const char *path, size_t max, char **data, size_t *len)
{
    *data = NULL;
    *len = 0;
    FILE *f = fopen(path, "rb");
    if (!f)
        return -1;
    struct stat st;
    const int stated = fstat(fileno(f), &st) == 0, e = errno;
    if (!stated || !S_ISREG(st.st_mode)) {
        fclose(f);
        errno = stated ? 0 : e;
        return -1;
    }
    *len = (size_t)st.st_size;
    if ((unsigned long long)st.st_size > (unsigned long long)max) {
        fclose(f);
        return -2;
    }
    char *buf = malloc(*len ? *len : 1);
    if (!buf) {
        fclose(f);
        return -3;
    }
    errno = 0;
    const size_t got = fread(buf, 1, *len, f);
    const int bad = ferror(f), re = errno;
    fclose(f);
    if (bad || got != *len) {
        free(buf);
        errno = bad ? re : 0;
        return -4;
    }
    *data = buf;
    return 0;
}

#include "sphd.h"

#include "sph_fileio.h"

#include <dirent.h>
#include <jansson.h>
#include <stdlib.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int sphd_mkdirs(const char *path)
{
    return sph_mkdirs(path, 0700);
}

int sphd_write_atomic(const char *path, const char *data, size_t len)
{
    return sph_write_atomic(path, data, len, 0600);
}

int sphd_write_json(const char *dir, const char *name, const json_t *j)
{
    char path[4096];
    if (snprintf(path, sizeof path, "%s/%s", dir, name) >= (int)sizeof path) {
        errno = ENAMETOOLONG;
        return -1;
    }
    char *text = json_dumps(j, JSON_INDENT(2) | JSON_REAL_PRECISION(17));
    if (!text) {
        errno = ENOMEM;
        return -1;
    }
    int rc = sphd_write_atomic(path, text, strlen(text));
    int saved = errno;
    free(text);
    errno = saved;
    return rc;
}

int sphd_remove_stale_temps(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return -1;
    char mine[32]; /* this process's own temporaries may be in flight on another thread */
    snprintf(mine, sizeof mine, ".tmp.%ld", (long)getpid());
    int removed = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        const char *t = strstr(e->d_name, ".tmp.");
        if (!t || strcmp(t, mine) == 0)
            continue;
        char path[4096];
        if (snprintf(path, sizeof path, "%s/%s", dir, e->d_name) < (int)sizeof path &&
            unlink(path) == 0)
            removed++;
    }
    closedir(d);
    return removed;
}

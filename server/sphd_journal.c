#include "sphd_journal.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void journal_path(char *buf, size_t n, const char *jobdir)
{
    snprintf(buf, n, "%s/journal.jsonl", jobdir);
}

static int append(const char *jobdir, const json_t *record, int sync, sph_error *err)
{
    char path[4096];
    journal_path(path, sizeof path, jobdir);
    char *line = json_dumps(record, JSON_COMPACT | JSON_REAL_PRECISION(17));
    if (!line)
        return sph_error_set(err, SPH_ERR_NOMEM, "", "cannot encode a journal record");
    size_t len = strlen(line);
    line[len] = '\n'; /* json_dumps' terminator becomes the newline; written without a NUL */
    int fd = open(path, O_RDWR | O_CREAT | O_APPEND | O_CLOEXEC, 0600);
    int rc = fd < 0 ? -1 : 0;
    /* after a crash mid-append the file ends in a torn line: end it, so this record stands alone */
    off_t end = rc == 0 ? lseek(fd, 0, SEEK_END) : 0;
    char last = '\n';
    if (end > 0 && pread(fd, &last, 1, end - 1) == 1 && last != '\n' && write(fd, "\n", 1) != 1)
        rc = -1;
    size_t done = 0;
    while (rc == 0 && done < len + 1) {
        ssize_t w = write(fd, line + done, len + 1 - done);
        if (w < 0 && errno != EINTR)
            rc = -1;
        else if (w > 0)
            done += (size_t)w;
    }
    if (rc == 0 && sync)
        rc = fsync(fd);
    int saved = errno;
    if (fd >= 0)
        close(fd);
    free(line);
    if (rc != 0)
        return sph_error_set(err, SPH_ERR_IO, "", "appending to journal '%s' failed: %s", path,
                             strerror(saved));
    return 0;
}

int sphd_journal_append(const char *jobdir, const json_t *record, sph_error *err)
{
    return append(jobdir, record, 1, err);
}

int sphd_journal_note(const char *jobdir, const json_t *record, sph_error *err)
{
    return append(jobdir, record, 0, err);
}

int sphd_journal_replay(const char *jobdir, void (*cb)(void *ud, const json_t *record), void *ud,
                        int *torn, sph_error *err)
{
    char path[4096];
    journal_path(path, sizeof path, jobdir);
    if (torn)
        *torn = 0;
    FILE *f = fopen(path, "r");
    if (!f)
        return sph_error_set(err, SPH_ERR_IO, "", "cannot open journal '%s': %s", path,
                             strerror(errno));
    char *line = NULL;
    size_t cap = 0;
    ssize_t n;
    while ((n = getline(&line, &cap, f)) > 0) {
        const int complete = line[n - 1] == '\n';
        json_error_t jerr;
        json_t *rec = complete ? json_loadb(line, (size_t)n, 0, &jerr) : NULL;
        if (!rec || !json_is_object(rec)) {
            /* only the last line can be torn by a crash; anything else is damage */
            if (torn)
                *torn = 1;
            json_decref(rec);
            continue;
        }
        cb(ud, rec);
        json_decref(rec);
    }
    free(line);
    fclose(f);
    return 0;
}

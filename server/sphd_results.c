/*
 * A job's result files for clients on other machines: the listing (`results`), one chunk of one
 * file (`fetch`) and the diagnostics as CSV (`export`). In the daemon these run on the files
 * thread (sphd_files.c), never on the socket thread; each fetch reads one bounded chunk.
 */
#include "sphd_daemon.h"
#include "sphd_h5.h"

#include "sph_base64.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#define CRC_BLOCK (1L << 20)

static int has_prefix_suffix(const char *name, const char *prefix, const char *suffix)
{
    size_t n = strlen(name), p = strlen(prefix), s = strlen(suffix);
    return n >= p + s && strncmp(name, prefix, p) == 0 && strcmp(name + n - s, suffix) == 0;
}

const char *sphd_results_kind(const char *name)
{
    static const char *const exact[][2] = {
        {"case.json", "case"},        {"job.json", "record"},
        {"steering.json", "record"},  {"journal.jsonl", "journal"},
        {"result.json", "result"},    {"diag.h5", "diagnostics"},
        {"checkpoint", "checkpoint"}, {"checkpoint.prev", "checkpoint"},
    };
    for (size_t i = 0; i < sizeof exact / sizeof exact[0]; i++)
        if (strcmp(name, exact[i][0]) == 0)
            return exact[i][1];
    if (strncmp(name, SPH_INPUT_DIR "/", sizeof SPH_INPUT_DIR) == 0)
        return "input";
    if (has_prefix_suffix(name, "snap_", ".h5"))
        return "snapshot";
    if (has_prefix_suffix(name, "", ".xmf"))
        return "xdmf";
    return "other";
}

/* A name `results` lists: a plain file name, not hidden, not a temporary of an atomic write. */
static int listable_name(const char *name)
{
    return name[0] && name[0] != '.' && !strchr(name, '/') && !strstr(name, "..") &&
           !strstr(name, ".tmp.");
}

/* A name `fetch` takes: a listable name, or files/NAME with NAME a usable input's name (no
 * '..', no leading '.' in any component: no way out of files/). */
static int fetchable_name(const char *name)
{
    const size_t p = sizeof SPH_INPUT_DIR; /* "files/" */
    if (strncmp(name, SPH_INPUT_DIR "/", p) == 0)
        return sph_input_name_check(name + p, NULL, 0) == 0 && !strstr(name, ".tmp.");
    return listable_name(name);
}

static int crc_file(int fd, unsigned long *crc)
{
    unsigned char *buf = malloc(CRC_BLOCK);
    if (!buf)
        return -1;
    uLong c = crc32(0L, Z_NULL, 0);
    off_t off = 0;
    for (;;) {
        ssize_t n = pread(fd, buf, CRC_BLOCK, off);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0) {
            free(buf);
            return -1;
        }
        if (n == 0)
            break;
        c = crc32(c, buf, (uInt)n);
        off += n;
    }
    free(buf);
    *crc = c;
    return 0;
}

static int by_name(const void *a, const void *b)
{
    const char *x = json_string_value(json_object_get(*(json_t *const *)a, "name"));
    const char *y = json_string_value(json_object_get(*(json_t *const *)b, "name"));
    return strcmp(x, y);
}

/* One listed file as {"name","size","kind"[,"crc32"]}; NULL (not an error) when it is not a
 * regular file or vanished meanwhile. */
static json_t *file_entry(int dfd, const char *name, int checksums, sphd_err *e, int *failed)
{
    int fd = openat(dfd, name, O_RDONLY | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0)
        return NULL;
    struct stat st;
    json_t *f = NULL;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode))
        goto out;
    f = json_pack("{s:s, s:I, s:s}", "name", name, "size", (json_int_t)st.st_size, "kind",
                  sphd_results_kind(name));
    if (f && checksums) {
        unsigned long crc;
        char hex[16];
        if (crc_file(fd, &crc) != 0) {
            sphd_err_set(e, SPHD_E_INTERNAL, NULL, "cannot read %s: %s", name, strerror(errno));
            *failed = 1;
            json_decref(f);
            f = NULL;
            goto out;
        }
        snprintf(hex, sizeof hex, "%08lx", crc & 0xffffffffUL);
        json_object_set_new(f, "crc32", json_string(hex));
    }
out:
    close(fd);
    return f;
}

/* The regular files under dir/rel (the job's files/, and the folders below it), listed as
 * rel/NAME. */
static void list_inputs(const char *dir, const char *rel, int depth, int checksums, json_t *files,
                        sphd_err *e, int *failed)
{
    char path[SPHD_PATH_MAX + 256];
    if (depth > 16 || snprintf(path, sizeof path, "%s/%s", dir, rel) >= (int)sizeof path)
        return;
    int dfd = open(path, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    DIR *d = dfd >= 0 ? fdopendir(dfd) : NULL;
    if (!d) {
        if (dfd >= 0)
            close(dfd);
        return; /* none: a case that names no file */
    }
    struct dirent *de;
    while (!*failed && (de = readdir(d))) {
        char sub[SPHD_PATH_MAX];
        if (!listable_name(de->d_name) ||
            snprintf(sub, sizeof sub, "%s/%s", rel, de->d_name) >= (int)sizeof sub)
            continue;
        struct stat st;
        if (fstatat(dfd, de->d_name, &st, AT_SYMLINK_NOFOLLOW) != 0)
            continue;
        if (S_ISDIR(st.st_mode)) {
            list_inputs(dir, sub, depth + 1, checksums, files, e, failed);
            continue;
        }
        json_t *f = file_entry(dfd, de->d_name, checksums, e, failed);
        if (f) {
            json_object_set_new(f, "name", json_string(sub));
            json_object_set_new(f, "kind", json_string(sphd_results_kind(sub)));
            json_array_append_new(files, f);
        }
    }
    closedir(d);
}

json_t *sphd_results_list(const sphd_job *j, int checksums, sphd_err *e)
{
    int dfd = open(j->dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    DIR *dir = dfd >= 0 ? fdopendir(dfd) : NULL;
    if (!dir) {
        if (dfd >= 0)
            close(dfd);
        sphd_err_set(e, SPHD_E_INTERNAL, NULL, "cannot read the job directory %s: %s", j->dir,
                     strerror(errno));
        return NULL;
    }
    json_t *files = json_array();
    int failed = !files;
    if (failed)
        sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
    struct dirent *de;
    while (!failed && (de = readdir(dir))) {
        if (!listable_name(de->d_name))
            continue;
        json_t *f = file_entry(dfd, de->d_name, checksums, e, &failed);
        if (f)
            json_array_append_new(files, f);
    }
    closedir(dir);
    if (!failed)
        list_inputs(j->dir, SPH_INPUT_DIR, 0, checksums, files, e, &failed);
    if (failed) {
        json_decref(files);
        return NULL;
    }
    /* sort by name: jansson arrays have no sort, so sort a copy of the item pointers */
    size_t n = json_array_size(files);
    json_t **items = malloc((n ? n : 1) * sizeof *items);
    json_t *sorted = json_array();
    if (!items || !sorted) {
        free(items);
        json_decref(sorted);
        json_decref(files);
        sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
        return NULL;
    }
    for (size_t i = 0; i < n; i++)
        items[i] = json_array_get(files, i);
    qsort(items, n, sizeof *items, by_name);
    for (size_t i = 0; i < n; i++)
        json_array_append(sorted, items[i]);
    free(items);
    json_decref(files);
    json_t *r = json_pack("{s:s, s:s, s:o}", "job", j->id, "dir", j->dir, "files", sorted);
    if (!r)
        sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
    return r;
}

json_t *sphd_results_fetch(const sphd_job *j, const char *file, long long offset, long length,
                           sphd_err *e)
{
    if (!fetchable_name(file)) {
        sphd_err_set(e, SPHD_E_BAD_REQUEST, "/args/file",
                     "'%.64s' is not a file of the job: give a name from 'results' "
                     "(no '/' but after files/, no leading '.', no '..')",
                     file);
        return NULL;
    }
    char path[SPHD_PATH_MAX + 256];
    if (snprintf(path, sizeof path, "%s/%s", j->dir, file) >= (int)sizeof path) {
        sphd_err_set(e, SPHD_E_BAD_REQUEST, "/args/file", "file name too long");
        return NULL;
    }
    int fd = open(path, O_RDONLY | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0) {
        if (errno == ENOENT || errno == ELOOP) {
            sphd_err_set(e, SPHD_E_NOT_FOUND, "/args/file",
                         "job %s has no file '%.64s' ('sphctl results %s' lists them)", j->id, file,
                         j->id);
            return NULL;
        }
        sphd_err_set(e, SPHD_E_INTERNAL, NULL, "cannot open %s: %s", path, strerror(errno));
        return NULL;
    }
    struct stat st;
    json_t *r = NULL;
    unsigned char *buf = NULL;
    char *text = NULL;
    if (fstat(fd, &st) != 0) {
        sphd_err_set(e, SPHD_E_INTERNAL, NULL, "cannot stat %s: %s", path, strerror(errno));
        goto out;
    }
    if (!S_ISREG(st.st_mode)) {
        sphd_err_set(e, SPHD_E_NOT_FOUND, "/args/file", "'%.64s' is not a regular file", file);
        goto out;
    }
    if (offset > (long long)st.st_size) {
        sphd_err_set(e, SPHD_E_BAD_REQUEST, "/args/offset",
                     "offset %lld is past the end of %s (%lld bytes)", offset, file,
                     (long long)st.st_size);
        goto out;
    }
    long long left = (long long)st.st_size - offset;
    size_t want = (size_t)(left < length ? left : length), got = 0;
    buf = malloc(want ? want : 1);
    text = buf ? malloc(sph_base64_encoded_len(want) + 1) : NULL;
    if (!text) {
        sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
        goto out;
    }
    while (got < want) {
        ssize_t n = pread(fd, buf + got, want - got, (off_t)(offset + (long long)got));
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0) {
            sphd_err_set(e, SPHD_E_INTERNAL, NULL, "cannot read %s: %s", path, strerror(errno));
            goto out;
        }
        if (n == 0)
            break; /* the file shrank meanwhile: send what there is */
        got += (size_t)n;
    }
    char hex[16];
    snprintf(hex, sizeof hex, "%08lx", crc32(crc32(0L, Z_NULL, 0), buf, (uInt)got) & 0xffffffffUL);
    sph_base64_encode(buf, got, text);
    const int eof = offset + (long long)got >= (long long)st.st_size;
    r = json_pack("{s:s, s:I, s:I, s:I, s:b, s:s, s:s}", "file", file, "offset", (json_int_t)offset,
                  "length", (json_int_t)got, "size", (json_int_t)st.st_size, "eof", eof, "crc32",
                  hex, "data", text);
    if (!r)
        sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
out:
    free(text);
    free(buf);
    close(fd);
    return r;
}

json_t *sphd_results_export_csv(const sphd_job *j, sphd_err *e)
{
    char path[SPHD_PATH_MAX + 16];
    if (snprintf(path, sizeof path, "%s/diag.h5", j->dir) >= (int)sizeof path) {
        sphd_err_set(e, SPHD_E_INTERNAL, NULL, "job directory path too long");
        return NULL;
    }
    struct stat st;
    const int missing = stat(path, &st) != 0;
    if (missing && errno != ENOENT) {
        sphd_err_set(e, SPHD_E_INTERNAL, NULL, "cannot read %s: %s", path, strerror(errno));
        return NULL;
    }
    if (missing) {
        if (j->c && !sph_case_is_sim(j->c))
            sphd_err_set(e, SPHD_E_BAD_STATE, "/args/job",
                         "job %s is a kernel study: it has no diagnostics time series (its "
                         "result is in result.json: 'sphctl fetch %s')",
                         j->id, j->id);
        else
            sphd_err_set(e, SPHD_E_BAD_STATE, "/args/job",
                         "job %s has no diagnostics yet: they are written once it runs "
                         "(start or step it first)",
                         j->id);
        return NULL;
    }
    char *text = NULL;
    size_t len = 0;
    FILE *mem = open_memstream(&text, &len);
    if (!mem) {
        sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
        return NULL;
    }
    sph_error err;
    sph_error_clear(&err);
    int rc = sphd_diagfile_export_csv(path, mem, &err);
    if (fclose(mem) != 0 && rc == 0) {
        free(text);
        sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
        return NULL;
    }
    if (rc != 0) {
        free(text);
        sphd_err_set(e, SPHD_E_INTERNAL, NULL, "cannot export %s: %s", path, err.message);
        return NULL;
    }
    long rows = 0;
    for (size_t i = 0; i < len; i++)
        rows += text[i] == '\n';
    json_t *r = json_pack("{s:s, s:I, s:s%}", "format", "csv", "rows",
                          (json_int_t)(rows > 0 ? rows - 1 : 0), "csv", text, len);
    free(text);
    if (!r)
        sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
    return r;
}

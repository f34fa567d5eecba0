/* sphctl's result-file commands: results (the listing), fetch (download, checksum verified) and
 * export (the diagnostics as CSV, or a sweep's table). */
#include "sphctl.h"

#include "sph_base64.h"
#include "sph_fileio.h"
#include "sph_inputs.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#define FETCH_CHUNK (4L << 20) /* sphd's maximum `length` */

static void fmt_size(double bytes, char *buf, size_t n)
{
    static const char *const units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
    int u = 0;
    while (bytes >= 1024 && u < 4) {
        bytes /= 1024;
        u++;
    }
    if (u == 0)
        snprintf(buf, n, "%.0f B", bytes);
    else
        snprintf(buf, n, "%.1f %s", bytes, units[u]);
}

/* A local failure in --json mode is still one JSON document on stdout. */
static int local_error(sphctl *c, int rc, const char *code, const char *fmt, const char *a,
                       const char *b)
{
    char msg[1024];
    snprintf(msg, sizeof msg, fmt, a, b);
    fprintf(stderr, "sphctl: %s\n", msg);
    if (c->json) {
        json_t *doc =
            json_pack("{s:b, s:{s:s, s:s}}", "ok", 0, "error", "code", code, "message", msg);
        if (doc)
            sphctl_print_json(doc, 1);
        json_decref(doc);
    }
    return rc;
}

/* ---- results ---- */

/* The listing of results, with the CRC-32 when checksums is not NULL. */
static void print_results(const json_t *r, const void *checksums)
{
    if (checksums)
        printf("%-32s %10s  %-12s  %s\n", "NAME", "SIZE", "KIND", "CRC32");
    else
        printf("%-32s %10s  %s\n", "NAME", "SIZE", "KIND");
    size_t i;
    json_t *f;
    json_array_foreach(json_object_get(r, "files"), i, f)
    {
        char size[32];
        fmt_size((double)json_integer_value(json_object_get(f, "size")), size, sizeof size);
        const char *name = json_string_value(json_object_get(f, "name"));
        const char *kind = json_string_value(json_object_get(f, "kind"));
        if (checksums)
            printf("%-32s %10s  %-12s  %s\n", name, size, kind,
                   json_string_value(json_object_get(f, "crc32")));
        else
            printf("%-32s %10s  %s\n", name, size, kind);
    }
    printf("(in %s on sphd's machine)\n", json_string_value(json_object_get(r, "dir")));
}

int sphctl_cmd_results(sphctl *c, int argc, char **argv)
{
    static const char help[] =
        "Usage: sphctl results JOB [--checksums]\n"
        "Lists the job's files in sphd's state directory: name, size, kind (case, record,\n"
        "journal, result, diagnostics, snapshot, xdmf, checkpoint, and input: files/NAME,\n"
        "a file the case names, sent with it).\n"
        "  --checksums   also the CRC-32 of each file (sphd reads every file: slower)\n"
        "Exit codes: 0 ok, 1 no such job, 69 sphd unreachable.\n";
    static const struct option lo[] = {
        {"checksums", no_argument, NULL, 0}, {"help", no_argument, NULL, 'h'}, {NULL, 0, NULL, 0}};
    static const sphctl_argspec spec = {help, "h", lo, NULL, 1, 1, "results takes one JOB"};
    const char *checksums = NULL;
    int rc = sphctl_args(&spec, argc, argv, sphctl_store_opt, &checksums);
    if (rc != SPHCTL_RUN)
        return rc;
    json_t *args = json_pack("{s:s}", "job", argv[optind]);
    if (checksums)
        json_object_set_new(args, "checksums", json_true());
    return sphctl_show(c, "results", args, print_results, checksums);
}

/* ---- fetch ---- */

/* Closes fd, after an fsync when nothing failed before (bad is 0). Returns 0, or -1 with errno
 * of the first failure (the caller's errno when bad). */
static int sync_close(int fd, int bad)
{
    bad = bad || fsync(fd) != 0;
    int saved = errno;
    if (close(fd) != 0 && !bad)
        return -1;
    errno = saved;
    return bad ? -1 : 0;
}

typedef struct fetch_file {
    const char *job, *name, *dir; /* dir: DEST/JOB */
    const char *want_crc;         /* from results --checksums */
    long long size;               /* from results */
    int progress;                 /* on a TTY */
} fetch_file;

/* Downloads one file into f->dir under a temporary name, then renames it. Returns 0 (crc set to
 * the file's CRC-32, *bytes its size) or an exit code (the partial file removed). */
static int fetch_one(sphctl *c, const fetch_file *f, char crc_out[16], long long *bytes)
{
    char tmp[4096], final[4096], sub[4096];
    /* files/NAME (the inputs, PROTOCOL.md 3.11) go to DIR/files/..., made as needed */
    const char *base = strrchr(f->name, '/');
    const int sublen =
        base ? snprintf(sub, sizeof sub, "%s/%.*s", f->dir, (int)(base - f->name), f->name)
             : snprintf(sub, sizeof sub, "%s", f->dir);
    if (sublen < 0 || sublen >= (int)sizeof sub)
        return local_error(c, SPHCTL_EX_CANTCREAT, "io", "path too long: %s%s", f->dir, "");
    base = base ? base + 1 : f->name;
    if (snprintf(final, sizeof final, "%s/%s", f->dir, f->name) >= (int)sizeof final ||
        snprintf(tmp, sizeof tmp, "%s/.%s.part.%ld", sub, base, (long)getpid()) >= (int)sizeof tmp)
        return local_error(c, SPHCTL_EX_CANTCREAT, "io", "path too long: %s%s", f->dir, "");
    if (sph_mkdirs(sub, 0755) != 0)
        return local_error(c, SPHCTL_EX_CANTCREAT, "io", "cannot create %s: %s", sub,
                           strerror(errno));
    int fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0)
        return local_error(c, SPHCTL_EX_CANTCREAT, "io", "cannot create %s: %s", tmp,
                           strerror(errno));
    uLong crc = crc32(0L, Z_NULL, 0);
    long long off = 0;
    unsigned char *buf = malloc(FETCH_CHUNK);
    int rc = buf ? 0 : local_error(c, SPHCTL_EX_SOFTWARE, "internal", "out of memory%s%s", "", "");
    for (int eof = 0; !rc && !eof;) {
        json_t *args = json_pack("{s:s, s:s, s:I, s:I}", "job", f->job, "file", f->name, "offset",
                                 (json_int_t)off, "length", (json_int_t)FETCH_CHUNK);
        json_t *r;
        if ((rc = sphctl_request(c, "fetch", args, &r, NULL, 0)))
            break;
        const char *data = json_string_value(json_object_get(r, "data"));
        const char *chunk_crc = json_string_value(json_object_get(r, "crc32"));
        json_int_t len = json_integer_value(json_object_get(r, "length"));
        eof = json_is_true(json_object_get(r, "eof"));
        size_t dlen = data ? strlen(data) : 0;
        long n =
            data && dlen / 4 * 3 <= (size_t)FETCH_CHUNK ? sph_base64_decode(data, dlen, buf) : -1;
        char hex[16] = "";
        if (n >= 0)
            snprintf(hex, sizeof hex, "%08lx",
                     crc32(crc32(0L, Z_NULL, 0), buf, (uInt)n) & 0xffffffffUL);
        if (n < 0 || n != len || !chunk_crc || strcmp(hex, chunk_crc) != 0) {
            char where[64];
            snprintf(where, sizeof where, "%lld", off);
            rc = local_error(c, SPHCTL_EX_FAILED, "checksum",
                             "%s: the chunk at offset %s arrived damaged (CRC-32 mismatch); "
                             "partial file removed, run fetch again",
                             f->name, where);
        } else if (sph_write_all(fd, buf, (size_t)n) != 0) {
            rc = local_error(c, SPHCTL_EX_CANTCREAT, "io", "cannot write %s: %s", tmp,
                             strerror(errno));
        } else {
            crc = crc32(crc, buf, (uInt)n);
            off += n;
            if (!eof && n == 0)
                eof = 1; /* no progress: the file shrank */
        }
        json_decref(r);
        if (f->progress && !rc) {
            fprintf(stderr, "\r%-32s %lld/%lld bytes", f->name, off, f->size);
            fflush(stderr);
        }
    }
    free(buf);
    if (f->progress)
        fputs("\r\033[K", stderr);
    if (sync_close(fd, rc != 0) != 0 && !rc)
        rc = local_error(c, SPHCTL_EX_CANTCREAT, "io", "cannot write %s: %s", tmp, strerror(errno));
    snprintf(crc_out, 16, "%08lx", crc & 0xffffffffUL);
    if (!rc && f->want_crc && strcmp(crc_out, f->want_crc) != 0)
        rc = local_error(c, SPHCTL_EX_FAILED, "checksum",
                         "%s: CRC-32 mismatch over the whole file (the file changed on sphd's "
                         "side, or the transfer is damaged; want %s); partial file removed, run "
                         "fetch again",
                         f->name, f->want_crc);
    if (!rc && rename(tmp, final) != 0)
        rc = local_error(c, SPHCTL_EX_CANTCREAT, "io", "cannot rename to %s: %s", final,
                         strerror(errno));
    if (rc)
        unlink(tmp);
    *bytes = off;
    return rc;
}

int sphctl_cmd_fetch(sphctl *c, int argc, char **argv)
{
    static const char help[] =
        "Usage: sphctl fetch JOB [--dest DIR] [--include-checkpoints]\n"
        "Downloads the job's files over the control socket into DIR/JOB/ (default DIR: .),\n"
        "for a client on another machine than sphd. Each chunk's CRC-32 is checked, then each\n"
        "whole file's against 'sphctl results JOB --checksums'; a file is written under a\n"
        "temporary name and renamed when complete.\n"
        "  --dest DIR              where to put the JOB directory (created if needed)\n"
        "  --include-checkpoints   also the checkpoints (large; only useful to resume elsewhere)\n"
        "Exit codes: 0 ok, 1 refused or a checksum mismatch (the partial file is removed),\n"
        "69 sphd unreachable, 73 cannot write DIR.\n";
    enum { DEST, CKPT, NOPTS };
    static const struct option lo[] = {{"dest", required_argument, NULL, DEST},
                                       {"include-checkpoints", no_argument, NULL, CKPT},
                                       {"help", no_argument, NULL, 'h'},
                                       {NULL, 0, NULL, 0}};
    static const sphctl_argspec spec = {help, "h", lo, NULL, 1, 1, "fetch takes one JOB"};
    const char *opt[NOPTS] = {".", NULL};
    int rc = sphctl_args(&spec, argc, argv, sphctl_store_opt, opt);
    if (rc != SPHCTL_RUN)
        return rc;
    const char *dest = opt[DEST], *job = argv[optind];
    int with_ckpt = opt[CKPT] != NULL;
    json_t *list;
    rc = sphctl_request(c, "results", json_pack("{s:s, s:b}", "job", job, "checksums", 1), &list,
                        NULL, 0);
    if (rc)
        return rc;
    char dir[4096];
    if (snprintf(dir, sizeof dir, "%s/%s", dest, job) >= (int)sizeof dir) {
        json_decref(list);
        return local_error(c, SPHCTL_EX_USAGE, "usage", "--dest too long: %s%s", dest, "");
    }
    if (sph_mkdirs(dir, 0755) != 0) {
        json_decref(list);
        return local_error(c, SPHCTL_EX_CANTCREAT, "io", "cannot create %s: %s", dir,
                           strerror(errno));
    }
    json_t *done = json_array();
    long long total = 0;
    size_t i;
    json_t *f;
    json_array_foreach(json_object_get(list, "files"), i, f)
    {
        const char *name = json_string_value(json_object_get(f, "name"));
        const char *kind = json_string_value(json_object_get(f, "kind"));
        if (!name || (!with_ckpt && kind && strcmp(kind, "checkpoint") == 0))
            continue;
        /* a plain name, or files/NAME below files/: nothing lands outside DEST/JOB */
        const int input = strncmp(name, SPH_INPUT_DIR "/", sizeof SPH_INPUT_DIR) == 0;
        if (name[0] == '.' || sph_input_name_check(name, NULL, 0) != 0 ||
            (!input && strchr(name, '/'))) {
            rc = local_error(c, SPHCTL_EX_FAILED, "bad_name",
                             "sphd listed '%s', which is not a name to write under %s", name, dir);
            break;
        }
        fetch_file ff = {.job = job,
                         .name = name,
                         .dir = dir,
                         .want_crc = json_string_value(json_object_get(f, "crc32")),
                         .size = json_integer_value(json_object_get(f, "size")),
                         .progress = !c->json && isatty(STDERR_FILENO)};
        char crc[16];
        long long bytes = 0;
        if ((rc = fetch_one(c, &ff, crc, &bytes)))
            break;
        total += bytes;
        json_array_append_new(done, json_pack("{s:s, s:I, s:s}", "name", name, "size",
                                              (json_int_t)bytes, "crc32", crc));
        if (!c->json) {
            char size[32];
            fmt_size((double)bytes, size, sizeof size);
            printf("%-32s %10s  ok\n", name, size);
            fflush(stdout);
        }
    }
    json_decref(list);
    if (!rc) {
        if (c->json) {
            json_t *doc = json_pack("{s:s, s:s, s:O, s:I}", "job", job, "dest", dir, "files", done,
                                    "bytes", (json_int_t)total);
            sphctl_print_json(doc, 1);
            json_decref(doc);
        } else {
            char size[32];
            fmt_size((double)total, size, sizeof size);
            printf("%zu file(s), %s in %s\n", json_array_size(done), size, dir);
        }
    }
    json_decref(done);
    return rc;
}

/* ---- export ---- */

/* Writes the table r holds as text (len bytes) to out atomically (when out is not NULL), then says
 * so: with --json r with the text's key (what) replaced by "out", else "N rows written to out";
 * without out, the text on stdout (--json: r, compact). rows: the key of r's row count. Returns
 * the exit code. */
static int put_table(sphctl *c, json_t *r, const char *what, const char *text, size_t len,
                     const char *out, const char *rows)
{
    if (out && sph_write_atomic(out, text, len, 0644) != 0)
        return local_error(c, SPHCTL_EX_CANTCREAT, "io", "cannot write %s: %s", out,
                           strerror(errno));
    if (c->json) {
        if (out) {
            json_object_del(r, what);
            json_object_set_new(r, "out", json_string(out));
        }
        sphctl_print_json(r, 1);
    } else if (out) {
        printf("%lld rows written to %s\n", (long long)json_integer_value(json_object_get(r, rows)),
               out);
    } else if (fwrite(text, 1, len, stdout) != len || fflush(stdout) != 0) {
        return SPHCTL_EX_CANTCREAT;
    }
    return 0;
}

/* A sweep's table in format (csv or json) on stdout or in out. */
static int export_sweep(sphctl *c, const char *sweep, const char *format, const char *out)
{
    json_t *r;
    int rc = sphctl_request(c, "export", json_pack("{s:s, s:s}", "sweep", sweep, "format", format),
                            &r, NULL, 0);
    if (rc)
        return rc;
    if (strcmp(format, "csv") == 0) {
        json_t *csv = json_object_get(r, "csv");
        rc = json_is_string(csv)
                 ? put_table(c, r, "csv", json_string_value(csv), json_string_length(csv), out,
                             "count")
                 : local_error(c, SPHCTL_EX_SOFTWARE, "internal", "sphd sent no CSV%s%s", "", "");
    } else if (!out) {
        sphctl_print_json(r, c->json); /* the table itself: indented unless --json */
    } else {
        char *text = json_dumps(r, JSON_INDENT(2) | JSON_REAL_PRECISION(12));
        size_t len = text ? strlen(text) : 0;
        char *nl = text ? realloc(text, len + 2) : NULL;
        if (nl) {
            memcpy(nl + len, "\n", 2);
            rc = put_table(c, r, "rows", nl, len + 1, out, "count");
        } else {
            free(text);
            rc = local_error(c, SPHCTL_EX_SOFTWARE, "internal", "out of memory%s%s", "", "");
        }
        free(nl);
    }
    json_decref(r);
    return rc;
}

int sphctl_cmd_export(sphctl *c, int argc, char **argv)
{
    static const char help[] =
        "Usage: sphctl export JOB [--out FILE]\n"
        "       sphctl export --sweep SWEEP [--format csv|json] [--out FILE]\n"
        "The job's diagnostics time series (step, t, dt, ekin, ... one row per diag) as CSV,\n"
        "for a spreadsheet; works while the job runs. With --sweep, the sweep's table: one row\n"
        "per job (job, state, its parameters, then its result's summary once it is done).\n"
        "  --sweep SWEEP   the sweep's table instead of one job's diagnostics\n"
        "  --format F      the sweep's table as csv (default) or json (the table sphd sends:\n"
        "                  sweep, params, columns, count, rows; indented, one line with --json)\n"
        "  --out FILE      write it to FILE (atomically) instead of stdout\n"
        "With --json: {\"format\": \"csv\", \"rows\": N, \"csv\": TEXT} on stdout (a sweep:\n"
        "{\"sweep\", \"params\", \"columns\", \"count\", \"format\", \"csv\" or \"rows\"}); with "
        "--out,\n"
        "\"out\": FILE instead of the text.\n"
        "Exit codes: 0 ok, 1 no such job or sweep, or no diagnostics (kernel studies have none,\n"
        "a simulation has them once it ran), 64 usage, 69 sphd unreachable, 73 cannot write\n"
        "FILE.\n";
    enum { OUT, SWEEP, FORMAT, NOPTS };
    static const struct option lo[] = {{"out", required_argument, NULL, OUT},
                                       {"sweep", required_argument, NULL, SWEEP},
                                       {"format", required_argument, NULL, FORMAT},
                                       {"help", no_argument, NULL, 'h'},
                                       {NULL, 0, NULL, 0}};
    static const char bad_count[] = "export takes one JOB, or --sweep SWEEP (not both)";
    static const sphctl_argspec spec = {help, "h", lo, NULL, 0, 1, bad_count};
    const char *opt[NOPTS] = {NULL};
    int rc = sphctl_args(&spec, argc, argv, sphctl_store_opt, opt);
    if (rc != SPHCTL_RUN)
        return rc;
    const char *out = opt[OUT], *format = opt[FORMAT] ? opt[FORMAT] : "csv";
    if ((argc - optind == 1) == (opt[SWEEP] != NULL))
        return sphctl_usage("export", "%s", bad_count);
    if (strcmp(format, "csv") != 0 && (strcmp(format, "json") != 0 || !opt[SWEEP]))
        return sphctl_usage("export",
                            opt[SWEEP] ? "--format takes csv or json, not '%s'"
                                       : "a job's export is csv only, not '%s'",
                            format);
    if (opt[SWEEP])
        return export_sweep(c, opt[SWEEP], format, out);
    json_t *r;
    rc = sphctl_request(c, "export", json_pack("{s:s, s:s}", "job", argv[optind], "format", "csv"),
                        &r, NULL, 0);
    if (rc)
        return rc;
    json_t *csv = json_object_get(r, "csv");
    rc = json_is_string(csv)
             ? put_table(c, r, "csv", json_string_value(csv), json_string_length(csv), out, "rows")
             : local_error(c, SPHCTL_EX_SOFTWARE, "internal", "sphd sent no CSV%s%s", "", "");
    json_decref(r);
    return rc;
}

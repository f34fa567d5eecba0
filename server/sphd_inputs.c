/*
 * The files a case names (its geometry items' "mesh", a wavemaker's series: sph_case_files) as a
 * job's inputs: `submit` and `sweep`
 * bring them in args.files, checked here (names, base64, size, CRC-32, exactly the files the
 * case names), and sphd keeps them in the job's directory under files/ before the job is
 * accepted, so that a restarted sphd, or a runner on a cluster node, reads them from there
 * (PROTOCOL.md 3.11).
 */
#include "sphd_daemon.h"

#include "sph_base64.h"
#include "sph_fileio.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zlib.h>

/* The JSON pointer /args/files/NAME (NAME escaped: '~' as ~0, '/' as ~1). */
static const char *files_path(const char *name, char *buf, size_t n)
{
    size_t k = (size_t)snprintf(buf, n, "/args/files/");
    for (const char *p = name; *p && k + 3 < n; p++) {
        if (*p == '~' || *p == '/') {
            buf[k++] = '~';
            buf[k++] = *p == '~' ? '0' : '1';
        } else {
            buf[k++] = *p;
        }
    }
    buf[k < n ? k : n - 1] = '\0';
    return buf;
}

void sphd_inputs_free(sphd_inputs *in)
{
    for (int i = 0; i < in->n; i++)
        free(in->f[i].data);
    in->n = 0;
}

const sphd_input *sphd_inputs_get(const sphd_inputs *in, const char *name)
{
    for (int i = 0; i < in->n; i++)
        if (strcmp(in->f[i].name, name) == 0)
            return &in->f[i];
    return NULL;
}

int sphd_inputs_decode(const json_t *files, sphd_inputs *out, sphd_err *e)
{
    memset(out, 0, sizeof *out);
    if (!files)
        return 0;
    long total = 0;
    const char *name;
    json_t *f;
    char path[512], why[512];
    json_object_foreach((json_t *)files, name, f)
    {
        files_path(name, path, sizeof path);
        if (sph_input_name_check(name, why, sizeof why) != 0) {
            sphd_inputs_free(out);
            return sphd_err_set(e, SPHD_E_BAD_REQUEST, path, "%s", why);
        }
        if (out->n >= SPH_INPUT_MAX_COUNT) {
            sphd_inputs_free(out);
            return sphd_err_set(e, SPHD_E_BAD_REQUEST, path, "more than %d files",
                                SPH_INPUT_MAX_COUNT);
        }
        const char *data = NULL, *crc = NULL;
        json_int_t size = -1;
        json_error_t jerr;
        if (json_unpack_ex(f, &jerr, JSON_STRICT, "{s:s, s:s, s:I}", "data", &data, "crc32", &crc,
                           "size", &size) != 0) {
            sphd_inputs_free(out);
            return sphd_err_set(e, SPHD_E_BAD_REQUEST, path,
                                "each file is {\"data\": BASE64, \"crc32\": HEX, \"size\": N}: %s",
                                jerr.text);
        }
        if (size < 0 || size > SPH_INPUT_MAX_FILE || (total += (long)size) > SPH_INPUT_MAX_TOTAL) {
            sphd_inputs_free(out);
            return sphd_err_set(e, SPHD_E_TOO_LARGE, path,
                                size > SPH_INPUT_MAX_FILE || size < 0
                                    ? "'size' must be in [0, %ld] bytes (the limit of one file)"
                                    : "the files hold more than %ld bytes in all (the limit of "
                                      "one request)",
                                size > SPH_INPUT_MAX_FILE || size < 0 ? SPH_INPUT_MAX_FILE
                                                                      : SPH_INPUT_MAX_TOTAL);
        }
        const size_t dlen = strlen(data);
        sphd_input *in = &out->f[out->n];
        in->data = malloc(dlen / 4 * 3 + 1);
        if (!in->data) {
            sphd_inputs_free(out);
            return sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
        }
        out->n++;
        snprintf(in->name, sizeof in->name, "%s", name);
        const long got = sph_base64_decode(data, dlen, in->data);
        if (got < 0) {
            sphd_inputs_free(out);
            return sphd_err_set(e, SPHD_E_BAD_REQUEST, path,
                                "'data' is not base64 (RFC 4648 section 4, padded, no "
                                "whitespace): send the file's bytes encoded");
        }
        in->len = (size_t)got;
        char hex[16];
        snprintf(hex, sizeof hex, "%08lx",
                 crc32(crc32(0L, Z_NULL, 0), in->data, (uInt)in->len) & 0xffffffffUL);
        if ((json_int_t)in->len != size || strcmp(hex, crc) != 0) {
            char msg[256];
            snprintf(msg, sizeof msg,
                     "the data arrived damaged: %zu bytes with CRC-32 %s, but 'size' says %lld "
                     "and 'crc32' %.16s; send the file again",
                     in->len, hex, (long long)size, crc);
            sphd_inputs_free(out);
            return sphd_err_set(e, SPHD_E_BAD_REQUEST, path, "%s", msg);
        }
    }
    return 0;
}

int sphd_inputs_match(const json_t *case_json, const sphd_inputs *in, unsigned char *used,
                      sphd_err *e)
{
    sph_case_file files[SPH_CASE_FILES_MAX];
    const int n = sph_case_files(case_json, files, SPH_CASE_FILES_MAX);
    char why[512], fp[512];
    for (int k = 0; k < n && k < SPH_CASE_FILES_MAX; k++) {
        const char *name = files[k].name;
        if (sph_input_name_check(name, why, sizeof why) != 0)
            return sphd_err_set(e, SPHD_E_INVALID_CASE, files[k].path, "%s", why);
        const sphd_input *f = sphd_inputs_get(in, name);
        if (!f)
            return sphd_err_set(e, SPHD_E_BAD_REQUEST, files_path(name, fp, sizeof fp),
                                "%s names '%.128s', which 'files' lacks: send the file with the "
                                "case (sphctl does)",
                                files[k].what, name);
        if (used)
            used[f - in->f] = 1;
    }
    return 0;
}

int sphd_inputs_unused(const sphd_inputs *in, const unsigned char *used, sphd_err *e)
{
    char fp[512];
    for (int i = 0; i < in->n; i++)
        if (!used[i])
            return sphd_err_set(e, SPHD_E_BAD_REQUEST, files_path(in->f[i].name, fp, sizeof fp),
                                "the case names no file '%.128s' (no geometry item has it as "
                                "\"mesh\", nor the wavemaker as its series' \"file\"): leave "
                                "it out",
                                in->f[i].name);
    return 0;
}

/* dir/files/NAME into buf. */
static int input_path(const char *dir, const char *name, char *buf, size_t n)
{
    return snprintf(buf, n, "%s/" SPH_INPUT_DIR "/%s", dir, name) < (int)n ? 0 : -1;
}

int sphd_inputs_dir(const char *dir, char *buf, size_t n)
{
    return snprintf(buf, n, "%s/" SPH_INPUT_DIR, dir) < (int)n ? 0 : -1;
}

int sphd_inputs_write(const char *dir, const json_t *case_json, const sphd_inputs *in, sphd_err *e)
{
    sph_case_file files[SPH_CASE_FILES_MAX];
    const int n = sph_case_files(case_json, files, SPH_CASE_FILES_MAX);
    for (int k = 0; k < n && k < SPH_CASE_FILES_MAX; k++) {
        const char *name = files[k].name;
        const sphd_input *f = sphd_inputs_get(in, name);
        if (!f)
            continue;
        char path[SPHD_PATH_MAX + 256];
        if (input_path(dir, name, path, sizeof path) != 0)
            return sphd_err_set(e, SPHD_E_INTERNAL, NULL, "path too long: %s", dir);
        char *slash = strrchr(path, '/');
        *slash = '\0';
        const int made = sph_mkdirs(path, 0700);
        *slash = '/';
        if (made != 0 || sph_write_atomic(path, f->data, f->len, 0600) != 0)
            return sphd_err_set(e, SPHD_E_INTERNAL, NULL, "cannot write %s: %s", path,
                                strerror(errno));
    }
    return 0;
}

void sphd_inputs_remove(const char *dir, const json_t *case_json)
{
    sph_case_file files[SPH_CASE_FILES_MAX];
    const int n = sph_case_files(case_json, files, SPH_CASE_FILES_MAX);
    for (int k = 0; k < n && k < SPH_CASE_FILES_MAX; k++) {
        const char *name = files[k].name;
        char path[SPHD_PATH_MAX + 256];
        if (input_path(dir, name, path, sizeof path) != 0)
            continue;
        unlink(path);
        /* the directories below files/ that are empty now, then files/ itself */
        char top[SPHD_PATH_MAX + 16];
        sphd_inputs_dir(dir, top, sizeof top);
        for (char *s = strrchr(path, '/'); s && strlen(path) > strlen(top);
             s = strrchr(path, '/')) {
            *s = '\0';
            if (rmdir(path) != 0)
                break;
        }
        rmdir(top);
    }
}

int sphd_inputs_same(const char *dir, const json_t *case_json, const sphd_inputs *in)
{
    sph_case_file files[SPH_CASE_FILES_MAX];
    const int n = sph_case_files(case_json, files, SPH_CASE_FILES_MAX);
    for (int k = 0; k < n && k < SPH_CASE_FILES_MAX; k++) {
        const char *name = files[k].name;
        const sphd_input *f = sphd_inputs_get(in, name);
        char path[SPHD_PATH_MAX + 256];
        if (!f || input_path(dir, name, path, sizeof path) != 0)
            return 0;
        FILE *fp = fopen(path, "rb");
        if (!fp)
            return 0;
        unsigned char *buf = malloc(f->len + 1);
        const size_t got = buf ? fread(buf, 1, f->len + 1, fp) : 0;
        const int same = buf && got == f->len && memcmp(buf, f->data, f->len) == 0;
        free(buf);
        fclose(fp);
        if (!same)
            return 0;
    }
    return 1;
}

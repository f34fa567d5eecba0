/* The files a case names (its geometry items' "mesh", a wavemaker's series: sph_case_files),
 * read next to the case file and sent with submit and sweep as args.files (PROTOCOL.md 3.11). */
#include "sphctl.h"

#include "sph_base64.h"
#include "sph_case.h"
#include "sph_inputs.h"
#include "sph_json.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <zlib.h>

#define MAX_COMBINATIONS 10000L /* sphd's limit for a sweep */

/* Adds the names the case names (sph_case_files) to names ({NAME: [what, path]}), the first
 * field naming each. */
static void add_names(const json_t *root, json_t *names)
{
    sph_case_file f[SPH_CASE_FILES_MAX];
    const int n = sph_case_files(root, f, SPH_CASE_FILES_MAX);
    for (int k = 0; k < n && k < SPH_CASE_FILES_MAX; k++)
        if (!json_object_get(names, f[k].name))
            json_object_set_new(names, f[k].name, json_pack("[s,s]", f[k].what, f[k].path));
}

/* Applies "PATH=VALUE" strings; a failure is left for sphd to report. */
static void apply_sets(json_t *root, const json_t *sets)
{
    size_t i;
    const json_t *s;
    sph_error err;
    json_array_foreach(sets, i, s) sph_json_apply_set(root, json_string_value(s), &err);
}

/* The names every combination of vary (NULL: the case with sets only) names. */
static json_t *case_names(const json_t *root, const json_t *sets, const json_t *vary)
{
    json_t *names = json_object();
    const size_t nv = json_array_size(vary);
    size_t idx[16] = {0};
    long total = 1;
    for (size_t i = 0; i < nv && i < 16; i++)
        total *= (long)json_array_size(json_object_get(json_array_get(vary, i), "values"));
    if (nv > 16 || total > MAX_COMBINATIONS || total < 1)
        total = 1; /* sphd refuses such a sweep: the case's own names will do */
    for (long n = 0; n < total; n++) {
        json_t *c = json_deep_copy(root);
        apply_sets(c, sets);
        for (size_t i = 0; i < nv && i < 16 && total > 1; i++) {
            const json_t *v = json_object_get(json_array_get(vary, i), "values");
            const char *path = json_string_value(json_object_get(json_array_get(vary, i), "path"));
            char *val = json_dumps(json_array_get(v, idx[i]), JSON_ENCODE_ANY | JSON_COMPACT);
            size_t len = (path ? strlen(path) : 0) + (val ? strlen(val) : 0) + 2;
            char *as = malloc(len);
            sph_error err;
            if (as && path && val) {
                snprintf(as, len, "%s=%s", path, val);
                sph_json_apply_set(c, as, &err);
            }
            free(as);
            free(val);
        }
        add_names(c, names);
        json_decref(c);
        for (size_t i = nv; i-- > 0 && total > 1;) { /* the last list varies fastest */
            if (++idx[i] < json_array_size(json_object_get(json_array_get(vary, i), "values")))
                break;
            idx[i] = 0;
        }
    }
    return names;
}

/* Reads dir/name whole into *data (*len bytes). Returns 0 or -1 (errno; EFBIG over the limit). */
static int read_input(const char *path, unsigned char **data, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return -1;
    struct stat st;
    if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) {
        int e = S_ISDIR(st.st_mode) ? EISDIR : errno;
        fclose(f);
        errno = e;
        return -1;
    }
    if (st.st_size > SPH_INPUT_MAX_FILE) {
        fclose(f);
        *len = (size_t)st.st_size;
        errno = EFBIG;
        return -1;
    }
    *data = malloc(st.st_size ? (size_t)st.st_size : 1);
    *len = *data ? fread(*data, 1, (size_t)st.st_size, f) : 0;
    const int bad = !*data || ferror(f) || *len != (size_t)st.st_size;
    fclose(f);
    if (bad) {
        free(*data);
        *data = NULL;
        errno = errno ? errno : EIO;
        return -1;
    }
    return 0;
}

int sphctl_attach_files(sphctl *c, const json_t *root, const json_t *sets, const json_t *vary,
                        json_t *args)
{
    json_t *names = case_names(root, sets, vary);
    if (json_object_size(names) == 0) {
        json_decref(names);
        return 0;
    }
    char dir[4096];
    const char *slash = strrchr(c->file, '/');
    if (slash)
        snprintf(dir, sizeof dir, "%.*s", (int)(slash - c->file), c->file);
    else
        snprintf(dir, sizeof dir, ".");
    if (!dir[0])
        snprintf(dir, sizeof dir, "/");
    json_t *files = json_object();
    long total = 0;
    int rc = 0;
    const char *name;
    json_t *kj;
    json_object_foreach(names, name, kj)
    {
        const char *what = json_string_value(json_array_get(kj, 0));
        const char *at = json_string_value(json_array_get(kj, 1));
        char why[512], path[4096 + 256];
        if (json_object_size(files) >= SPH_INPUT_MAX_COUNT) {
            fprintf(stderr, "sphctl: %s: the case names more than %d files\n", c->file,
                    SPH_INPUT_MAX_COUNT);
            rc = SPHCTL_EX_DATAERR;
            break;
        }
        if (sph_input_name_check(name, why, sizeof why) != 0) {
            fprintf(stderr, "sphctl: %s: %s (%s): %s\n", c->file, what, at, why);
            rc = SPHCTL_EX_DATAERR;
            break;
        }
        snprintf(path, sizeof path, "%s/%s", dir, name);
        unsigned char *data = NULL;
        size_t len = 0;
        if (read_input(path, &data, &len) != 0) {
            if (errno == EFBIG)
                fprintf(stderr,
                        "sphctl: %s: %s names %s: %zu bytes, more than the %ld bytes a file "
                        "sent with a case may have\n",
                        c->file, what, path, len, SPH_INPUT_MAX_FILE);
            else
                fprintf(stderr, "sphctl: %s: %s names '%s': cannot read %s: %s\n", c->file, what,
                        name, path, strerror(errno));
            rc = errno == EFBIG ? SPHCTL_EX_DATAERR : SPHCTL_EX_NOINPUT;
            break;
        }
        total += (long)len;
        if (total > SPH_INPUT_MAX_TOTAL) {
            free(data);
            fprintf(stderr,
                    "sphctl: %s: the files the case names hold more than %ld bytes in all (the "
                    "limit of one request); make them smaller\n",
                    c->file, SPH_INPUT_MAX_TOTAL);
            rc = SPHCTL_EX_DATAERR;
            break;
        }
        char *b64 = malloc(sph_base64_encoded_len(len) + 1);
        if (!b64) {
            free(data);
            rc = SPHCTL_EX_SOFTWARE;
            break;
        }
        sph_base64_encode(data, len, b64);
        char crc[16];
        snprintf(crc, sizeof crc, "%08lx",
                 crc32(crc32(0L, Z_NULL, 0), data, (uInt)len) & 0xffffffffUL);
        json_object_set_new(
            files, name,
            json_pack("{s:s, s:s, s:I}", "data", b64, "crc32", crc, "size", (json_int_t)len));
        free(b64);
        free(data);
    }
    json_decref(names);
    if (rc)
        json_decref(files);
    else
        json_object_set_new(args, "files", files);
    return rc;
}

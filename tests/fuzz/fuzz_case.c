/*
 * Fuzz target: the case parser (every method: kernel_study, wcsph, mps and whatever the case
 * names). Input: the case's JSON text, then optionally NUL-separated `--set PATH=VALUE`
 * assignments applied to it first (as `sphd --run --set` and `submit`'s "set" do).
 */
#include "fuzz_util.h"

#include "sph_case.h"
#include "sph_json.h"

#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *text = (const char *)data;
    const char *nul = memchr(text, '\0', size);
    size_t json_len = nul ? (size_t)(nul - text) : size;
    json_t *root = json_loadb(text, json_len, 0, NULL);
    if (!root)
        return 0;
    sph_error err;
    int rc = 0;
    /* the assignments: NUL-terminated strings after the first NUL (the last one may lack it) */
    for (size_t off = json_len + 1; nul && off < size && rc == 0;) {
        const char *a = text + off;
        const char *end = memchr(a, '\0', size - off);
        size_t len = end ? (size_t)(end - a) : size - off;
        char buf[1024];
        if (len >= sizeof buf)
            break;
        memcpy(buf, a, len);
        buf[len] = '\0';
        rc = sph_json_apply_set(root, buf, &err);
        off += len + 1;
    }
    if (rc == 0) {
        sph_case c;
        if (sph_case_from_json(root, &c, &err) == 0)
            (void)sph_method_name(c.method);
    }
    json_decref(root);
    return 0;
}

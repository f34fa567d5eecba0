#include "sph_error.h"

#include <stdio.h>
#include <string.h>

void sph_error_clear(sph_error *err)
{
    if (!err)
        return;
    err->code = SPH_OK;
    err->path[0] = '\0';
    err->message[0] = '\0';
}

int sph_error_set(sph_error *err, sph_error_code code, const char *path, const char *fmt, ...)
{
    if (!err)
        return (int)code;
    err->code = code;
    snprintf(err->path, sizeof err->path, "%s", path ? path : "");
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->message, sizeof err->message, fmt, ap);
    va_end(ap);
    return (int)code;
}

const char *sph_error_code_name(sph_error_code code)
{
    switch (code) {
    case SPH_OK:
        return "ok";
    case SPH_ERR_INVALID:
        return "invalid_case";
    case SPH_ERR_NOMEM:
        return "too_large";
    case SPH_ERR_UNSTABLE:
        return "unstable";
    case SPH_ERR_IO:
        return "io_error";
    case SPH_ERR_INTERNAL:
        return "internal";
    }
    return "internal";
}

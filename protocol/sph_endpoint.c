#include "sph_endpoint.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int sph_runtime_dir(char *out, size_t n)
{
    const char *xdg = getenv("XDG_RUNTIME_DIR");
    int len;
    if (xdg && *xdg)
        len = snprintf(out, n, "%s/sphd", xdg);
    else
        len = snprintf(out, n, "/tmp/sphd-%ld", (long)getuid());
    return len < 0 || (size_t)len >= n ? -1 : 0;
}

static int default_endpoint(char *out, size_t n, const char *name)
{
    char dir[SPH_ENDPOINT_MAX];
    if (sph_runtime_dir(dir, sizeof dir))
        return -1;
    int len = snprintf(out, n, "ipc://%s/%s", dir, name);
    return len < 0 || (size_t)len >= n ? -1 : 0;
}

int sph_default_control_endpoint(char *out, size_t n)
{
    return default_endpoint(out, n, "control");
}

int sph_default_stream_endpoint(char *out, size_t n)
{
    return default_endpoint(out, n, "stream");
}

const char *sph_ipc_path(const char *ep)
{
    return strncmp(ep, "ipc://", 6) == 0 ? ep + 6 : NULL;
}

int sph_tcp_is_loopback(const char *ep)
{
    if (strncmp(ep, "tcp://", 6) != 0)
        return -1;
    const char *host = ep + 6;
    /* An interface-qualified "iface;host:port" binds host; look at what follows the ';'. */
    const char *semi = strchr(host, ';');
    if (semi)
        host = semi + 1;
    if (strncmp(host, "127.", 4) == 0) {
        /* 127.x.y.z, not a host name that happens to start with "127." */
        const char *p = host + 4;
        while ((*p >= '0' && *p <= '9') || *p == '.')
            p++;
        return *p == ':' ? 1 : 0;
    }
    if (strncmp(host, "localhost:", 10) == 0 || strncmp(host, "[::1]:", 6) == 0 ||
        strncmp(host, "lo:", 3) == 0)
        return 1;
    return 0;
}

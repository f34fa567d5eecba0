/*
 * sph_endpoint: the default endpoints of sphd, shared by the daemon and its clients so that on one
 * machine no flags are needed (DESIGN.md section 3).
 */
#ifndef SPH_ENDPOINT_H
#define SPH_ENDPOINT_H

#include <stddef.h>

#define SPH_ENDPOINT_MAX 512

/* The directory holding the default ipc sockets: $XDG_RUNTIME_DIR/sphd, or /tmp/sphd-$UID when
 * XDG_RUNTIME_DIR is unset or empty. Returns 0, or -1 when it does not fit in n bytes. */
int sph_runtime_dir(char *out, size_t n);

/* ipc://RUNTIME_DIR/control and ipc://RUNTIME_DIR/stream. Return 0 or -1 (too long). */
int sph_default_control_endpoint(char *out, size_t n);
int sph_default_stream_endpoint(char *out, size_t n);

/* The file-system path of an ipc:// endpoint (borrowed pointer into ep), or NULL when ep is not
 * an ipc endpoint. */
const char *sph_ipc_path(const char *ep);

/* 1 when ep is tcp:// on a loopback host (127.x.y.z, localhost, [::1]); 0 for other tcp hosts
 * (including "*" and 0.0.0.0); -1 when it is not a tcp endpoint. */
int sph_tcp_is_loopback(const char *ep);

#endif

/* Base64 (RFC 4648 section 4, with '=' padding) for file chunks on the control socket. */
#ifndef SPH_BASE64_H
#define SPH_BASE64_H

#include <stddef.h>

/* Characters sph_base64_encode writes for n bytes, without the terminating NUL. */
size_t sph_base64_encoded_len(size_t n);

/* Encodes n bytes of src into dst (room for sph_base64_encoded_len(n) + 1 chars, NUL-terminated).
 * Returns the length written. */
size_t sph_base64_encode(const void *src, size_t n, char *dst);

/* Decodes len characters of src (padded, no whitespace) into dst (room for 3 * len / 4 bytes).
 * Returns the number of bytes decoded, or -1 if src is not valid base64. */
long sph_base64_decode(const char *src, size_t len, void *dst);

#endif

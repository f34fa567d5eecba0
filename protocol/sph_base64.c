#include "sph_base64.h"

static const char alphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

size_t sph_base64_encoded_len(size_t n)
{
    return (n + 2) / 3 * 4;
}

size_t sph_base64_encode(const void *src, size_t n, char *dst)
{
    const unsigned char *s = src;
    char *o = dst;
    size_t i = 0;
    for (; i + 3 <= n; i += 3) {
        unsigned long v = (unsigned long)s[i] << 16 | (unsigned long)s[i + 1] << 8 | s[i + 2];
        *o++ = alphabet[v >> 18 & 63];
        *o++ = alphabet[v >> 12 & 63];
        *o++ = alphabet[v >> 6 & 63];
        *o++ = alphabet[v & 63];
    }
    if (i < n) {
        unsigned long v = (unsigned long)s[i] << 16;
        if (i + 1 < n)
            v |= (unsigned long)s[i + 1] << 8;
        *o++ = alphabet[v >> 18 & 63];
        *o++ = alphabet[v >> 12 & 63];
        *o++ = i + 1 < n ? alphabet[v >> 6 & 63] : '=';
        *o++ = '=';
    }
    *o = '\0';
    return (size_t)(o - dst);
}

static int value_of(char c)
{
    if (c >= 'A' && c <= 'Z')
        return c - 'A';
    if (c >= 'a' && c <= 'z')
        return c - 'a' + 26;
    if (c >= '0' && c <= '9')
        return c - '0' + 52;
    if (c == '+')
        return 62;
    if (c == '/')
        return 63;
    return -1;
}

long sph_base64_decode(const char *src, size_t len, void *dst)
{
    unsigned char *o = dst;
    if (len % 4 != 0)
        return -1;
    for (size_t i = 0; i < len; i += 4) {
        const int last = i + 4 == len;
        int pad = 0;
        if (last && src[i + 3] == '=')
            pad = src[i + 2] == '=' ? 2 : 1;
        unsigned long v = 0;
        for (int k = 0; k < 4; k++) {
            int x = k >= 4 - pad ? 0 : value_of(src[i + k]);
            if (x < 0)
                return -1;
            v = v << 6 | (unsigned long)x;
        }
        *o++ = (unsigned char)(v >> 16);
        if (pad < 2)
            *o++ = (unsigned char)(v >> 8 & 0xff);
        if (pad < 1)
            *o++ = (unsigned char)(v & 0xff);
    }
    return (long)(o - (unsigned char *)dst);
}

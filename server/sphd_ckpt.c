#include "sphd_ckpt.h"
#include "sphd_ckpt_format.h"

#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <zlib.h>

/*
 * Layout (little-endian as written by this machine; a checkpoint is not a portable format):
 *   header:  magic "SPHCKPT1" | u32 nsections | u32 reserved | u64 body bytes | u32 crc(header)
 *   section: char name[32] | u64 size | u32 crc(data) | u32 reserved | data, padded to 8 bytes
 *   trailer: "SPHCKEND" | u32 crc(all bytes before the trailer) | u32 the same, inverted
 */
#define MAGIC     "SPHCKPT1"
#define END_MAGIC "SPHCKEND"

struct sphd_ckpt {
    unsigned char *bytes; /* the whole file */
    size_t size;
    int nsections;
    const ckpt_section_header **headers;
};

static size_t pad8(size_t n)
{
    return (n + 7) & ~(size_t)7;
}

static uint32_t crc(uint32_t c, const void *p, size_t n)
{
    const unsigned char *b = p;
    while (n > 0) { /* zlib takes uInt lengths */
        uInt chunk = n > (1u << 30) ? (1u << 30) : (uInt)n;
        c = (uint32_t)crc32(c, b, chunk);
        b += chunk;
        n -= chunk;
    }
    return c;
}

static int write_all(int fd, const void *p, size_t n, uint32_t *running)
{
    const char *c = p;
    *running = crc(*running, p, n);
    while (n > 0) {
        ssize_t w = write(fd, c, n);
        if (w < 0) {
            if (errno == EINTR)
                continue;
            return -1;
        }
        c += w;
        n -= (size_t)w;
    }
    return 0;
}

int sphd_ckpt_write(const char *dir, const sphd_ckpt_section *s, int n, sph_error *err)
{
    char path[4096], prev[4096], tmp[4096];
    snprintf(path, sizeof path, "%s/checkpoint", dir);
    snprintf(prev, sizeof prev, "%s/checkpoint.prev", dir);
    snprintf(tmp, sizeof tmp, "%s/checkpoint.tmp.%ld", dir, (long)getpid());
    ckpt_header h = {.magic = MAGIC, .nsections = (uint32_t)n};
    for (int i = 0; i < n; i++) {
        if (strlen(s[i].name) >= SPHD_CKPT_NAME_MAX)
            return sph_error_set(err, SPH_ERR_INTERNAL, "", "checkpoint section name too long");
        h.body += sizeof(ckpt_section_header) + pad8(s[i].size);
    }
    h.crc = crc(0, &h, offsetof(ckpt_header, crc));

    int fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    if (fd < 0)
        return sph_error_set(err, SPH_ERR_IO, "", "cannot create checkpoint '%s': %s", tmp,
                             strerror(errno));
    uint32_t running = 0;
    static const char zeros[8] = {0};
    int rc = write_all(fd, &h, sizeof h, &running);
    /* fault injection for the crash tests: a window in which the checkpoint is half written */
    const char *delay = getenv("SPHD_FAULT_CKPT_DELAY_MS");
    if (delay && rc == 0) {
        long ms = atol(delay);
        struct timespec ts = {ms / 1000, (ms % 1000) * 1000000L};
        nanosleep(&ts, NULL);
    }
    for (int i = 0; rc == 0 && i < n; i++) {
        ckpt_section_header sh = {.size = s[i].size, .crc = crc(0, s[i].data, s[i].size)};
        snprintf(sh.name, sizeof sh.name, "%s", s[i].name);
        rc = write_all(fd, &sh, sizeof sh, &running);
        if (rc == 0)
            rc = write_all(fd, s[i].data, s[i].size, &running);
        if (rc == 0)
            rc = write_all(fd, zeros, pad8(s[i].size) - s[i].size, &running);
    }
    ckpt_trailer t = {.magic = END_MAGIC, .crc = running, .crc_inverted = ~running};
    uint32_t ignored = 0;
    if (rc == 0)
        rc = write_all(fd, &t, sizeof t, &ignored);
    if (rc == 0)
        rc = fsync(fd);
    int saved = errno;
    if (close(fd) != 0 && rc == 0) {
        rc = -1;
        saved = errno;
    }
    if (rc != 0) {
        unlink(tmp);
        return sph_error_set(err, SPH_ERR_IO, "", "writing checkpoint '%s' failed: %s", tmp,
                             strerror(saved));
    }
    /* the new one is complete: the latest becomes the previous, the new one the latest */
    if (access(path, F_OK) == 0 && rename(path, prev) != 0) {
        saved = errno;
        unlink(tmp);
        return sph_error_set(err, SPH_ERR_IO, "", "rotating checkpoint in '%s' failed: %s", dir,
                             strerror(saved));
    }
    if (rename(tmp, path) != 0) {
        saved = errno;
        unlink(tmp);
        return sph_error_set(err, SPH_ERR_IO, "", "saving checkpoint '%s' failed: %s", path,
                             strerror(saved));
    }
    int dfd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd >= 0) {
        fsync(dfd);
        close(dfd);
    }
    return 0;
}

static unsigned char *read_file(const char *path, size_t *size, sph_error *err)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        sph_error_set(err, SPH_ERR_IO, "", "cannot open checkpoint '%s': %s", path,
                      strerror(errno));
        return NULL;
    }
    unsigned char *buf = NULL;
    size_t len = 0, cap = 0;
    for (;;) {
        if (len == cap) {
            cap = cap ? 2 * cap : 1 << 20;
            unsigned char *nb = realloc(buf, cap);
            if (!nb) {
                free(buf);
                fclose(f);
                sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory reading '%s'", path);
                return NULL;
            }
            buf = nb;
        }
        size_t r = fread(buf + len, 1, cap - len, f);
        len += r;
        if (r == 0)
            break;
    }
    int bad = ferror(f);
    fclose(f);
    if (bad) {
        free(buf);
        sph_error_set(err, SPH_ERR_IO, "", "reading checkpoint '%s' failed", path);
        return NULL;
    }
    *size = len;
    return buf;
}

sphd_ckpt *sphd_ckpt_load_file(const char *path, sph_error *err)
{
    size_t size = 0;
    unsigned char *b = read_file(path, &size, err);
    if (!b)
        return NULL;
    const char *why = NULL;
    ckpt_header h;
    ckpt_trailer t;
    if (size < sizeof h + sizeof t) {
        why = "truncated";
    } else {
        memcpy(&h, b, sizeof h);
        memcpy(&t, b + size - sizeof t, sizeof t);
        if (memcmp(h.magic, MAGIC, 8) != 0)
            why = "not a checkpoint (bad magic)";
        else if (h.crc != crc(0, &h, offsetof(ckpt_header, crc)))
            why = "header checksum mismatch";
        else if (sizeof h + h.body + sizeof t != size)
            why = "truncated or extended (size mismatch)";
        else if (h.nsections > h.body / sizeof(ckpt_section_header))
            why = "more sections than the file holds"; /* before they are allocated */
        else if (memcmp(t.magic, END_MAGIC, 8) != 0 || t.crc_inverted != ~t.crc)
            why = "missing end marker";
        else if (t.crc != crc(0, b, size - sizeof t))
            why = "file checksum mismatch";
    }
    sphd_ckpt *c = NULL;
    if (!why) {
        c = calloc(1, sizeof *c);
        c->headers = c ? calloc(h.nsections ? h.nsections : 1, sizeof *c->headers) : NULL;
        if (!c || !c->headers) {
            free(c);
            free(b);
            sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory");
            return NULL;
        }
        size_t off = sizeof h;
        for (uint32_t i = 0; i < h.nsections && !why; i++) {
            const ckpt_section_header *sh = (const ckpt_section_header *)(b + off);
            if (off + sizeof *sh > size - sizeof t || sh->size > size - sizeof t - off - sizeof *sh)
                why = "section runs past the end";
            else if (sh->crc != crc(0, b + off + sizeof *sh, sh->size))
                why = "section checksum mismatch";
            else if (memchr(sh->name, '\0', sizeof sh->name) == NULL)
                why = "bad section name";
            c->headers[i] = sh;
            off += sizeof *sh + pad8(sh->size);
        }
        c->nsections = (int)h.nsections;
    }
    if (why) {
        if (c)
            free(c->headers);
        free(c);
        free(b);
        sph_error_set(err, SPH_ERR_IO, "", "checkpoint '%s' is corrupt: %s", path, why);
        return NULL;
    }
    c->bytes = b;
    c->size = size;
    return c;
}

sphd_ckpt *sphd_ckpt_load(const char *dir, int *fell_back, sph_error *err)
{
    char path[4096], prev[4096];
    snprintf(path, sizeof path, "%s/checkpoint", dir);
    snprintf(prev, sizeof prev, "%s/checkpoint.prev", dir);
    if (fell_back)
        *fell_back = 0;
    sph_error first;
    sphd_ckpt *c = sphd_ckpt_load_file(path, &first);
    if (c)
        return c;
    sph_error second;
    c = sphd_ckpt_load_file(prev, &second);
    if (c) {
        if (fell_back)
            *fell_back = 1;
        sph_error_set(err, SPH_OK, "", "%s; using the previous checkpoint", first.message);
        return c;
    }
    sph_error_set(err, SPH_ERR_IO, "", "no valid checkpoint in '%s': %s; %s", dir, first.message,
                  second.message);
    return NULL;
}

int sphd_ckpt_set_aside(const char *dir)
{
    static const char *const names[] = {"checkpoint", "checkpoint.prev"};
    int kept = 0;
    for (int k = 0; k < 2; k++) {
        char from[4096], to[4200];
        snprintf(from, sizeof from, "%s/%s", dir, names[k]);
        snprintf(to, sizeof to, "%s.unreadable", from);
        kept += rename(from, to) == 0;
    }
    return kept;
}

const void *sphd_ckpt_get(const sphd_ckpt *c, const char *name, size_t *size)
{
    for (int i = 0; i < c->nsections; i++)
        if (strcmp(c->headers[i]->name, name) == 0) {
            if (size)
                *size = c->headers[i]->size;
            return (const unsigned char *)c->headers[i] + sizeof(ckpt_section_header);
        }
    return NULL;
}

void sphd_ckpt_free(sphd_ckpt *c)
{
    if (!c)
        return;
    free(c->headers);
    free(c->bytes);
    free(c);
}

/*
 * Fuzz target: the server's checkpoint reader, as a job resumes: the checkpoint file
 * (sphd_ckpt_load: header, sections, checksums, end marker), its "exec" and "sim" sections and
 * the outputs' state (sphd_exec_resume), for a small fixed case.
 *
 * Input: one byte of flags, then the file. A fuzzer cannot forge CRC-32s, so the flags ask the
 * harness to make some of them right, to get past them to what follows: bit 0 the sections'
 * checksums, bit 1 the header's (and its body size), bit 2 the trailer's. With no flag set the
 * file is taken as it is.
 */
#include "fuzz_ckpt_case.h"
#include "fuzz_util.h"

#include "sph_case.h"
#include "sphd_exec.h"

#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#define HEADER_SIZE  32 /* magic[8] u32 nsections u32 reserved u64 body u32 crc u32 pad */
#define SECTION_SIZE 48 /* name[32] u64 size u32 crc u32 reserved */
#define TRAILER_SIZE 16 /* magic[8] u32 crc u32 ~crc */

static uint32_t crc(const unsigned char *p, size_t n)
{
    return (uint32_t)crc32(0L, p, (uInt)n);
}

static void fix_sections(unsigned char *b, size_t size)
{
    uint32_t nsections;
    memcpy(&nsections, b + 8, 4);
    size_t off = HEADER_SIZE;
    for (uint32_t i = 0; i < nsections && off + SECTION_SIZE <= size - TRAILER_SIZE; i++) {
        uint64_t len;
        memcpy(&len, b + off + 32, 8);
        if (len > size - TRAILER_SIZE - off - SECTION_SIZE)
            return;
        uint32_t c = crc(b + off + SECTION_SIZE, (size_t)len);
        memcpy(b + off + 40, &c, 4);
        off += SECTION_SIZE + (((size_t)len + 7) & ~(size_t)7);
    }
}

static void fix_header(unsigned char *b, size_t size)
{
    uint64_t body = size - HEADER_SIZE - TRAILER_SIZE;
    memcpy(b + 16, &body, 8);
    uint32_t c = crc(b, 24);
    memcpy(b + 24, &c, 4);
}

static void fix_trailer(unsigned char *b, size_t size)
{
    uint32_t c = crc(b, size - TRAILER_SIZE), inv = ~c;
    memcpy(b + size - TRAILER_SIZE + 8, &c, 4);
    memcpy(b + size - TRAILER_SIZE + 12, &inv, 4);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static sph_case c;
    static int have_case;
    if (!have_case) {
        json_t *root = json_loads(fuzz_ckpt_case_text, 0, NULL);
        sph_error err;
        if (!root || sph_case_from_json(root, &c, &err) != 0)
            abort();
        json_decref(root);
        have_case = 1;
    }
    if (size < 1)
        return 0;
    const unsigned flags = data[0];
    size_t len = size - 1;
    unsigned char *b = malloc(len ? len : 1);
    if (!b)
        return 0;
    memcpy(b, data + 1, len);
    if (len >= HEADER_SIZE + TRAILER_SIZE) {
        if (flags & 1)
            fix_sections(b, len);
        if (flags & 2)
            fix_header(b, len);
        if (flags & 4)
            fix_trailer(b, len);
    }
    const char *dir = sph_fuzz_dir();
    if (sph_fuzz_write(dir, "checkpoint", b, len) == 0) {
        int fell_back = 0;
        sph_error err;
        sphd_exec *x = sphd_exec_resume(&c, dir, &fell_back, &err);
        sphd_exec_free(x);
    }
    free(b);
    sph_fuzz_empty(dir);
    return 0;
}

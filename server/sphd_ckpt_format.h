/*
 * sphd_ckpt_format: the on-disk layout of a checkpoint file (sphd_ckpt.c writes and reads it; the
 * fuzz seed tool tests/fuzz/make_seeds.c forges files with it). See sphd_ckpt.c for the format.
 */
#ifndef SPHD_CKPT_FORMAT_H
#define SPHD_CKPT_FORMAT_H

#include "sphd_ckpt.h"

#include <stdint.h>

typedef struct {
    char magic[8];
    uint32_t nsections;
    uint32_t reserved;
    uint64_t body;
    uint32_t crc;
    uint32_t pad;
} ckpt_header;

typedef struct {
    char name[SPHD_CKPT_NAME_MAX];
    uint64_t size;
    uint32_t crc;
    uint32_t reserved;
} ckpt_section_header;

typedef struct {
    char magic[8];
    uint32_t crc;
    uint32_t crc_inverted;
} ckpt_trailer;

#endif

/*
 * sphd_web: the dashboard's files (web/), built into sphd by cmake/embed_web.cmake.
 */
#ifndef SPHD_WEB_H
#define SPHD_WEB_H

#include <stddef.h>

typedef struct sphd_web_file {
    const char *path; /* "/index.html", "/vendor/uPlot.iife.min.js", ... */
    const unsigned char *data;
    size_t len;
} sphd_web_file;

/* The files, ended by one whose path is NULL. */
extern const sphd_web_file sphd_web_files[];

#endif

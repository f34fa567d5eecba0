/* Test helper: appends ROWS rows to a diagnostics file, one every MS milliseconds, so that a
 * reader can check it sees the series grow while the writer holds the file open (SWMR).
 * Usage: diag_writer FILE ROWS MS */
#include "sphd_h5.h"

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

int main(int argc, char **argv)
{
    if (argc != 4) {
        fprintf(stderr, "usage: diag_writer FILE ROWS MS\n");
        return 64;
    }
    const long rows = atol(argv[2]), ms = atol(argv[3]);
    const sphd_diag_column cols[] = {{"t", "s", 0}, {"ekin", "J/m", 0}, {"lost", "1", 1}};
    sph_error err;
    sphd_diagfile *d = sphd_diagfile_open(argv[1], cols, 3, -1, &err);
    if (!d) {
        fprintf(stderr, "diag_writer: %s\n", err.message);
        return 1;
    }
    for (long i = 0; i < rows; i++) {
        double v[3] = {0.001 * (double)i, 0.5 * (double)i, (double)(i / 10)};
        if (sphd_diagfile_append(d, i, v, &err)) {
            fprintf(stderr, "diag_writer: %s\n", err.message);
            sphd_diagfile_close(d);
            return 1;
        }
        struct timespec ts = {ms / 1000, (ms % 1000) * 1000000L};
        nanosleep(&ts, NULL);
    }
    sphd_diagfile_close(d);
    return 0;
}

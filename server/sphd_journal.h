/*
 * sphd_journal: a job's journal, `JOBDIR/journal.jsonl`: one JSON object per line, appended and
 * fsync'd before the caller acknowledges what it records, never rewritten. Replaying it gives the
 * job's history; a torn last line (a crash mid-append) is skipped, and reported.
 */
#ifndef SPHD_JOURNAL_H
#define SPHD_JOURNAL_H

#include "sph_error.h"

#include <jansson.h>

/* Appends record (borrowed) as one line and fsyncs. Returns 0 or SPH_ERR_IO. */
int sphd_journal_append(const char *jobdir, const json_t *record, sph_error *err);

/* The same without the fsync: in the file (the kernel's page cache) when it returns, so a killed
 * sphd (kill -9) finds it, but a power cut may lose it. For records written too often to wait
 * for the disk each time (an event's seq). */
int sphd_journal_note(const char *jobdir, const json_t *record, sph_error *err);

/* Calls cb(ud, record) for every complete record in order (record borrowed for the call).
 * *torn (may be NULL) is set to 1 when a partial last line was skipped. Returns 0, or SPH_ERR_IO
 * if the journal cannot be read (a missing journal is an error too). */
int sphd_journal_replay(const char *jobdir, void (*cb)(void *ud, const json_t *record), void *ud,
                        int *torn, sph_error *err);

#endif

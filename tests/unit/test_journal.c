/* Job journal: records (appended or noted) come back in order; a torn last line (crash mid-append)
 * is skipped and reported; appends after it still replay; a missing journal is an io_error. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "sphd_journal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int seen[100], nseen;

static void collect(void *ud, const json_t *rec)
{
    (void)ud;
    seen[nseen++] = (int)json_integer_value(json_object_get(rec, "n"));
}

static void test_journal(void **state)
{
    (void)state;
    char dir[] = "/tmp/sphd-test-journal-XXXXXX";
    assert_non_null(mkdtemp(dir));
    sph_error err;
    for (int i = 0; i < 5; i++) {
        json_t *r = json_pack("{s:s, s:i}", "event", "state", "n", i);
        assert_int_equal(sphd_journal_append(dir, r, &err), 0);
        json_decref(r);
    }
    int torn;
    nseen = 0;
    assert_int_equal(sphd_journal_replay(dir, collect, NULL, &torn, &err), 0);
    assert_int_equal(nseen, 5);
    assert_int_equal(torn, 0);
    for (int i = 0; i < 5; i++)
        assert_int_equal(seen[i], i);

    /* a crash mid-append leaves a partial line */
    char path[128];
    snprintf(path, sizeof path, "%s/journal.jsonl", dir);
    FILE *f = fopen(path, "a");
    fputs("{\"event\": \"sta", f);
    fclose(f);
    nseen = 0;
    assert_int_equal(sphd_journal_replay(dir, collect, NULL, &torn, &err), 0);
    assert_int_equal(nseen, 5);
    assert_int_equal(torn, 1);

    /* the next append starts a new line after the torn one: the record is not lost */
    json_t *r = json_pack("{s:s, s:i}", "event", "state", "n", 5);
    assert_int_equal(sphd_journal_append(dir, r, &err), 0);
    json_decref(r);
    nseen = 0;
    assert_int_equal(sphd_journal_replay(dir, collect, NULL, &torn, &err), 0);
    assert_int_equal(nseen, 6);
    assert_int_equal(seen[5], 5);

    /* a note (no fsync: an event's seq) is a record like the others, in order */
    r = json_pack("{s:s, s:i}", "event", "seq", "n", 6);
    assert_int_equal(sphd_journal_note(dir, r, &err), 0);
    json_decref(r);
    nseen = 0;
    assert_int_equal(sphd_journal_replay(dir, collect, NULL, &torn, &err), 0);
    assert_int_equal(nseen, 7);
    assert_int_equal(seen[6], 6);

    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    assert_int_equal(system(cmd), 0);
    assert_int_equal(sphd_journal_replay(dir, collect, NULL, &torn, &err), SPH_ERR_IO);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_journal)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}

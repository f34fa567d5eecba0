/*
 * The command table and the dispatcher, without sockets' clients: requests go straight into
 * sphd_dispatch() of a daemon that has a PUB socket but no workers (jobs stay queued), and the
 * replies are checked for their error code and path. Data-driven, like the invalid cases.
 */
#include "sphd.h"
#include "sphd_daemon.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zmq.h>

#include <cmocka.h>

typedef struct fixture {
    sphd_daemon d;
    char tmp[256];
} fixture;

static int setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    snprintf(f->tmp, sizeof f->tmp, "/tmp/sphd-test-XXXXXX");
    assert_non_null(mkdtemp(f->tmp));
    snprintf(f->d.opts.state_dir, sizeof f->d.opts.state_dir, "%s", f->tmp);
    snprintf(f->d.opts.publish, sizeof f->d.opts.publish, "inproc://stream");
    f->d.opts.threads = 1;
    f->d.opts.max_jobs = 3;
    f->d.opts.max_msg_size = 1 << 20;
    f->d.ctx = zmq_ctx_new();
    f->d.pub = zmq_socket(f->d.ctx, ZMQ_PUB);
    assert_int_equal(zmq_bind(f->d.pub, "inproc://stream"), 0);
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    sphd_jobs_free(&f->d);
    int zero = 0;
    zmq_setsockopt(f->d.pub, ZMQ_LINGER, &zero, sizeof zero);
    zmq_close(f->d.pub);
    zmq_ctx_term(f->d.ctx);
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", f->tmp);
    assert_int_equal(system(cmd), 0);
    free(f);
    return 0;
}

/* Dispatches text; returns the reply (new ref). */
static json_t *call(fixture *f, const char *text)
{
    sphd_pending from = {.nframes = 0, .op = "?"};
    char *reply = sphd_dispatch(&f->d, &from, text, strlen(text));
    assert_non_null(reply);
    json_t *r = json_loads(reply, 0, NULL);
    free(reply);
    assert_non_null(r);
    return r;
}

static void expect_error(fixture *f, const char *text, const char *code, const char *path)
{
    json_t *r = call(f, text);
    json_t *e = json_object_get(r, "error");
    const char *got_path = json_string_value(json_object_get(e, "path"));
    if (!json_is_false(json_object_get(r, "ok")) ||
        strcmp(json_string_value(json_object_get(e, "code")), code) != 0 ||
        (path && strcmp(got_path ? got_path : "", path) != 0)) {
        char *s = json_dumps(r, 0);
        fail_msg("%s\n  want %s at %s\n  got %s", text, code, path ? path : "(any)", s);
    }
    assert_non_null(json_string_value(json_object_get(e, "message")));
    json_decref(r);
}

static json_t *expect_ok(fixture *f, const char *text)
{
    json_t *r = call(f, text);
    if (!json_is_true(json_object_get(r, "ok"))) {
        char *s = json_dumps(r, 0);
        fail_msg("%s\n  got %s", text, s);
    }
    json_t *res = json_incref(json_object_get(r, "result"));
    json_decref(r);
    return res;
}

#define KS                                                                                         \
    "{\"name\":\"ks\",\"method\":\"kernel_study\",\"domain\":{\"min\":[0],\"max\":[6]},"           \
    "\"particles\":101,\"kernels\":[{\"type\":\"cubic_spline\"}]}"

static void test_envelope_errors(void **state)
{
    fixture *f = *state;
    static const struct {
        const char *text, *code, *path;
    } cases[] = {
        {"", "bad_request", NULL},
        {"nope", "bad_request", NULL},
        {"[]", "bad_request", ""},
        {"{\"v\":1}", "bad_request", "/op"},
        {"{\"op\":7}", "bad_request", "/op"},
        {"{\"op\":\"x\"}", "unknown_op", "/op"},
        {"{\"v\":3,\"op\":\"ping\"}", "bad_request", "/v"},
        {"{\"v\":1.5,\"op\":\"ping\"}", "bad_request", "/v"},
        {"{\"op\":\"ping\",\"zz\":1}", "bad_request", "/zz"},
        {"{\"op\":\"ping\",\"id\":{}}", "bad_request", "/id"},
        {"{\"op\":\"ping\",\"args\":3}", "bad_request", "/args"},
        {"{\"op\":\"ping\",\"args\":{\"a\":1}}", "bad_request", "/args/a"},
        {"{\"op\":\"submit\"}", "bad_request", "/args/case"},
        {"{\"op\":\"submit\",\"args\":{\"case\":[]}}", "bad_request", "/args/case"},
        {"{\"op\":\"submit\",\"args\":{\"case\":" KS ",\"start\":1}}", "bad_request",
         "/args/start"},
        {"{\"op\":\"submit\",\"args\":{\"case\":" KS ",\"job\":\"a b\"}}", "bad_request",
         "/args/job"},
        {"{\"op\":\"submit\",\"args\":{\"case\":" KS ",\"set\":[\"particles=1\"]}}", "invalid_case",
         "/particles"},
        {"{\"op\":\"submit\",\"args\":{\"case\":{\"method\":\"nope\"}}}", "invalid_case",
         "/method"},
        {"{\"op\":\"query\",\"args\":{\"job\":\"none\"}}", "not_found", "/args/job"},
        {"{\"op\":\"step\",\"args\":{\"job\":\"none\",\"n\":\"1\"}}", "bad_request", "/args/n"},
        {"{\"op\":\"step\",\"args\":{\"job\":\"none\",\"n\":1}}", "not_found", "/args/job"},
        {"{\"op\":\"results\",\"args\":{\"job\":\"none\"}}", "not_found", "/args/job"},
        {"{\"op\":\"results\",\"args\":{\"job\":\"none\",\"checksums\":1}}", "bad_request",
         "/args/checksums"},
        {"{\"op\":\"fetch\",\"args\":{\"job\":\"none\"}}", "bad_request", "/args/file"},
        {"{\"op\":\"fetch\",\"args\":{\"job\":\"none\",\"file\":\"a\",\"offset\":1.5}}",
         "bad_request", "/args/offset"},
        {"{\"op\":\"fetch\",\"args\":{\"job\":\"none\",\"file\":\"a\"}}", "not_found", "/args/job"},
        {"{\"op\":\"export\",\"args\":{\"job\":\"none\",\"format\":1}}", "bad_request",
         "/args/format"},
        {"{\"op\":\"export\",\"args\":{\"job\":\"none\"}}", "not_found", "/args/job"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
        expect_error(f, cases[i].text, cases[i].code, cases[i].path);
    assert_int_equal(f->d.requests, (long)(sizeof cases / sizeof cases[0]));
    assert_int_equal(f->d.errors, f->d.requests);
}

static void test_reply_echoes_id(void **state)
{
    fixture *f = *state;
    const char *text = "{\"v\":1,\"id\":\"abc\",\"op\":\"ping\"}";
    json_t *r = call(f, text);
    assert_string_equal(json_string_value(json_object_get(r, "id")), "abc");
    assert_true(json_is_true(json_object_get(json_object_get(r, "result"), "pong")));
    json_decref(r);
    text = "{\"id\":5,\"op\":\"nope\"}";
    r = call(f, text);
    assert_int_equal(json_integer_value(json_object_get(r, "id")), 5);
    json_decref(r);
}

static void test_hello_lists_the_table(void **state)
{
    fixture *f = *state;
    json_t *h = expect_ok(f, "{\"op\":\"hello\"}");
    json_t *ops = json_object_get(h, "ops");
    size_t n = 0;
    for (; sphd_op_name(n); n++)
        assert_string_equal(json_string_value(json_array_get(ops, n)), sphd_op_name(n));
    assert_int_equal(n, 16);
    assert_int_equal(json_array_size(ops), n);
    assert_string_equal(json_string_value(json_object_get(h, "stream")), "inproc://stream");
    json_decref(h);
}

static void test_job_states_without_workers(void **state)
{
    fixture *f = *state;
    json_t *r = expect_ok(f, "{\"op\":\"submit\",\"args\":{\"case\":" KS ",\"job\":\"a\"}}");
    assert_string_equal(json_string_value(json_object_get(r, "state")), "queued");
    assert_true(json_is_true(json_object_get(r, "created")));
    json_decref(r);
    /* idempotent, then conflict */
    r = expect_ok(f, "{\"op\":\"submit\",\"args\":{\"case\":" KS ",\"job\":\"a\"}}");
    assert_true(json_is_false(json_object_get(r, "created")));
    json_decref(r);
    expect_error(f,
                 "{\"op\":\"submit\",\"args\":{\"case\":" KS
                 ",\"job\":\"a\",\"set\":[\"particles=51\"]}}",
                 "conflict", "/args/case");
    /* queued -> paused -> step pending -> stopped */
    r = expect_ok(f, "{\"op\":\"pause\",\"args\":{\"job\":\"a\"}}");
    assert_string_equal(json_string_value(json_object_get(r, "state")), "paused");
    json_decref(r);
    expect_error(f, "{\"op\":\"start\",\"args\":{\"job\":\"a\"}}", "bad_state", "/args/job");
    r = expect_ok(f, "{\"op\":\"step\",\"args\":{\"job\":\"a\",\"until\":0.5}}");
    assert_non_null(json_object_get(r, "pending_step"));
    json_decref(r);
    expect_error(f, "{\"op\":\"step\",\"args\":{\"job\":\"a\",\"n\":1,\"until\":1}}", "bad_request",
                 "/args");
    r = expect_ok(f, "{\"op\":\"stop\",\"args\":{\"job\":\"a\"}}");
    assert_string_equal(json_string_value(json_object_get(r, "state")), "stopped");
    json_decref(r);
    expect_error(f, "{\"op\":\"resume\",\"args\":{\"job\":\"a\"}}", "bad_state", "/args/job");
    expect_error(f, "{\"op\":\"step\",\"args\":{\"job\":\"a\",\"n\":1}}", "bad_state", "/args/job");
    /* --max-jobs 3: the stopped job does not count */
    for (int i = 0; i < 3; i++)
        json_decref(expect_ok(f, "{\"op\":\"submit\",\"args\":{\"case\":" KS ",\"start\":false}}"));
    expect_error(f, "{\"op\":\"submit\",\"args\":{\"case\":" KS "}}", "busy", NULL);
    r = expect_ok(f, "{\"op\":\"list\"}");
    assert_int_equal(json_array_size(json_object_get(r, "jobs")), 4);
    json_decref(r);
    /* the case was written for each job */
    char path[512];
    snprintf(path, sizeof path, "%s/jobs/a/case.json", f->tmp);
    assert_int_equal(access(path, R_OK), 0);
}

static void test_job_ids(void **state)
{
    (void)state;
    assert_true(sphd_job_id_ok("dambreak-1"));
    assert_true(sphd_job_id_ok("a.b_c-D9"));
    assert_false(sphd_job_id_ok(""));
    assert_false(sphd_job_id_ok(".hidden"));
    assert_false(sphd_job_id_ok(".."));
    assert_false(sphd_job_id_ok("a/b"));
    assert_false(sphd_job_id_ok("a b"));
    assert_false(sphd_job_id_ok("caf\xc3\xa9"));
    char longid[80];
    memset(longid, 'x', sizeof longid);
    longid[63] = '\0';
    assert_true(sphd_job_id_ok(longid));
    longid[63] = 'x';
    longid[64] = '\0';
    assert_false(sphd_job_id_ok(longid));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_envelope_errors, setup, teardown),
        cmocka_unit_test_setup_teardown(test_reply_echoes_id, setup, teardown),
        cmocka_unit_test_setup_teardown(test_hello_lists_the_table, setup, teardown),
        cmocka_unit_test_setup_teardown(test_job_states_without_workers, setup, teardown),
        cmocka_unit_test_setup_teardown(test_job_ids, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

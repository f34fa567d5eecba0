/* Default endpoints and the endpoint checks shared by sphd and sphctl. */
#include "sph_endpoint.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

static void test_runtime_dir(void **state)
{
    (void)state;
    char buf[SPH_ENDPOINT_MAX], want[SPH_ENDPOINT_MAX];
    setenv("XDG_RUNTIME_DIR", "/run/user/1234", 1);
    assert_int_equal(sph_default_control_endpoint(buf, sizeof buf), 0);
    assert_string_equal(buf, "ipc:///run/user/1234/sphd/control");
    assert_int_equal(sph_default_stream_endpoint(buf, sizeof buf), 0);
    assert_string_equal(buf, "ipc:///run/user/1234/sphd/stream");
    unsetenv("XDG_RUNTIME_DIR");
    assert_int_equal(sph_runtime_dir(buf, sizeof buf), 0);
    snprintf(want, sizeof want, "/tmp/sphd-%ld", (long)getuid());
    assert_string_equal(buf, want);
    setenv("XDG_RUNTIME_DIR", "", 1); /* empty counts as unset */
    assert_int_equal(sph_runtime_dir(buf, sizeof buf), 0);
    assert_string_equal(buf, want);
    assert_int_equal(sph_runtime_dir(buf, 4), -1); /* does not fit */
}

static void test_ipc_path(void **state)
{
    (void)state;
    assert_string_equal(sph_ipc_path("ipc:///tmp/x/control"), "/tmp/x/control");
    assert_null(sph_ipc_path("tcp://127.0.0.1:5555"));
}

static void test_loopback(void **state)
{
    (void)state;
    assert_int_equal(sph_tcp_is_loopback("tcp://127.0.0.1:5555"), 1);
    assert_int_equal(sph_tcp_is_loopback("tcp://127.1.2.3:5555"), 1);
    assert_int_equal(sph_tcp_is_loopback("tcp://localhost:5555"), 1);
    assert_int_equal(sph_tcp_is_loopback("tcp://[::1]:5555"), 1);
    assert_int_equal(sph_tcp_is_loopback("tcp://lo:5555"), 1);
    assert_int_equal(sph_tcp_is_loopback("tcp://*:5555"), 0);
    assert_int_equal(sph_tcp_is_loopback("tcp://0.0.0.0:5555"), 0);
    assert_int_equal(sph_tcp_is_loopback("tcp://192.168.1.2:5555"), 0);
    assert_int_equal(sph_tcp_is_loopback("tcp://eth0;10.0.0.1:5555"), 0);
    assert_int_equal(sph_tcp_is_loopback("tcp://localhost.evil.org:5555"), 0);
    assert_int_equal(sph_tcp_is_loopback("tcp://127.example.org:5555"), 0);
    assert_int_equal(sph_tcp_is_loopback("ipc:///tmp/x"), -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_runtime_dir),
        cmocka_unit_test(test_ipc_path),
        cmocka_unit_test(test_loopback),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

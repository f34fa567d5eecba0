/* Base64 against the test vectors of RFC 4648 section 10, a round trip over every byte value, and
 * malformed input. */
#include "sph_base64.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

static const char *const vectors[][2] = {
    {"", ""},
    {"f", "Zg=="},
    {"fo", "Zm8="},
    {"foo", "Zm9v"},
    {"foob", "Zm9vYg=="},
    {"fooba", "Zm9vYmE="},
    {"foobar", "Zm9vYmFy"},
};

static void test_rfc4648_encode(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof vectors / sizeof vectors[0]; i++) {
        char out[16];
        size_t n = strlen(vectors[i][0]);
        assert_int_equal(sph_base64_encoded_len(n), strlen(vectors[i][1]));
        assert_int_equal(sph_base64_encode(vectors[i][0], n, out), strlen(vectors[i][1]));
        assert_string_equal(out, vectors[i][1]);
    }
}

static void test_rfc4648_decode(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof vectors / sizeof vectors[0]; i++) {
        char out[16] = {0};
        long n = sph_base64_decode(vectors[i][1], strlen(vectors[i][1]), out);
        assert_int_equal(n, (long)strlen(vectors[i][0]));
        assert_memory_equal(out, vectors[i][0], (size_t)n);
    }
}

static void test_round_trip(void **state)
{
    (void)state;
    unsigned char in[256], back[256];
    char text[400];
    for (int i = 0; i < 256; i++)
        in[i] = (unsigned char)(255 - i);
    for (size_t n = 0; n <= sizeof in; n += 37) {
        size_t len = sph_base64_encode(in, n, text);
        assert_int_equal(sph_base64_decode(text, len, back), (long)n);
        assert_memory_equal(back, in, n);
    }
}

static void test_malformed(void **state)
{
    (void)state;
    unsigned char out[16];
    assert_int_equal(sph_base64_decode("Zm9", 3, out), -1);        /* not a multiple of 4 */
    assert_int_equal(sph_base64_decode("Zm9v!A==", 8, out), -1);   /* bad character */
    assert_int_equal(sph_base64_decode("Zg==Zm9v", 8, out), -1);   /* padding in the middle */
    assert_int_equal(sph_base64_decode("Z===", 4, out), -1);       /* too much padding */
    assert_int_equal(sph_base64_decode("Zm9v\nYg==", 9, out), -1); /* whitespace */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rfc4648_encode),
        cmocka_unit_test(test_rfc4648_decode),
        cmocka_unit_test(test_round_trip),
        cmocka_unit_test(test_malformed),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* Prints the case table (protocol/sph_case_table.h) as JSON, for tests/schema/check_case_table.py.
 */
#include "sph_case_table.h"

#include <stdio.h>

int main(void)
{
    json_t *rows = sph_case_fields_json();
    if (!rows || json_dumpf(rows, stdout, JSON_INDENT(1)) != 0)
        return 1;
    json_decref(rows);
    putchar('\n');
    return 0;
}

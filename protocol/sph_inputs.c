/* sph_inputs: the rule for the names of the files a case names. */
#include "sph_inputs.h"

#include <stdio.h>
#include <string.h>

int sph_input_name_check(const char *name, char *why, size_t n)
{
    const size_t len = strlen(name);
    const char *bad = NULL;
    if (len == 0)
        bad = "it is empty";
    else if (len > SPH_INPUT_NAME_MAX)
        bad = "it is longer than 127 bytes";
    else if (name[0] == '/')
        bad = "it is an absolute path: give it relative to the case file's directory";
    for (const char *p = name; !bad && *p; p++) {
        const unsigned char ch = (unsigned char)*p;
        const int start = p == name || p[-1] == '/';
        if (ch < 0x20 || ch == 0x7f || ch == '\\')
            bad = "it holds a control character or '\\'";
        else if (start && ch == '/')
            bad = "it has an empty component ('//')";
        else if (start && ch == '.')
            bad = "a component starts with '.' (no '.', '..' or hidden names: the file must be "
                  "in the case file's directory or below it)";
    }
    if (!bad && name[len - 1] == '/')
        bad = "it ends with '/'";
    if (bad && why)
        snprintf(why, n, "file name '%.*s' is not usable: %s", SPH_INPUT_NAME_MAX, name, bad);
    return bad ? -1 : 0;
}

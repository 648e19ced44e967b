/* A software or driver version as a preference holds it: "5.9", "3.15.2" or "2.10.0", blanks around
 * it allowed, a missing third number 0. It reads what the Lua dissectors' pattern
 * ^%s*(%d+)%.(%d+)%.?(%d*)%s*$ reads, into doubles as Lua's numbers are. */
/* <standalone> */
#include <epan/packet.h>
/* </standalone> */

/* The three numbers of the version; FALSE for text that is not one. */
static gboolean dotted_version_parts(const char *text, double part[3])
{
    const char *p = text;
    int i;

    if (p == NULL)
        return FALSE;
    while (g_ascii_isspace(*p))
        p++;
    for (i = 0; i < 3; i++) {
        part[i] = 0;
        if (i == 1 && *p++ != '.')
            return FALSE;
        if (i == 2 && *p == '.')
            p++;
        if (i < 2 && !g_ascii_isdigit(*p))
            return FALSE;
        for (; g_ascii_isdigit(*p); p++)
            part[i] = part[i] * 10 + (*p - '0');
    }
    while (g_ascii_isspace(*p))
        p++;
    return *p == '\0';
}

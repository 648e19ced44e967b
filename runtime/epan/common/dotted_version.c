/* A software or driver version as a preference holds it: "5.9", "3.15.2" or "2.10.0", blanks before
 * it allowed, a missing third number 0: the one reader of a version's text that every dissector
 * joins. whole: blanks after it and nothing else, what the Lua dissectors' pattern
 * ^%s*(%d+)%.(%d+)%.?(%d*)%s*$ reads; else the text may go on after it, as the primary interface's
 * preference always has (a third number then needs its digit after the dot). vt_blank: a vertical
 * tab is a blank too, as for Lua's %s; only the text-line dissectors have read it so. */
/* <standalone> */
#include <epan/packet.h>
/* </standalone> */

/* A part stops growing at DOTTED_VERSION_BIG or more (its first thirteen digits): far past every
 * version a table names, and never an overflow. */
#define DOTTED_VERSION_BIG G_GUINT64_CONSTANT(1000000000000)

static gboolean dotted_version_blank(char c, gboolean vt_blank)
{
    return g_ascii_isspace(c) || (vt_blank && c == '\v');
}

/* The three numbers of the version; FALSE for text that is not one. */
static gboolean dotted_version_parts(const char *text, gboolean whole, gboolean vt_blank, guint64 part[3])
{
    const char *p = text;
    int i;

    if (p == NULL)
        return FALSE;
    while (dotted_version_blank(*p, vt_blank))
        p++;
    for (i = 0; i < 3; i++) {
        part[i] = 0;
        if (i == 1 && *p++ != '.')
            return FALSE;
        if (i == 2 && !(*p == '.' && g_ascii_isdigit(p[1]))) {
            if (whole && *p == '.')
                p++;                            /* "5.9." reads as 5.9 */
            break;
        }
        if (i == 2)
            p++;
        if (!g_ascii_isdigit(*p))
            return FALSE;
        for (; g_ascii_isdigit(*p); p++) {
            if (part[i] < DOTTED_VERSION_BIG)
                part[i] = part[i] * 10 + (guint64)(*p - '0');
        }
    }
    if (!whole)
        return TRUE;
    while (dotted_version_blank(*p, vt_blank))
        p++;
    return *p == '\0';
}

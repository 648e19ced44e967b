/* runtime/epan/common/dotted_version.c alone: the one reader of a version preference's text that
 * every native dissector joins. Built and run by tests/native/test_dotted_version.py; prints "ok"
 * or the failed check. */
#include <stdio.h>

#include "dotted_version.c"

#define CHECK(x) do { if (!(x)) { printf("failed: %s (line %d)\n", #x, __LINE__); return 1; } } while (0)

static int parts(const char *text, gboolean whole, gboolean vt_blank, guint64 a, guint64 b, guint64 c)
{
    guint64 part[3];
    return dotted_version_parts(text, whole, vt_blank, part) && part[0] == a && part[1] == b && part[2] == c;
}

static int refused(const char *text, gboolean whole)
{
    guint64 part[3];
    return !dotted_version_parts(text, whole, FALSE, part);
}

int main(void)
{
    /* whole: ^%s*(%d+)%.(%d+)%.?(%d*)%s*$, as the Lua dissectors read it */
    CHECK(parts(" 3.15.7 ", TRUE, FALSE, 3, 15, 7) && parts("5.11", TRUE, FALSE, 5, 11, 0));
    CHECK(parts("5.1.", TRUE, FALSE, 5, 1, 0) && parts("5.1234", TRUE, FALSE, 5, 1234, 0));
    CHECK(refused("", TRUE) && refused("5", TRUE) && refused("5.11.1.2", TRUE) && refused("x5.11", TRUE));
    CHECK(refused("5.11 1", TRUE) && refused("5.9.x", TRUE) && refused("5.", TRUE) && refused(NULL, TRUE));
    /* not whole: the text may go on after the version; a third number needs its digit */
    CHECK(parts("5.9 (CB3)", FALSE, FALSE, 5, 9, 0) && parts("5.9.x", FALSE, FALSE, 5, 9, 0));
    CHECK(parts(" 3.2.", FALSE, FALSE, 3, 2, 0) && parts("10.7.5000", FALSE, FALSE, 10, 7, 5000));
    CHECK(refused("abc", FALSE) && refused("5.", FALSE) && refused(".5", FALSE));
    /* a vertical tab is a blank only when asked */
    CHECK(parts("\v5.9\v", TRUE, TRUE, 5, 9, 0) && refused("\v5.9", TRUE));
    /* a part stops growing at its first thirteen digits: no overflow */
    CHECK(parts("123456789012345678901.1", TRUE, FALSE, 1234567890123u, 1, 0));
    printf("ok\n");
    return 0;
}

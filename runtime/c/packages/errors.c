/* <standalone> */
#include "runtime_support.h"
/* </standalone> */
/* ---- errors ------------------------------------------------------------------------------- */

static void urwire__set_path(urwire_error *e, const char *path)
{
    size_t n = strlen(path);
    if (n >= sizeof e->path)
        n = sizeof e->path - 1;
    memcpy(e->path, path, n);
    e->path[n] = '\0';
}

/* Sets *e; returns false, for `return urwire__fail(...)`. A NULL e is an error nobody reads
 * (a robot state's sub-packages, whose failures are bits): the decoders then keep no
 * urwire_error on the stack for it. */
URWIRE__PRIVATE bool urwire__fail(urwire_error *e, urwire_status status, size_t offset, const char *path,
                                  int64_t value, int64_t left)
{
    if (e == NULL)
        return false;
    e->status = status;
    e->offset = offset;
    e->value = value;
    e->left = left;
    urwire__set_path(e, path);
    return false;
}

/* The field at offset needs need bytes and the layout ends at end. */
URWIRE__PRIVATE bool urwire__short(urwire_error *e, const char *path, size_t offset, size_t need, size_t end)
{
    return urwire__fail(e, URWIRE_E_SHORT, offset, path, (int64_t)need, end > offset ? (int64_t)(end - offset) : 0);
}

static void urwire__prefix_path(urwire_error *e, const char *name, size_t name_len, size_t index);

/* Where the element's index goes in a span's path ("[]"), or NULL when it has none. */
static const char *urwire__index_hole(const urwire__span *s)
{
    const char *p;
    if (s->index == URWIRE__NO_INDEX)
        return NULL;
    for (p = s->path; *p; p++)  /* a loop, not strstr: that would cost a firmware 1 KB */
        if (p[0] == '[' && p[1] == ']')
            return p;
    return NULL;
}

/* The first field of a fixed run (ended by a NULL path) that does not fit names the error; an
 * element's index goes into its path's "[]". */
URWIRE__PRIVATE bool urwire__short_in_run(urwire_error *e, const urwire__span *run, size_t pos, size_t end)
{
    const char *hole;
    for (; run->path; run++) {
        if (pos + run->offset + run->size <= end)
            continue;
        hole = urwire__index_hole(run);
        urwire__short(e, hole ? hole + 2 : run->path, pos + run->offset, run->size, end);
        if (hole && e != NULL)
            urwire__prefix_path(e, run->path, (size_t)(hole - run->path), run->index);
        return false;
    }
    return urwire__short(e, "?", pos, 0, end);  /* not reached: the caller saw the run not fit */
}

URWIRE__PRIVATE bool urwire__no_space(urwire_error *e, size_t pos, size_t need, size_t cap)
{
    return urwire__fail(e, URWIRE_E_NO_SPACE, pos, "", (int64_t)need, (int64_t)(cap - pos));
}

/* text[0..len) into path at `at`, as much of it as falls before max. */
static void urwire__put_cut(char *path, size_t max, size_t at, const char *text, size_t len)
{
    if (at < max)
        memcpy(path + at, text, len < max - at ? len : max - at);
}

/* Prefix the error's path with name[index] (name, of name_len characters, may be empty),
 * joined as Python's paths are: threads[1].label_name, [0].type. In place, cut to
 * URWIRE_PATH_MAX - 1 characters like any path: no second path on the stack, and one number's
 * digits. */
static void urwire__prefix_path(urwire_error *e, const char *name, size_t name_len, size_t index)
{
    char digits[24];
    size_t max = sizeof e->path - 1, nd = urwire__digits(digits, (int64_t)index);
    size_t rest = strlen(e->path), n, keep;
    bool dot = rest && e->path[0] != '[' && e->path[0] != '.';
    n = name_len + 2 + nd + (dot ? 1 : 0);  /* the prefix's length */
    keep = n >= max ? 0 : (rest < max - n ? rest : max - n);
    memmove(e->path + (n < max ? n : max), e->path, keep);
    e->path[(n < max ? n : max) + keep] = '\0';
    urwire__put_cut(e->path, max, 0, name, name_len);
    urwire__put_cut(e->path, max, name_len, "[", 1);
    urwire__put_cut(e->path, max, name_len + 1, digits, nd);
    urwire__put_cut(e->path, max, name_len + 1 + nd, "]", 1);
    if (dot)
        urwire__put_cut(e->path, max, n - 1, ".", 1);
}

/* Prefix the error's path with name[index], or name[index][index2] when two (the second
 * index first: a path cut at the end is the same either way); for `return
 * urwire__within2(...)`. A NULL e is an error nobody reads. */
URWIRE__PRIVATE bool urwire__within2(urwire_error *e, const char *name, size_t index, size_t index2, bool two)
{
    if (e == NULL)
        return false;
    if (two)
        urwire__prefix_path(e, "", 0, index2);
    urwire__prefix_path(e, name, strlen(name), index);
    return false;
}

URWIRE__PRIVATE bool urwire__within(urwire_error *e, const char *name, size_t index)
{
    return urwire__within2(e, name, index, 0, false);
}

const char *urwire_status_name(urwire_status status)
{
    switch (status) {
    case URWIRE_OK: return "URWIRE_OK";
    case URWIRE_E_SHORT: return "URWIRE_E_SHORT";
    case URWIRE_E_NEGATIVE_LENGTH: return "URWIRE_E_NEGATIVE_LENGTH";
    case URWIRE_E_VALUE_TYPE: return "URWIRE_E_VALUE_TYPE";
    case URWIRE_E_TERMINATOR: return "URWIRE_E_TERMINATOR";
    case URWIRE_E_TOO_DEEP: return "URWIRE_E_TOO_DEEP";
    case URWIRE_E_TOO_MANY_ITEMS: return "URWIRE_E_TOO_MANY_ITEMS";
    case URWIRE_E_EMPTY_ROWS: return "URWIRE_E_EMPTY_ROWS";
    case URWIRE_E_PACKAGE_HEADER_CUT: return "URWIRE_E_PACKAGE_HEADER_CUT";
    case URWIRE_E_PACKAGE_LENGTH_LOW: return "URWIRE_E_PACKAGE_LENGTH_LOW";
    case URWIRE_E_PACKAGE_LENGTH_HIGH: return "URWIRE_E_PACKAGE_LENGTH_HIGH";
    case URWIRE_E_LENGTH_LOW: return "URWIRE_E_LENGTH_LOW";
    case URWIRE_E_LENGTH_HIGH: return "URWIRE_E_LENGTH_HIGH";
    case URWIRE_E_MESSAGE_TYPE: return "URWIRE_E_MESSAGE_TYPE";
    case URWIRE_E_TRUNCATED_MESSAGE: return "URWIRE_E_TRUNCATED_MESSAGE";
    case URWIRE_E_TRUNCATED_HEADER: return "URWIRE_E_TRUNCATED_HEADER";
    case URWIRE_E_TOO_BIG_FOR_BUFFER: return "URWIRE_E_TOO_BIG_FOR_BUFFER";
    case URWIRE_E_NO_SPACE: return "URWIRE_E_NO_SPACE";
    case URWIRE_E_TOO_LONG: return "URWIRE_E_TOO_LONG";
    }
    return "URWIRE_E_UNKNOWN";
}

/* "<what> at offset <o>: " */
static void urwire__at(urwire__text *t, const urwire_error *e, const char *what)
{
    urwire__str(t, what);
    urwire__str(t, " at offset ");
    urwire__num(t, (int64_t)e->offset);
    urwire__str(t, ": ");
}

size_t urwire_error_text(const urwire_error *e, char *out, size_t cap)
{
    urwire__text t;
    t.out = out;
    t.cap = cap;
    t.n = 0;
    switch (e->status) {
    case URWIRE_OK:
        urwire__str(&t, "no error");
        break;
    case URWIRE_E_SHORT:
    case URWIRE_E_PACKAGE_HEADER_CUT:
        urwire__at(&t, e, e->status == URWIRE_E_SHORT ? e->path : "package");
        urwire__str(&t, "needs ");
        urwire__num(&t, e->value);
        urwire__str(&t, " bytes, ");
        urwire__num(&t, e->left);
        urwire__str(&t, " left");
        break;
    case URWIRE_E_NEGATIVE_LENGTH:
        urwire__at(&t, e, e->path);
        urwire__str(&t, "negative length ");
        urwire__num(&t, e->value);
        break;
    case URWIRE_E_VALUE_TYPE:
        urwire__at(&t, e, e->path);
        urwire__str(&t, "unknown value type ");
        urwire__num(&t, e->value);
        break;
    case URWIRE_E_TERMINATOR:
        urwire__at(&t, e, e->path);
        urwire__str(&t, "expected terminator 0x");
        urwire__hex2(&t, e->left);
        urwire__str(&t, ", found 0x");
        urwire__hex2(&t, e->value);
        break;
    case URWIRE_E_TOO_DEEP:
        urwire__at(&t, e, e->path);
        urwire__str(&t, "nesting deeper than ");
        urwire__num(&t, e->value);
        break;
    case URWIRE_E_TOO_MANY_ITEMS:
        urwire__at(&t, e, e->path);
        urwire__num(&t, e->value);
        urwire__str(&t, " items need more than the ");
        urwire__num(&t, e->left);
        urwire__str(&t, " bytes left");
        break;
    case URWIRE_E_EMPTY_ROWS:
        urwire__at(&t, e, e->path);
        urwire__num(&t, e->value);
        urwire__str(&t, " rows of 0 columns");
        break;
    case URWIRE_E_PACKAGE_LENGTH_LOW:
        urwire__at(&t, e, "package");
        urwire__str(&t, "length ");
        urwire__num(&t, e->value);
        urwire__str(&t, " is below ");
        urwire__num(&t, URWIRE_PACKAGE_HEADER_SIZE);
        break;
    case URWIRE_E_PACKAGE_LENGTH_HIGH:
        urwire__at(&t, e, "package");
        urwire__str(&t, "length ");
        urwire__num(&t, e->value);
        urwire__str(&t, " exceeds the ");
        urwire__num(&t, e->left);
        urwire__str(&t, " bytes left");
        break;
    case URWIRE_E_LENGTH_LOW:
        urwire__str(&t, "length ");
        urwire__num(&t, e->value);
        urwire__str(&t, " is below ");
        urwire__num(&t, URWIRE_HEADER_SIZE);
        break;
    case URWIRE_E_LENGTH_HIGH:
        urwire__str(&t, "length ");
        urwire__num(&t, e->value);
        urwire__str(&t, " is above ");
        urwire__num(&t, URWIRE_MAX_MESSAGE_LENGTH);
        break;
    case URWIRE_E_MESSAGE_TYPE:
        urwire__str(&t, "unknown message type ");
        urwire__num(&t, e->value);
        break;
    case URWIRE_E_TRUNCATED_MESSAGE:
        urwire__str(&t, "truncated message: length ");
        urwire__num(&t, e->value);
        urwire__str(&t, ", ");
        urwire__num(&t, e->left);
        urwire__str(&t, " bytes left");
        break;
    case URWIRE_E_TRUNCATED_HEADER:
        urwire__str(&t, "truncated header: ");
        urwire__num(&t, e->left);
        urwire__str(&t, " bytes left");
        break;
    case URWIRE_E_TOO_BIG_FOR_BUFFER:
        urwire__str(&t, "message of length ");
        urwire__num(&t, e->value);
        urwire__str(&t, " exceeds the framer's buffer of ");
        urwire__num(&t, e->left);
        urwire__str(&t, " bytes");
        break;
    case URWIRE_E_NO_SPACE:
        urwire__at(&t, e, e->path);
        urwire__str(&t, "needs ");
        urwire__num(&t, e->value);
        urwire__str(&t, " bytes, ");
        urwire__num(&t, e->left);
        urwire__str(&t, " left in the output");
        break;
    case URWIRE_E_TOO_LONG:
        urwire__str(&t, e->path);
        urwire__str(&t, ": ");
        urwire__num(&t, e->value);
        urwire__str(&t, " bytes do not fit the length prefix (max ");
        urwire__num(&t, e->left);
        urwire__str(&t, ")");
        break;
    }
    return urwire__end(&t);
}

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

static void urwire__prefix_path(urwire_error *e, const char *name, size_t name_len, size_t index, size_t index2,
                                bool two);

/* Where an element's index goes in a span's path ("[]"), or NULL when it has none. */
static const char *urwire__index_hole(const char *path)
{
    const char *p;
    for (p = path; *p; p++)  /* a loop, not strstr: that would cost a firmware 1 KB */
        if (p[0] == '[' && p[1] == ']')
            return p;
    return NULL;
}

/* The first span of a fixed run (ended by a NULL path) that does not fit before end, with its
 * offset (*at) and its element's index (*index, URWIRE__NO_INDEX: none); NULL when all fit. A
 * repeat row (path "") stands for elements 1 to size - 1 of a group, `offset` bytes apart,
 * whose element 0 is the `index` rows before it. */
static const urwire__span *urwire__first_short(const urwire__span *run, size_t pos, size_t end, size_t *at,
                                               size_t *index)
{
    const urwire__span *s;
    size_t k;
    for (; run->path; run++) {
        if (run->path[0] != '\0') {
            *at = pos + run->offset;
            *index = run->index;
            if (*at + run->size > end)
                return run;
            continue;
        }
        for (k = 1; k < run->size; k++)
            for (s = run - run->index; s < run; s++) {
                *at = pos + k * run->offset + s->offset;
                *index = k;
                if (*at + s->size > end)
                    return s;
            }
    }
    return NULL;
}

/* The first field of a fixed run that does not fit names the error; an element's index goes
 * into its path's "[]". */
URWIRE__PRIVATE bool urwire__short_in_run(urwire_error *e, const urwire__span *run, size_t pos, size_t end)
{
    size_t at, index;
    const urwire__span *s = urwire__first_short(run, pos, end, &at, &index);
    const char *hole;
    if (s == NULL)
        return urwire__short(e, "?", pos, 0, end);  /* not reached: the caller saw the run not fit */
    hole = index != URWIRE__NO_INDEX ? urwire__index_hole(s->path) : NULL;
    urwire__short(e, hole ? hole + 2 : s->path, at, s->size, end);
    if (hole && e != NULL)
        urwire__prefix_path(e, s->path, (size_t)(hole - s->path), index, 0, false);
    return false;
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

/* Prefix the error's path with name[index] (name, of name_len characters, may be empty), or
 * name[index][index2] when two, joined as Python's paths are: threads[1].label_name,
 * variables[2][0].type. In place, cut to URWIRE_PATH_MAX - 1 characters like any path: no
 * second path on the stack. */
static void urwire__prefix_path(urwire_error *e, const char *name, size_t name_len, size_t index, size_t index2,
                                bool two)
{
    char digits[2][24];
    size_t max = sizeof e->path - 1, nd = urwire__digits(digits[0], (int64_t)index);
    size_t nd2 = two ? urwire__digits(digits[1], (int64_t)index2) : 0;
    size_t rest = strlen(e->path), n, keep;
    bool dot = rest && e->path[0] != '[' && e->path[0] != '.';
    n = name_len + 2 + nd + (two ? 2 + nd2 : 0) + (dot ? 1 : 0);  /* the prefix's length */
    keep = n >= max ? 0 : (rest < max - n ? rest : max - n);
    memmove(e->path + (n < max ? n : max), e->path, keep);
    e->path[(n < max ? n : max) + keep] = '\0';
    urwire__put_cut(e->path, max, 0, name, name_len);
    urwire__put_cut(e->path, max, name_len, "[", 1);
    urwire__put_cut(e->path, max, name_len + 1, digits[0], nd);
    urwire__put_cut(e->path, max, name_len + 1 + nd, "]", 1);
    if (two) {
        urwire__put_cut(e->path, max, name_len + 2 + nd, "[", 1);
        urwire__put_cut(e->path, max, name_len + 3 + nd, digits[1], nd2);
        urwire__put_cut(e->path, max, name_len + 3 + nd + nd2, "]", 1);
    }
    if (dot)
        urwire__put_cut(e->path, max, n - 1, ".", 1);
}

/* urwire__prefix of a NUL-terminated name, for `return urwire__within2(...)`; a NULL e is an
 * error nobody reads. */
URWIRE__PRIVATE bool urwire__within2(urwire_error *e, const char *name, size_t index, size_t index2, bool two)
{
    if (e != NULL)
        urwire__prefix_path(e, name, strlen(name), index, index2, two);
    return false;
}

URWIRE__PRIVATE bool urwire__within(urwire_error *e, const char *name, size_t index)
{
    return urwire__within2(e, name, index, 0, false);
}

/* The statuses' names in their order, then the name of any other, in an object of their own:
 * as string literals they shared the one string section of the file, which the linker keeps
 * whole for any error path a firmware links (430 bytes in every firmware). */
static const char urwire__status_names[] =
    "URWIRE_OK\0" "URWIRE_E_SHORT\0" "URWIRE_E_NEGATIVE_LENGTH\0" "URWIRE_E_VALUE_TYPE\0"
    "URWIRE_E_TERMINATOR\0" "URWIRE_E_TOO_DEEP\0" "URWIRE_E_TOO_MANY_ITEMS\0" "URWIRE_E_EMPTY_ROWS\0"
    "URWIRE_E_PACKAGE_HEADER_CUT\0" "URWIRE_E_PACKAGE_LENGTH_LOW\0" "URWIRE_E_PACKAGE_LENGTH_HIGH\0"
    "URWIRE_E_LENGTH_LOW\0" "URWIRE_E_LENGTH_HIGH\0" "URWIRE_E_MESSAGE_TYPE\0"
    "URWIRE_E_TRUNCATED_MESSAGE\0" "URWIRE_E_TRUNCATED_HEADER\0" "URWIRE_E_TOO_BIG_FOR_BUFFER\0"
    "URWIRE_E_NO_SPACE\0" "URWIRE_E_TOO_LONG\0" "URWIRE_E_UNKNOWN";

const char *urwire_status_name(urwire_status status)
{
    const char *name = urwire__status_names;
    unsigned k = (unsigned)status, last = (unsigned)URWIRE_E_TOO_LONG;
    for (k = k <= last ? k : last + 1u; k > 0; k--)
        name += strlen(name) + 1;
    return name;
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

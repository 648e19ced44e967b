/* <standalone> */
#include "runtime_support.h"
/* </standalone> */
/* ---- errors ------------------------------------------------------------------------------- */

/* Sets *e; returns false, for `return urwire__fail(...)`. path is the parser's own text (a
 * literal or a table's), kept, not copied. A NULL e is an error nobody reads (a robot
 * state's sub-packages, whose failures are bits): the decoders then keep no urwire_error on
 * the stack for it. */
URWIRE__PRIVATE bool urwire__fail(urwire_error *e, urwire_status status, size_t offset, const char *path,
                                  int64_t value, int64_t left)
{
    if (e == NULL)
        return false;
    e->status = status;
    e->offset = offset;
    e->value = value;
    e->left = left;
    e->field = path;
    e->steps = 0;
    return false;
}

/* The field at offset needs need bytes and the layout ends at end. */
URWIRE__PRIVATE bool urwire__short(urwire_error *e, const char *path, size_t offset, size_t need, size_t end)
{
    return urwire__fail(e, URWIRE_E_SHORT, offset, path, (int64_t)need, end > offset ? (int64_t)(end - offset) : 0);
}

/* Puts name[index] (name, of name_len characters, may be empty), or name[index][index2] when
 * two, before the error's path: one step more. Indexes are counts within one message, far
 * below 2^32; a MATRIX's columns are int16. A path of more steps than URWIRE_PATH_STEPS (no
 * layout of the spec nests that deep) keeps its innermost. */
static void urwire__add_step(urwire_error *e, const char *name, size_t name_len, size_t index, size_t index2,
                                bool two)
{
    urwire_path_step *s;
    if (e->steps == URWIRE_PATH_STEPS)
        return;
    s = &e->step[e->steps++];
    s->name = name;
    s->name_len = (uint16_t)name_len;
    s->index = (uint32_t)index;
    s->index2 = two ? (uint16_t)(index2 + 1) : 0;
}

/* Where an element's index goes in a span's path ("[]"), or NULL when it has none. */
static const char *urwire__index_hole(const char *path)
{
    const char *p;
    for (p = path; *p; p++)  /* a loop, not strstr: that would cost a firmware 1 KB */
        if (p[0] == '[' && p[1] == ']')
            return p;
    return NULL;
}

/* The first span of a fixed run (ended by a row of size 0) that does not fit before end, with
 * its offset (*at) and its element's index (*index, URWIRE__NO_INDEX: none); NULL when all fit.
 * A repeat row (size URWIRE__REPEAT | n) stands for elements 1 to n - 1 of a group, `offset`
 * bytes apart, whose element 0 is the `index` rows before it. */
static const urwire__span *urwire__first_short(const urwire__span *run, size_t pos, size_t end, size_t *at,
                                               size_t *index)
{
    const urwire__span *s;
    size_t k;
    for (; run->size != 0; run++) {
        if (!(run->size & URWIRE__REPEAT)) {
            *at = pos + run->offset;
            *index = run->index;
            if (*at + run->size > end)
                return run;
            continue;
        }
        for (k = 1; k < (run->size & ~URWIRE__REPEAT); k++)
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
 * into its path's "[]" (with URWIRE_NO_NAMES, a path of no name and no "[]": the index alone). */
URWIRE__PRIVATE bool urwire__short_in_run(urwire_error *e, const urwire__span *run, size_t pos, size_t end)
{
    size_t at, index;
    const urwire__span *s = urwire__first_short(run, pos, end, &at, &index);
    const char *path, *hole;
    if (s == NULL)
        return urwire__short(e, "?", pos, 0, end);  /* not reached: the caller saw the run not fit */
    path = URWIRE__SPAN_PATH(s);
    hole = index != URWIRE__NO_INDEX ? urwire__index_hole(path) : NULL;
    urwire__short(e, hole ? hole + 2 : path, at, s->size, end);
    if (index != URWIRE__NO_INDEX && e != NULL)
        urwire__add_step(e, path, hole ? (size_t)(hole - path) : 0, index, 0, false);
    return false;
}

URWIRE__PRIVATE bool urwire__no_space(urwire_error *e, size_t pos, size_t need, size_t cap)
{
    return urwire__fail(e, URWIRE_E_NO_SPACE, pos, "", (int64_t)need, (int64_t)(cap - pos));
}

/* Prefix the error's path with name[index], or name[index][index2] when two, for `return
 * urwire__within2(...)`; a NULL e is an error nobody reads. */
URWIRE__PRIVATE bool urwire__within2(urwire_error *e, const char *name, size_t index, size_t index2, bool two)
{
    if (e != NULL)
        urwire__add_step(e, name, strlen(name), index, index2, two);
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

/* p[0..n) of the path, as much as the room left for it holds. */
static void urwire__path_part(urwire__text *t, const char *p, size_t n, size_t *room)
{
    n = n < *room ? n : *room;
    urwire__bytes(t, p, n);
    *room -= n;
}

/* "[<index>]" of the path. */
static void urwire__path_index(urwire__text *t, size_t index, size_t *room)
{
    char digits[24];
    urwire__path_part(t, "[", 1, room);
    urwire__path_part(t, digits, urwire__digits(digits, (int64_t)index), room);
    urwire__path_part(t, "]", 1, room);
}

/* The error's path: its steps, outermost first, then its field, joined as Python's paths are
 * (a dot before a part that starts with neither '[' nor '.'): threads[1].label_name,
 * variables[2][0].type. Cut to URWIRE_PATH_MAX - 1 characters. */
static void urwire__path(urwire__text *t, const urwire_error *e)
{
    size_t room = URWIRE_PATH_MAX - 1, k = e->steps;
    const urwire_path_step *s;
    const char *next;
    while (k--) {
        s = &e->step[k];
        urwire__path_part(t, s->name, s->name_len, &room);
        urwire__path_index(t, s->index, &room);
        if (s->index2)
            urwire__path_index(t, (size_t)s->index2 - 1, &room);
        next = k == 0 ? e->field : e->step[k - 1].name_len ? e->step[k - 1].name : "[";
        if (*next && *next != '[' && *next != '.')
            urwire__path_part(t, ".", 1, &room);
    }
    urwire__path_part(t, e->field, strlen(e->field), &room);
}

/* "<path> at offset <o>: ", the error's path, or what when it is not NULL. */
static void urwire__at(urwire__text *t, const urwire_error *e, const char *what)
{
    if (what != NULL)
        urwire__str(t, what);
    else
        urwire__path(t, e);
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
        urwire__at(&t, e, e->status == URWIRE_E_SHORT ? NULL : "package");
        urwire__str(&t, "needs ");
        urwire__num(&t, e->value);
        urwire__str(&t, " bytes, ");
        urwire__num(&t, e->left);
        urwire__str(&t, " left");
        break;
    case URWIRE_E_NEGATIVE_LENGTH:
        urwire__at(&t, e, NULL);
        urwire__str(&t, "negative length ");
        urwire__num(&t, e->value);
        break;
    case URWIRE_E_VALUE_TYPE:
        urwire__at(&t, e, NULL);
        urwire__str(&t, "unknown value type ");
        urwire__num(&t, e->value);
        break;
    case URWIRE_E_TERMINATOR:
        urwire__at(&t, e, NULL);
        urwire__str(&t, "expected terminator 0x");
        urwire__hex2(&t, e->left);
        urwire__str(&t, ", found 0x");
        urwire__hex2(&t, e->value);
        break;
    case URWIRE_E_TOO_DEEP:
        urwire__at(&t, e, NULL);
        urwire__str(&t, "nesting deeper than ");
        urwire__num(&t, e->value);
        break;
    case URWIRE_E_TOO_MANY_ITEMS:
        urwire__at(&t, e, NULL);
        urwire__num(&t, e->value);
        urwire__str(&t, " items need more than the ");
        urwire__num(&t, e->left);
        urwire__str(&t, " bytes left");
        break;
    case URWIRE_E_EMPTY_ROWS:
        urwire__at(&t, e, NULL);
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
        urwire__at(&t, e, NULL);
        urwire__str(&t, "needs ");
        urwire__num(&t, e->value);
        urwire__str(&t, " bytes, ");
        urwire__num(&t, e->left);
        urwire__str(&t, " left in the output");
        break;
    case URWIRE_E_TOO_LONG:
        urwire__path(&t, e);
        urwire__str(&t, ": ");
        urwire__num(&t, e->value);
        urwire__str(&t, " bytes do not fit the length prefix (max ");
        urwire__num(&t, e->left);
        urwire__str(&t, ")");
        break;
    }
    return urwire__end(&t);
}

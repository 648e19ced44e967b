/* Software versions as one number, (major * 1000 + minor) * 1000 + bugfix (5.9 is 5009000,
 * 5.25.1 is 5025001; an upper bound written 5.8 is 5008999, any 5.8.x): parsed from the
 * preference's text, shown back as text, tested against a range. What follows the version: the
 * value-type table and the names of an enum whose codes depend on it, and the form (layout) of a
 * package or subtype, chosen by the version or else by the length
 * (docs/contract.md#choosing-a-layout). As runtime/lua/packages/versions.lua. */
#define UR_BUGFIX_ANY 999   /* a bugfix number that stands for every bugfix release of its minor */
#define UR_VERSION_NONE G_MAXUINT32  /* no version known (a Version message may announce 0.0) */

static guint32
ur_version_number(guint32 major, guint32 minor, gint64 bugfix)
{
    if (bugfix > UR_BUGFIX_ANY)
        bugfix = UR_BUGFIX_ANY;
    if (bugfix < 0)
        bugfix = 0;
    return (major * 1000 + minor) * 1000 + (guint32)bugfix;
}

/* "5.9" -> 5009000, "5.25.1" -> 5025001 (leading blanks allowed, and any text after the version:
 * runtime/c/common/version_text.c); UR_VERSION_NONE when the text is no version. */
static guint32
ur_parse_version(const char *text)
{
    urwire__version_text t;
    uint64_t *part = t.part;
    if (text == NULL || !urwire__read_version(text, text + strlen(text), false, false, &t))
        return UR_VERSION_NONE;
    for (unsigned i = 0; i < 3; i++) {
        while (part[i] >= 10000000)     /* a part of eight digits or more reads as its first seven */
            part[i] /= 10;
    }
    guint64 bugfix = part[2] > UR_BUGFIX_ANY ? UR_BUGFIX_ANY : part[2];
    guint64 v = (part[0] * 1000 + part[1]) * 1000 + bugfix;
    /* As Lua's numbers do, a minor of 1000 or more carries into the major; a version past what
     * one number holds reads as the newest there is. */
    return v >= UR_VERSION_NONE ? UR_VERSION_NONE - 1 : (guint32)v;
}

/* 5009000 -> "5.9", 5025001 -> "5.25.1", 5008999 (any 5.8.x) -> "5.8", into buf. */
#define UR_VERSION_TEXT 24
static const char *
ur_version_text(guint32 v, char buf[UR_VERSION_TEXT])
{
    guint32 bugfix = v % 1000, minor = v / 1000 % 1000, major = v / 1000000;
    if (bugfix == 0 || bugfix == UR_BUGFIX_ANY)
        snprintf(buf, UR_VERSION_TEXT, "%u.%u", major, minor);
    else
        snprintf(buf, UR_VERSION_TEXT, "%u.%u.%u", major, minor, bugfix);
    return buf;
}

static inline gboolean
ur_version_in(guint32 v, guint32 low, guint32 high)
{
    return v >= low && v <= high;
}

/* The value types of version v: the table in force, else the last. */
static const ur_value_table *
ur_value_table_of(guint32 v)
{
    for (unsigned i = 0; i < array_length(ur_value_tables); i++) {
        if (ur_version_in(v, ur_value_tables[i].low, ur_value_tables[i].high))
            return &ur_value_tables[i];
    }
    return &ur_value_tables[array_length(ur_value_tables) - 1];
}

/* The names of an enum whose codes depend on the version, for version v. */
static const value_string *
ur_enum_names(const ur_names *t, guint32 v)
{
    for (unsigned i = 0; i < t->n_rows; i++) {
        if (ur_version_in(v, t->rows[i].low, t->rows[i].high))
            return t->rows[i].names;
    }
    return t->newest;
}

/* True when some version's table names the code. */
static gboolean
ur_named_in_any(const ur_names *t, guint32 code)
{
    for (unsigned i = 0; i < t->n_rows; i++) {
        if (try_val_to_str(code, t->rows[i].names) != NULL)
            return TRUE;
    }
    return FALSE;
}

/* The segment of the version axis that holds v: 1 below the first start, else 1 + the starts at
 * or below v. */
static unsigned
ur_segment_of(guint32 v)
{
    unsigned lo = 0, hi = array_length(ur_segment_starts);
    while (lo < hi) {
        unsigned mid = (lo + hi) / 2;
        if (ur_segment_starts[mid] <= v)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo + 1;
}

static gboolean
ur_fits(const ur_form *form, unsigned size)
{
    if (form->sizes == NULL)
        return size >= form->min;
    for (unsigned i = 0; i < form->n_sizes; i++) {
        if (form->sizes[i] == size)
            return TRUE;
    }
    return FALSE;
}

/* The form of a body of `size` bytes for version v, the version to read it with (*use), and
 * whether the length chose it: the version's form when it fits; else the one form whose exact
 * size it is; else the version's form, whose short or extra bytes are then reported. */
static const ur_form *
ur_choose(const ur_forms *forms, unsigned size, guint32 v, guint32 *use, gboolean *by_length)
{
    *use = v;
    *by_length = FALSE;
    if (forms->single)
        return &forms->forms[0];
    int k = forms->segments[ur_segment_of(v) - 1];
    const ur_form *mine = &forms->forms[(k < 0 ? -k : k) - 1];
    if (k < 0)
        *use = mine->rep;   /* read as the version it stands for */
    if (ur_fits(mine, size))
        return mine;
    for (unsigned i = 0; i < forms->n_by_length; i++) {
        if (forms->by_length[i].size == size) {
            const ur_form *found = &forms->forms[forms->by_length[i].form - 1];
            *use = found->rep;
            *by_length = TRUE;
            return found;
        }
    }
    return mine;
}

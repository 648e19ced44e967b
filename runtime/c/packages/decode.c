/* <standalone> */
#include "runtime_support.h"
/* </standalone> */
/* ---- decoding messages -------------------------------------------------------------------- */
/* The one sub-package list is URWIRE__PACKAGES_TYPE, decoded as URWIRE__PACKAGES_KIND; each
 * sub-package is read in the form urwire__choose gives (forms.c), through the generated
 * switches urwire__decode_package and, on the robot-state fast path, urwire__decode_member. */

static void urwire__init_message(urwire_message *out, const uint8_t *bytes, size_t len, urwire_sw_version version)
{
    out->bytes = bytes;
    out->length = len;
    out->message_type = len > URWIRE__TYPE_AT ? bytes[URWIRE__TYPE_AT] : 0;
    out->failed = false;
    out->error.status = URWIRE_OK;
    out->error.field = "";
    out->error.steps = 0;
    out->raw = urwire__view(bytes, 0);
    urwire__init_seq(&out->packages, bytes, len, &version, -1);
    out->version = version;
    out->implied = false;
    out->implied_version = version;
}

static void urwire__fail_message(urwire_message *out, size_t raw_from)
{
    out->failed = true;
    out->raw = urwire__view(out->bytes + raw_from, out->length - raw_from);
}

/* Checks the sub-package header at pos; false (and *err set) when it cannot be framed. */
static bool urwire__frame_package(const uint8_t *msg, size_t pos, size_t end, size_t *size, urwire_error *err)
{
    size_t left = end - pos;
    int64_t declared;
    if (left < URWIRE_PACKAGE_HEADER_SIZE)
        return urwire__fail(err, URWIRE_E_PACKAGE_HEADER_CUT, pos, URWIRE__NAME("package"),
                            URWIRE_PACKAGE_HEADER_SIZE, (int64_t)left);
    declared = URWIRE__PACKAGE_LENGTH(msg + pos);
    if (declared < (int64_t)URWIRE_PACKAGE_HEADER_SIZE)
        return urwire__fail(err, URWIRE_E_PACKAGE_LENGTH_LOW, pos, URWIRE__NAME("package"), declared, 0);
    if ((uint64_t)declared > left)
        return urwire__fail(err, URWIRE_E_PACKAGE_LENGTH_HIGH, pos, URWIRE__NAME("package"), declared,
                            (int64_t)left);
    *size = (size_t)declared;
    return true;
}

/* urwire__frame_package in the loop of a robot state. At -Os (__OPTIMIZE_SIZE__, set by gcc and
 * clang) it is called, not inlined, once per sub-package: its common case is written out there
 * (-9% per robot state). At -O2 and -O3 it is inlined anyway, and the copy cost 3-4%. */
URWIRE__INLINE bool urwire__frame_next_package(const uint8_t *msg, size_t pos, size_t end, size_t *size,
                                               urwire_error *err)
{
#if defined(__OPTIMIZE_SIZE__)
    int64_t declared = end - pos >= URWIRE_PACKAGE_HEADER_SIZE ? URWIRE__PACKAGE_LENGTH(msg + pos) : 0;
    if (URWIRE__LIKELY(declared >= (int64_t)URWIRE_PACKAGE_HEADER_SIZE && (uint64_t)declared <= end - pos)) {
        *size = (size_t)declared;
        return true;
    }
#endif
    return urwire__frame_package(msg, pos, end, size, err);
}

/* The version a sub-package list is read under, as it goes: a form chosen by its length while
 * the version is only assumed sets the version for the rest of the message, and for the
 * stream (`implied`). `mine` and `first_sizes` are the rows of the segment's forms. */
typedef struct urwire__running {
    urwire__ver now;
    size_t segment;
    const uint8_t *mine;
    const uint32_t *first_sizes;
    bool implied;
} urwire__running;

static void urwire__run_at(urwire__running *r, urwire_sw_version version)
{
    size_t row;
    /* field by field: a urwire__ver built and copied costs a firmware's stack 50 bytes here */
    r->now.version = version;
    r->now.key = urwire__version_key(version);
    r->segment = urwire__segment(r->now.key);
    row = r->segment * urwire__package_form_table.ncodes;
    r->mine = urwire__package_form_table.mine + row;
    r->first_sizes = urwire__package_first_sizes + row;
}

static void urwire__start(urwire__running *r, urwire_sw_version version)
{
    urwire__run_at(r, version);
    r->implied = false;
}

/* The form of a sub-package of type `type` (which has a layout) and body `size` that is not
 * simply the version's own, and the version to read it with. */
static const urwire__form *urwire__other_form(uint8_t type, size_t size, urwire__running *r, urwire__ver *use)
{
    urwire_sw_version v = r->now.version;
    bool by_length;
    const urwire__form *f = urwire__choose(&urwire__package_form_table, type, r->segment, size, &v, &by_length);
    /* urwire__choose changes the version when a form is chosen by length, or when the version
     * has no form of its own (the nearest form below, read as the version it stands for). */
    if (urwire__version_key(v) != r->now.key) {  /* field by field, as in urwire__run_at */
        use->version = v;
        use->key = urwire__version_key(v);
    } else {
        *use = r->now;
    }
    if (!URWIRE__ONE_FORM_A_CODE && by_length && r->now.version.assumed) {
        urwire__run_at(r, v);
        r->implied = true;
    }
    return f;
}

/* The form of the sub-package of type `type` and body `size` (NULL: no layout), and the
 * version to read it with. */
URWIRE__INLINE const urwire__form *urwire__package_form(uint8_t type, size_t size, urwire__running *r, urwire__ver *use)
{
    if (type >= URWIRE__COUNT(urwire__package_forms) || urwire__package_forms[type].count == 0)
        return NULL;
    if (urwire__fits_brief(r->first_sizes[type], size)) {
        *use = r->now;
        return &urwire__package_form_list[r->mine[type] - 1];
    }
    return urwire__other_form(type, size, r, use);
}

/* Frames the sub-packages of a robot state from pos and chooses the form of each, decoding
 * none: how many framed, where framing stopped (end, or a header that cannot be framed: *err),
 * and the version the layout sizes showed. */
static bool urwire__walk_packages(const uint8_t *msg, size_t pos, size_t end, urwire__running *r, size_t *count,
                                  size_t *stop, urwire_error *err)
{
    size_t size = 0;
    urwire__ver use;
    uint8_t type;
    *count = 0;
    while (pos < end && urwire__frame_package(msg, pos, end, &size, err)) {
        type = msg[pos + URWIRE__PACKAGE_TYPE_AT];
        /* Only a body that the version's form does not fit can show another version, and only
         * where a code has several forms. */
        if (!URWIRE__ONE_FORM_A_CODE && type < URWIRE__COUNT(urwire__package_forms) &&
            !urwire__fits_brief(r->first_sizes[type], size - URWIRE_PACKAGE_HEADER_SIZE) &&
            urwire__package_forms[type].count != 0)
            urwire__other_form(type, size - URWIRE_PACKAGE_HEADER_SIZE, r, &use);
        pos += size;
        ++*count;
    }
    *stop = pos;
    return pos == end;
}

/* A robot state: frames the sub-packages by their lengths; each is decoded when iterated. */
URWIRE__NOINLINE static bool urwire__decode_packages(urwire_message *out, urwire_sw_version version)
{
    urwire__running r;
    size_t end = 0;
    urwire__start(&r, version);
    out->kind = URWIRE__PACKAGES_KIND;
    urwire__init_seq(&out->packages, out->bytes, URWIRE_HEADER_SIZE, &version, -1);
    if (!urwire__walk_packages(out->bytes, URWIRE_HEADER_SIZE, out->length, &r, &out->packages.count, &end,
                               &out->error)) {
        out->packages.end = end;
        urwire__fail_message(out, end);
        return false;  /* a list that cannot be framed implies no version */
    }
    out->packages.end = end;
    out->implied = r.implied;
    out->implied_version = r.now.version;
    return true;
}

/* The form of subtype `subtype` of type t (which has a layout) for a message of len bytes, by
 * its version and length (the Version message's by the version it carries): its kind, and the
 * version it is read in (*version, and *ver as the layouts read it). Out of line, so that its
 * locals are not on the stack under the layout's decoder. */
URWIRE__NOINLINE static urwire_message_kind urwire__layout_form(const uint8_t *bytes, size_t len,
                                                                 const urwire__message_type *t, int64_t subtype,
                                                                 urwire_sw_version *version, urwire__ver *ver)
{
    bool by_length;
    const urwire__form *f;
    if (t->code == URWIRE__VERSION_TYPE && subtype == URWIRE__VERSION_SUBTYPE)
        urwire__peek_version(bytes, len, version);
    f = urwire__choose(t->forms, (size_t)subtype, urwire__segment(urwire__version_key(*version)), len - t->body,
                       version, &by_length);
    *ver = urwire__ver_of(*version);
    return (urwire_message_kind)f->layout;
}

/* The layout of subtype `subtype` of type t (which has a layout) in the bytes after its header,
 * in the form its version and length choose (urwire__layout_form), into *as: its kind, and
 * false when it is malformed (*err set). *version becomes the version of the form it was read
 * in. */
static bool urwire__decode_layout(const uint8_t *bytes, size_t len, const urwire__message_type *t, int64_t subtype,
                                  urwire_sw_version *version, urwire_message_kind *kind, void *as, urwire_error *err)
{
    size_t pos = t->body;
    urwire__ver ver;
    *kind = urwire__layout_form(bytes, len, t, subtype, version, &ver);
    return urwire__message_decoders[*kind](bytes, &pos, len, &ver, as, err);
}

/* A Version message's layout (every form of its subtype is that layout), read as
 * urwire_decode_message reads it, for the framer: its decoder is called by its kind, a
 * constant, so that no other layout's decoder is under the framer on the stack. *version
 * becomes the version it carries; *out is a URWIRE__VERSION_LAYOUT. */
URWIRE__PRIVATE bool urwire__decode_announced(const uint8_t *bytes, size_t len, urwire_sw_version *version,
                                              void *out)
{
    const urwire__message_type *t = urwire__message_type_of(URWIRE__VERSION_TYPE);
    const urwire__decode_fn decode = urwire__message_decoders[URWIRE__VERSION_KIND];  /* NULL: no such layout */
    size_t pos = t->body;
    urwire__ver ver;
    return decode != NULL &&
           urwire__layout_form(bytes, len, t, URWIRE__VERSION_SUBTYPE, version, &ver) == URWIRE__VERSION_KIND &&
           decode(bytes, &pos, len, &ver, out, NULL);
}

/* A message with a common header and a subtype: the header, then the subtype's layout, read in
 * the version in out->version, which becomes that of its form (kept there: a copy would cost
 * every decoder's stack 16 bytes). */
static bool urwire__decode_subtype(urwire_message *out, const urwire__message_type *t)
{
    int64_t subtype;
    if (out->length < t->body) {
        out->kind = URWIRE_KIND_UNKNOWN_MESSAGE;
        urwire__short_in_run(&out->error, t->header, 0, out->length);
        urwire__fail_message(out, URWIRE_HEADER_SIZE);
        return false;
    }
    subtype = t->read_header != NULL ? t->read_header(out) : 0;  /* a body message's layout: its code 0 */
    if (subtype < 0 || (uint64_t)subtype >= t->forms->ncodes || t->forms->codes[subtype].count == 0) {
        out->kind = URWIRE_KIND_UNKNOWN_SUBTYPE;
        out->raw = urwire__view(out->bytes + t->body, out->length - t->body);
        return true;
    }
    if (!urwire__decode_layout(out->bytes, out->length, t, subtype, &out->version, &out->kind, &out->as,
                               &out->error)) {
        urwire__fail_message(out, t->body);
        return false;
    }
    return true;
}

/* The start of urwire_decode_message: *out set for a message with nothing more to decode (too
 * short for a header: failed, or of no known type), else its type. No flag goes out by address, so
 * its callers' calls after it can be tail calls, and the robot-state path keeps one frame less. */
static const urwire__message_type *urwire__message_head(const uint8_t *bytes, size_t len,
                                                         const urwire_sw_version *version,
                                                         urwire_message *out)
{
    const urwire__message_type *t;
    urwire__init_message(out, bytes, len, *version);
    if (len < URWIRE_HEADER_SIZE) {
        /* The framer never hands out such a message; a direct caller may. */
        out->kind = URWIRE_KIND_UNKNOWN_MESSAGE;
        out->message_type = 0;
        out->failed = true;
        out->raw = urwire__view(bytes, len);
        urwire__short(&out->error, URWIRE__NAME("length"), 0, URWIRE_HEADER_SIZE, len);
        return NULL;
    }
    out->message_type = bytes[URWIRE__TYPE_AT];
    t = urwire__message_type_of(out->message_type);
    if (t == NULL) {
        out->kind = URWIRE_KIND_UNKNOWN_MESSAGE;
        out->raw = urwire__view(bytes + URWIRE_HEADER_SIZE, len - URWIRE_HEADER_SIZE);
    }
    return t;
}

bool urwire_decode_message(const uint8_t *bytes, size_t len, urwire_sw_version version, urwire_message *out)
{
    const urwire__message_type *t = urwire__message_head(bytes, len, &version, out);
    if (t == NULL)
        return !out->failed;
    return t->packages ? urwire__decode_packages(out, version) : urwire__decode_subtype(out, t);
}

/* The sub-packages of a robot state from pos by the general rule (the version's form when its
 * brief fits the body, else the one form of its exact size, else the nearest), each decoded
 * straight into its member of *out, until end or a header that cannot be framed (*err): where
 * it stopped. One loop for the whole message, so that the work per sub-package is only its
 * own; a fast path calls it for one sub-package it has no case for (urwire__decode_member is
 * inlined here, and only here). */
static size_t urwire__decode_general(const uint8_t *msg, size_t pos, size_t end, urwire__running *r,
                                     urwire_robot_state *out, size_t *count, urwire_error *err)
{
    urwire__ver other;
    const urwire__ver *use;
    /* The segment's rows, held here: the stores into *out could alias them in r. */
    const uint8_t *mine = r->mine;
    const uint32_t *first_sizes = r->first_sizes;
    size_t size = 0, body, n = 0;
    uint8_t type, form;
    /* One pass: framing each sub-package and decoding it overlap in the CPU. */
    for (; pos < end && urwire__frame_next_package(msg, pos, end, &size, err); pos += size, n++) {
        type = msg[pos + URWIRE__PACKAGE_TYPE_AT];
        body = pos + URWIRE_PACKAGE_HEADER_SIZE;
        use = &r->now;
        /* The common case, laid out straight: the version's form, which fits the body by its brief. */
        form = URWIRE__LIKELY(type < URWIRE__COUNT(urwire__package_forms) &&
                              urwire__fits_brief(first_sizes[type], size - URWIRE_PACKAGE_HEADER_SIZE))
                   ? mine[type]
                   : 0;
        if (URWIRE__UNLIKELY(form == 0)) {
            if (type >= URWIRE__COUNT(urwire__package_forms) || urwire__package_forms[type].count == 0) {
                out->unknown++;
                continue;
            }
            form = (uint8_t)(urwire__other_form(type, size - URWIRE_PACKAGE_HEADER_SIZE, r, &other) -
                             urwire__package_form_list + 1);
            use = &other;
            mine = r->mine;
            first_sizes = r->first_sizes;
        }
        if (urwire__decode_member(type, form, msg, &body, pos + size, use, out, NULL))
            out->present |= (uint32_t)URWIRE_BIT(type);
        else
            out->malformed |= (uint32_t)URWIRE_BIT(type);
    }
    *count += n;
    return pos;
}

/* The sub-packages of a robot state from pos in fast path `path` (a constant: the loop is
 * written out for each path, with its cases inlined): a type with a case there and a body of
 * its size costs one switch and one compare. Any other sub-package is read by the general rule,
 * and the loop goes on while the stream's version still takes this path (a form chosen by its
 * length may imply another). It stops before a header that cannot be framed, for
 * urwire__decode_general to report. The bits it gathers are kept in registers and or-ed into
 * *out at the end: a store less per sub-package. */
URWIRE__INLINE size_t urwire__decode_fast(int path, const uint8_t *msg, size_t pos, size_t end, urwire__running *r,
                                          urwire_robot_state *out, size_t *count)
{
    urwire__fast_bits bits = {0, 0, 0};
    size_t size = 0, at, n = 0, one = 0;
    uint8_t type;
    for (; end - pos >= URWIRE_PACKAGE_HEADER_SIZE; pos += size, n++) {
        /* A length below the header's size wraps around and fails the one test as well. */
        size = (size_t)URWIRE__PACKAGE_LENGTH(msg + pos);
        if (URWIRE__UNLIKELY(size - URWIRE_PACKAGE_HEADER_SIZE > end - pos - URWIRE_PACKAGE_HEADER_SIZE))
            break;
        at = pos + URWIRE_PACKAGE_HEADER_SIZE;
        type = msg[pos + URWIRE__PACKAGE_TYPE_AT];
        if (URWIRE__LIKELY(urwire__fast_member(path, type, size - URWIRE_PACKAGE_HEADER_SIZE, msg, &at, pos + size,
                                               &r->now, out, &bits, NULL)))
            continue;
        if (type >= URWIRE__COUNT(urwire__package_forms) || urwire__package_forms[type].count == 0) {
            out->unknown++;  /* no layout in any version */
            continue;
        }
        urwire__decode_general(msg, pos, pos + size, r, out, &one, NULL);
        if (urwire__package_fast_paths[r->segment] != path) {
            pos += size;
            n++;
            break;
        }
    }
    out->present |= bits.present;
    out->malformed |= bits.malformed;
    out->layouts |= bits.layouts;
    *count += n;
    return pos;
}

/* Frames the sub-packages of a robot state from pos and decodes each straight into its member
 * of *out, until end or a header that cannot be framed (*err): where it stopped. The fast path
 * of the version's segment, if it has one, goes as far as it can; the general rule does the
 * rest. A build with URWIRE_NO_FAST_PATHS (-DURWIRE_NO_FAST_PATHS) has no fast path, and the
 * general rule does it all, to the same result: a firmware then links one copy of the switch
 * over sub-package types, not two (1 KB of flash on Cortex-M4 for the robot-state firmware). */
static size_t urwire__decode_into_state(const uint8_t *msg, size_t pos, size_t end, urwire__running *r,
                                        urwire_robot_state *out, size_t *count, urwire_error *err)
{
    out->present = 0;
    out->malformed = 0;
    out->layouts = 0;
    out->unknown = 0;
    *count = 0;
#if defined(URWIRE_NO_FAST_PATHS)
    (void)urwire__package_fast_paths;  /* no fast path reads it */
#else
#define URWIRE__FAST_CASE(k)                                         \
    case k:                                                          \
        pos = urwire__decode_fast(k, msg, pos, end, r, out, count); \
        break;
    switch (urwire__package_fast_paths[r->segment]) {
        URWIRE__FAST_PATHS(URWIRE__FAST_CASE)
    default:
        break;
    }
#undef URWIRE__FAST_CASE
#endif
    return pos < end ? urwire__decode_general(msg, pos, end, r, out, count, err) : pos;
}

/* The next sub-package of seq decoded into *as, and why it could not be (*err, reset first;
 * NULL: no one reads it): its header's offset (*at), its form (*f, NULL: no layout), the version
 * it was read in (*use) and whether it failed. False at the end, seq untouched. */
URWIRE__INLINE bool urwire__next_layout(urwire_seq *seq, size_t *at, const urwire__form **f, urwire__ver *use, void *as,
                                    urwire_error *err, bool *failed)
{
    const uint8_t *msg = seq->msg;
    urwire__running r;
    size_t pos = seq->pos, body, stop;
    int64_t size;
    if (seq->count == 0 || seq->end - pos < URWIRE_PACKAGE_HEADER_SIZE)
        return false;
    size = URWIRE__PACKAGE_LENGTH(msg + pos);
    if (size < (int64_t)URWIRE_PACKAGE_HEADER_SIZE || (uint64_t)size > seq->end - pos)
        return false;  /* not reached for a seq from urwire_decode_message */
    body = pos + URWIRE_PACKAGE_HEADER_SIZE;
    stop = pos + (size_t)size;
    if (err != NULL)
        err->status = URWIRE_OK;
    urwire__start(&r, seq->version);
    *f = urwire__package_form(msg[pos + URWIRE__PACKAGE_TYPE_AT], stop - body, &r, use);
    if (*f == NULL)
        use->version = seq->version;
    *failed = *f != NULL && !urwire__decode_package((uint8_t)(*f - urwire__package_form_list + 1), msg, &body, stop,
                                                    use, as, err);
    *at = pos;
    seq->version = r.now.version;  /* the version the layout sizes showed, for the packages after it */
    seq->pos = stop;
    seq->count--;
    return true;
}

/* urwire__next_layout out of line, for the encoder of a robot state. */
URWIRE__PRIVATE bool urwire__next_package_layout(urwire_seq *seq, size_t *at, const urwire__form **f, urwire__ver *use,
                                                 void *as, bool *failed)
{
    return urwire__next_layout(seq, at, f, use, as, NULL, failed);
}

bool urwire_next_package(urwire_seq *seq, urwire_package *out)
{
    const urwire__form *f;
    urwire__ver use;
    size_t pos;
    if (out == NULL)  /* no package to fill: none read */
        return false;
    if (!urwire__next_layout(seq, &pos, &f, &use, &out->as, &out->error, &out->failed))
        return false;
    out->type = seq->msg[pos + URWIRE__PACKAGE_TYPE_AT];
    out->offset = pos;
    out->raw = urwire__view(seq->msg + pos + URWIRE_PACKAGE_HEADER_SIZE, seq->pos - pos - URWIRE_PACKAGE_HEADER_SIZE);
    out->version = use.version;
    out->known = f != NULL;
    out->layout = f != NULL ? (urwire_package_layout)f->layout : URWIRE_LAYOUT_COUNT;
    return true;
}

bool urwire_decode_robot_state(const urwire_message *m, urwire_robot_state *out)
{
    const urwire_seq *seq = &m->packages;
    urwire__running r;
    size_t count;
    if (m->kind != URWIRE__PACKAGES_KIND) {
        out->present = 0;
        out->malformed = 0;
        out->layouts = 0;
        out->unknown = 0;
        return false;
    }
    /* The frames were checked by urwire_decode_message. */
    urwire__start(&r, seq->version);
    urwire__decode_into_state(seq->msg, seq->pos, seq->end, &r, out, &count, NULL);
    return !m->failed && out->malformed == 0;
}

/* urwire_decode_robot_state_message of a robot state: out of line, so that a message of any
 * other type is decoded without its locals on the stack. */
URWIRE__NOINLINE static bool urwire__decode_state_message(const uint8_t *bytes, size_t len, urwire_sw_version version,
                                                          urwire_message *m, urwire_robot_state *out)
{
    urwire__running r;
    size_t end;
    urwire__init_message(m, bytes, len, version);
    urwire__start(&r, version);
    m->kind = URWIRE__PACKAGES_KIND;
    urwire__init_seq(&m->packages, bytes, URWIRE_HEADER_SIZE, &version, -1);
    end = urwire__decode_into_state(bytes, URWIRE_HEADER_SIZE, len, &r, out, &m->packages.count, &m->error);
    m->packages.end = end;
    if (end < len) {
        urwire__fail_message(m, end);
    } else {
        m->implied = r.implied;
        m->implied_version = r.now.version;
    }
    return !m->failed && out->malformed == 0;
}

/* urwire_decode_robot_state_message of a message of any other type: as urwire_decode_message,
 * without its robot-state branch, which a firmware that reads robot states this way then does
 * not link; out of line, so that a robot state is decoded without its locals on the stack. */
URWIRE__NOINLINE static void urwire__decode_other_message(const uint8_t *bytes, size_t len,
                                                          const urwire_sw_version *version,
                                                          urwire_message *m)
{
    const urwire__message_type *t = urwire__message_head(bytes, len, version, m);
    if (t != NULL)
        urwire__decode_subtype(m, t);
}

bool urwire_decode_robot_state_message(const uint8_t *bytes, size_t len, urwire_sw_version version,
                                       urwire_message *m, urwire_robot_state *out)
{
    if (len < URWIRE_HEADER_SIZE || bytes[URWIRE__TYPE_AT] != URWIRE__PACKAGES_TYPE) {
        out->present = 0;
        out->malformed = 0;
        out->layouts = 0;
        out->unknown = 0;
        urwire__decode_other_message(bytes, len, &version, m);
        return false;
    }
    return urwire__decode_state_message(bytes, len, version, m, out);
}

/* Each sub-package is decoded into its layout alone: the error no one reads is not kept. */
bool urwire_message_has_error(const urwire_message *m)
{
    urwire_seq seq;
    double as[URWIRE__LAYOUT_DOUBLES];
    const urwire__form *f;
    urwire__ver use;
    size_t at;
    bool failed;
    if (m->failed)
        return true;
    if (m->kind != URWIRE__PACKAGES_KIND)
        return false;
    seq = m->packages;
    while (urwire__next_layout(&seq, &at, &f, &use, as, NULL, &failed))
        if (failed)
            return true;
    return false;
}

/* The version a robot state's layout sizes show, for a stream whose version is assumed: what
 * the framer carries on to the next message (false: they show none, or the list cannot be
 * framed). */
URWIRE__PRIVATE bool urwire__implied_version(const uint8_t *msg, size_t len, urwire_sw_version *version)
{
    urwire__running r;
    size_t count, stop;
    urwire__start(&r, *version);
    if (!urwire__walk_packages(msg, URWIRE_HEADER_SIZE, len, &r, &count, &stop, NULL) || !r.implied)
        return false;
    *version = r.now.version;
    return true;
}

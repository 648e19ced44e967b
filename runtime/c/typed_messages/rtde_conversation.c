/* ---- a connection: framing, following the setup exchanges, values, the client's messages ---- */

#define RTDE__NO_ID (-1)

static size_t rtde__recipe_size(const rtde_recipe *recipe)
{
    return recipe->size;
}

static bool rtde__values(rtde__reader *r, rtde_data *out)
{
    size_t n = rtde__recipe_size(out->recipe);
    if (!rtde__need(r, n, "values"))
        return false;
    out->bytes = r->buf + r->pos;
    r->pos += n;
    return true;
}

#define RTDE__TEXT(x) #x
#define RTDE__NUMBER(x) RTDE__TEXT(x)
#define RTDE__SETUPS_OVERFLOW "more than " RTDE__NUMBER(RTDE_MAX_PENDING) " setups awaited replies"
#define RTDE__VERSIONS_OVERFLOW "more than " RTDE__NUMBER(RTDE_MAX_PENDING_VERSIONS) \
    " protocol version requests awaited replies"
#define RTDE__UNKNOWN(request) "reply after bytes lost from the capture: its " request " is unknown"

/* Points the recipe slots and the pending names at their storage: the slots' arrays one after
 * another in each of the given arrays. */
static void rtde__place(rtde_conversation *c, const rtde_limits *limits, rtde_recipe *recipes, uint8_t *types,
                        uint16_t *offset, uint16_t *name_at, uint16_t *name_length, char *names, char *pending)
{
    size_t i, k;
    c->limits = *limits;
    c->recipes = recipes;
    c->recipes_used = 0;
    for (i = 0; i < limits->recipes; i++) {
        recipes[i].used = false;
        recipes[i].types = types + i * limits->variables;
        recipes[i].offset = offset + i * limits->variables;
        recipes[i].name_at = name_at + i * limits->variables;
        recipes[i].name_length = name_length + i * limits->variables;
        recipes[i].names = names + i * limits->names;
    }
    for (k = 0; k < 2; k++)
        for (i = 0; i < RTDE_MAX_PENDING; i++)
            c->pending[k][i].names = pending + (k * RTDE_MAX_PENDING + i) * limits->names;
    c->refused.names = pending + (size_t)(2 * RTDE_MAX_PENDING) * limits->names;
}

void rtde_conversation_init(rtde_conversation *c)
{
    rtde_limits limits;
    limits.recipes = RTDE_MAX_RECIPES;
    limits.variables = RTDE_MAX_VARIABLES;
    limits.names = RTDE_MAX_NAMES;
    memset(c, 0, sizeof *c);
    rtde__place(c, &limits, c->own.recipes, &c->own.types[0][0], &c->own.offset[0][0], &c->own.name_at[0][0],
                &c->own.name_length[0][0], &c->own.names[0][0], &c->own.pending[0][0]);
}

/* The storage's parts, each rounded up to a multiple of 16 bytes so that the next is aligned. */
static size_t rtde__round(size_t n)
{
    return RTDE__ROUND16(n);
}

size_t rtde_storage_size(const rtde_limits *limits)
{
    if (limits->recipes == 0 || limits->variables == 0 || limits->names == 0 || limits->recipes > RTDE_PROTOCOL_RECIPES
        || limits->variables > RTDE_PROTOCOL_VARIABLES || limits->names > RTDE_PROTOCOL_NAMES)
        return 0;
    return RTDE_STORAGE_SIZE(limits->recipes, limits->variables, limits->names);
}

bool rtde_conversation_init_in(rtde_conversation *c, const rtde_limits *limits, void *storage, size_t size)
{
    size_t need = rtde_storage_size(limits), slots = limits->recipes * limits->variables;
    uint8_t *at = (uint8_t *)storage;
    rtde_recipe *recipes;
    uint16_t *offset, *name_at, *name_length;
    uint8_t *types;
    char *names;
    if (need == 0 || size < need || storage == NULL)
        return false;
    memset(c, 0, offsetof(rtde_conversation, own));
    recipes = (rtde_recipe *)(void *)at;
    at += rtde__round(limits->recipes * sizeof(rtde_recipe));
    offset = (uint16_t *)(void *)at;
    at += rtde__round(slots * sizeof(uint16_t));
    name_at = (uint16_t *)(void *)at;
    at += rtde__round(slots * sizeof(uint16_t));
    name_length = (uint16_t *)(void *)at;
    at += rtde__round(slots * sizeof(uint16_t));
    types = at;
    at += rtde__round(slots);
    names = (char *)at;
    at += rtde__round(limits->recipes * limits->names);
    rtde__place(c, limits, recipes, types, offset, name_at, name_length, names, (char *)at);
    return true;
}

uint8_t rtde_protocol_in_force(const rtde_conversation *c)
{
    return c->protocol ? c->protocol : RTDE_DEFAULT_PROTOCOL;
}

/* One queue of requests after bytes lost (text_lines.py's Pending, for the Python decoder): its
 * count of requests kept and not kept, and whether its pairing is unknown from here on. */
static void rtde__queue_lost(bool from_robot, uint8_t *count, uint64_t lost, bool *unknown)
{
    if (!from_robot) {
        *unknown = true;
    } else if (*count > 0 || lost > 0) {
        *count = 0;
        *unknown = true;
    }
}

void rtde_conversation_lost(rtde_conversation *c, bool from_robot)
{
    int kind;
    rtde__queue_lost(from_robot, &c->asked_count, c->asked_lost, &c->asked_unknown);
    for (kind = 0; kind < 2; kind++)
        rtde__queue_lost(from_robot, &c->pending_count[kind], c->pending_lost[kind], &c->pending_unknown[kind]);
}

static bool rtde__known_code(uint8_t code)
{
    size_t i;
    for (i = 0; i < sizeof rtde__codes; i++)
        if (rtde__codes[i] == code)
            return true;
    return false;
}

rtde_error rtde_message_size(const uint8_t *buf, size_t length, size_t *size)
{
    if (length < RTDE_HEADER_SIZE)
        return RTDE_NEED_MORE;
    *size = (size_t)urwire__uint(buf, 2);
    if (*size < RTDE_HEADER_SIZE || !rtde__known_code(buf[2]))
        return RTDE_BAD_HEADER;
    return *size > length ? RTDE_NEED_MORE : RTDE_OK;
}

const rtde_layout_info *rtde_layout_of(uint8_t layout)
{
    return layout < RTDE_LAYOUT_COUNT ? &rtde__layouts[layout] : &rtde__layouts[0];
}

const char *rtde_unlaid_name(uint8_t code)
{
    size_t i;
    for (i = 0; i < sizeof rtde__undocumented / sizeof rtde__undocumented[0]; i++)
        if (rtde__undocumented[i].code == code)
            return rtde__undocumented[i].name;
    return "unknown";
}

int rtde_value_type_of(const uint8_t *name, size_t length)
{
    int t;
    for (t = 0; t < RTDE_VT_COUNT; t++)
        if (strlen(rtde__value_type_names[t]) == length && memcmp(rtde__value_type_names[t], name, length) == 0)
            return t;
    return -1;
}

const char *rtde_value_type_name(uint8_t type)
{
    return type < RTDE_VT_COUNT ? rtde__value_type_names[type] : "";
}

static uint8_t rtde__layout_for(uint8_t code, bool from_robot, uint8_t protocol)
{
    size_t i;
    for (i = 0; i < sizeof rtde__dispatch / sizeof rtde__dispatch[0]; i++)
        if (rtde__dispatch[i].code == code && rtde__dispatch[i].from_robot == from_robot
            && rtde__dispatch[i].protocol == protocol)
            return rtde__dispatch[i].layout;
    return RTDE_LAYOUT_NONE;
}

const rtde_recipe *rtde_recipe_of(const rtde_conversation *c, bool from_robot, int id)
{
    size_t i;
    for (i = 0; i < c->recipes_used; i++)
        if (c->recipes[i].used && c->recipes[i].from_robot == from_robot && c->recipes[i].id == id)
            return &c->recipes[i];
    return NULL;
}

/* The recipe a reply replaces: gone, when the reply makes none that can be kept (its request
 * unknown or not kept, names and types differing in number, past the limits), so that its data
 * packages are not read by the old one. A refusal sets up nothing (recipe id 0) and keeps it. */
static void rtde__forget_recipe(rtde_conversation *c, bool from_robot, int id)
{
    rtde_recipe *old = (rtde_recipe *)rtde_recipe_of(c, from_robot, id);
    if (old)
        old->used = false;
}

/* The slot a new recipe of this direction and id goes in: the one it replaces, or a free one. */
static rtde_recipe *rtde__recipe_slot(rtde_conversation *c, bool from_robot, int id)
{
    rtde_recipe *slot = (rtde_recipe *)rtde_recipe_of(c, from_robot, id);
    size_t i;
    if (slot)
        return slot;
    for (i = 0; i < c->recipes_used; i++)
        if (!c->recipes[i].used)
            return &c->recipes[i];
    return c->recipes_used < c->limits.recipes ? &c->recipes[c->recipes_used++] : NULL;
}

/* The next name of a comma-separated list at *at (advanced past it and its comma). */
static bool rtde__next_name(const uint8_t *list, size_t length, size_t *at, size_t *start, size_t *n)
{
    size_t i;
    if (*at > length || length == 0)
        return false;
    *start = *at;
    for (i = *at; i < length && list[i] != ','; i++)
        ;
    *n = i - *at;
    *at = i + 1;
    return true;
}

static bool rtde__is_refusal(const uint8_t *word, size_t n)
{
    size_t i;
    for (i = 0; i < sizeof rtde__refusals / sizeof rtde__refusals[0]; i++)
        if (strlen(rtde__refusals[i]) == n && memcmp(rtde__refusals[i], word, n) == 0)
            return true;
    return rtde_value_type_of(word, n) < 0;
}

/* The oldest setup request of a kind, taken for its reply: it becomes c->refused (the view's home),
 * and c->refused's buffer goes to the queue's end for a later request. */
static void rtde__take_request(rtde_conversation *c, int kind)
{
    char *spare = c->refused.names;
    size_t i;
    c->refused = c->pending[kind][0];
    for (i = 1; i < c->pending_count[kind]; i++)
        c->pending[kind][i - 1] = c->pending[kind][i];
    c->pending_count[kind]--;
    c->pending[kind][c->pending_count[kind]].names = spare;
}

/* A reply's types against its request's names: a recipe, or the refusal noted on the message. */
static rtde_error rtde__make_recipe(rtde_conversation *c, int kind, rtde_text types, int id, rtde_message *m)
{
    const uint8_t *names;
    rtde_recipe *recipe = NULL;
    size_t at_names, at_types, s1, n1, s2, n2, count = 0, size = 0, pass;
    bool refused = false, from_robot = kind == 0;
    if (c->pending_count[kind] == 0) {
        if (c->pending_unknown[kind]) {     /* bytes lost may have held its request, or answered it */
            m->error = RTDE__UNKNOWN("setup");
            rtde__forget_recipe(c, from_robot, id);
            return RTDE_OK;
        }
        if (c->pending_lost[kind] > 0) {    /* its request was not kept: its names are unknown */
            c->pending_lost[kind]--;
            m->error = "reply to a setup that was not kept: " RTDE__SETUPS_OVERFLOW;
            rtde__forget_recipe(c, from_robot, id);
            return RTDE_OK;
        }
        m->warning = "a setup reply without a request seen: its recipe's names are unknown";
        rtde__forget_recipe(c, from_robot, id);
        return RTDE_OK;
    }
    rtde__take_request(c, kind);
    if (c->refused.length == RTDE_NAMES_NOT_KEPT) {    /* longer than this connection keeps */
        c->refused.length = 0;
        rtde__forget_recipe(c, from_robot, id);
        return RTDE_TOO_MANY;
    }
    names = (const uint8_t *)c->refused.names;
    m->request_names.data = names;
    m->request_names.length = c->refused.length;
    /* Pass 0 checks the pairs (their numbers, refusals, the limit); pass 1 writes the recipe. */
    for (pass = 0; pass < 2; pass++) {
        at_names = at_types = 0;
        count = size = 0;
        if (pass == 1) {
            recipe = rtde__recipe_slot(c, from_robot, id);
            if (recipe == NULL)
                return RTDE_TOO_MANY;
            recipe->used = true;
            recipe->from_robot = from_robot;
            recipe->id = (int16_t)id;
            memcpy(recipe->names, names, c->refused.length);
        }
        for (;;) {
            bool more_names = rtde__next_name(names, c->refused.length, &at_names, &s1, &n1);
            bool more_types;
            int t;
            while (more_names && n1 == 0)           /* an empty name names no variable */
                more_names = rtde__next_name(names, c->refused.length, &at_names, &s1, &n1);
            more_types = rtde__next_name(types.data, types.length, &at_types, &s2, &n2);
            if (!more_names || !more_types) {
                if (more_names != more_types) {
                    m->warning = "names asked and types answered differ in number";
                    rtde__forget_recipe(c, from_robot, id);
                    return RTDE_OK;
                }
                break;
            }
            if (rtde__is_refusal(types.data + s2, n2)) {
                refused = true;
                continue;
            }
            t = rtde_value_type_of(types.data + s2, n2);
            if (recipe != NULL) {
                recipe->types[count] = (uint8_t)t;
                /* Past 65535 bytes no data package fits a message: such a recipe is never read. */
                recipe->offset[count] = (uint16_t)(size <= 0xffffu ? size : 0xffffu);
                recipe->name_at[count] = (uint16_t)s1;
                recipe->name_length[count] = (uint16_t)n1;
            }
            count++;
            size += rtde__value_types[t].value_size;
        }
        if (refused) {
            m->refused = true;
            return RTDE_OK;
        }
        if (count > c->limits.variables) {
            rtde__forget_recipe(c, from_robot, id);
            return RTDE_TOO_MANY;
        }
    }
    if (recipe != NULL) {
        recipe->count = count;
        recipe->size = size;
    }
    return RTDE_OK;
}

/* Whether the spec lays out any message in this protocol version. */
static bool rtde__protocol_has_layouts(uint16_t protocol)
{
    size_t i;
    for (i = 0; i < sizeof rtde__dispatch / sizeof rtde__dispatch[0]; i++)
        if (rtde__dispatch[i].protocol == protocol)
            return true;
    return false;
}

/* Decimal digits of n at out; returns the position after them. */
static char *rtde__put_number(char *out, unsigned n)
{
    char digits[10];
    size_t k = 0;
    do {
        digits[k++] = (char)('0' + n % 10u);
        n /= 10u;
    } while (n);
    while (k)
        *out++ = digits[--k];
    return out;
}

static char *rtde__put_text(char *out, const char *text)
{
    size_t n = strlen(text);
    memcpy(out, text, n);
    return out + n;
}

/* A protocol version reply: only a version with layouts is taken (a robot accepting 0 or 300
 * leaves the one in force, and its reply says so). */
static void rtde__version_reply(rtde_conversation *c, rtde_message *m)
{
    bool any = c->asked_count > 0, accepted = m->u.request_protocol_version_reply.accepted != 0;
    uint16_t asked = c->asked[0];
    if (any) {
        memmove(c->asked, c->asked + 1, sizeof c->asked - sizeof c->asked[0]);
        c->asked_count--;
    } else if (c->asked_unknown) {
        m->error = RTDE__UNKNOWN("protocol version request");
    } else if (c->asked_lost > 0) {
        c->asked_lost--;
        m->error = "reply to a protocol version request that was not kept: " RTDE__VERSIONS_OVERFLOW;
    }
    if (accepted && any) {
        if (rtde__protocol_has_layouts(asked)) {
            c->protocol = (uint8_t)asked;
        } else {
            char *p = rtde__put_text(c->said, "protocol version ");
            p = rtde__put_number(p, asked);
            p = rtde__put_text(p, " accepted, which has no layouts: protocol ");
            p = rtde__put_number(p, rtde_protocol_in_force(c));
            p = rtde__put_text(p, " stays in force");
            *p = '\0';
            m->error = c->said;
        }
    } else if (!accepted && c->protocol == 0) {
        c->protocol = 1;                    /* the robot keeps protocol 1 until one is accepted */
    }
}

/* What a message changes in the connection. */
static rtde_error rtde__follow(rtde_conversation *c, rtde_message *m)
{
    uint8_t layout = m->layout;
    if (layout == RTDE_LAYOUT_REQUEST_PROTOCOL_VERSION) {
        if (c->asked_unknown)               /* kept by none after bytes lost: its reply says why */
            return RTDE_OK;
        if (c->asked_lost > 0 || c->asked_count == RTDE_MAX_PENDING_VERSIONS) {
            c->asked_lost++;                /* not kept: its reply will say so */
            m->error = "protocol version request not kept: " RTDE__VERSIONS_OVERFLOW;
        } else {
            c->asked[c->asked_count++] = m->u.request_protocol_version.protocol_version;
        }
    } else if (layout == RTDE_LAYOUT_REQUEST_PROTOCOL_VERSION_REPLY) {
        rtde__version_reply(c, m);
    } else if (rtde__roles[layout].request_kind >= 0) {
        int kind = rtde__roles[layout].request_kind;
        const rtde_text *names = layout == RTDE_LAYOUT_SETUP_OUTPUTS ? &m->u.setup_outputs.variables
                               : layout == RTDE_LAYOUT_SETUP_OUTPUTS_V1 ? &m->u.setup_outputs_v1.variables
                               : &m->u.setup_inputs.variables;
        rtde_pending *slot;
        if (c->pending_unknown[kind])       /* kept by none after bytes lost: its reply says why */
            return RTDE_OK;
        if (c->pending_lost[kind] > 0 || c->pending_count[kind] == RTDE_MAX_PENDING) {
            c->pending_lost[kind]++;        /* not kept: its reply will say so */
            m->error = "setup not kept: " RTDE__SETUPS_OVERFLOW;
            return RTDE_OK;
        }
        slot = &c->pending[kind][c->pending_count[kind]++];
        if (names->length > c->limits.names) {
            slot->length = RTDE_NAMES_NOT_KEPT;     /* kept in its place, so that its reply finds it */
            return RTDE_TOO_MANY;
        }
        slot->length = names->length;
        memcpy(slot->names, names->data, names->length);
    } else if (layout == RTDE_LAYOUT_SETUP_OUTPUTS_REPLY) {
        return rtde__make_recipe(c, 0, m->u.setup_outputs_reply.types, m->u.setup_outputs_reply.recipe_id, m);
    } else if (layout == RTDE_LAYOUT_SETUP_OUTPUTS_REPLY_V1) {
        return rtde__make_recipe(c, 0, m->u.setup_outputs_reply_v1.types, RTDE__NO_ID, m);
    } else if (layout == RTDE_LAYOUT_SETUP_INPUTS_REPLY) {
        return rtde__make_recipe(c, 1, m->u.setup_inputs_reply.types, m->u.setup_inputs_reply.recipe_id, m);
    } else if (layout == RTDE_LAYOUT_START_REPLY && !m->u.start_reply.accepted) {
        m->warning = "the robot refused to start";
    }
    return RTDE_OK;
}

/* A message's members outside its union, each set to nothing. Not memset of the whole message: a
 * data package, nearly every message of a connection, writes its own few members of the union, and
 * at -Os compilers clear 100 bytes with `rep stos`, which takes longer than decoding the package. */
static void rtde__clear_message(rtde_message *m, bool from_robot)
{
    m->layout = RTDE_LAYOUT_NONE;
    m->code = 0;
    m->from_robot = from_robot;
    m->warning = NULL;
    m->error = NULL;
    m->refused = false;
    m->error_field = NULL;
    m->error_need = 0;
    m->request_names.data = NULL;
    m->request_names.length = 0;
}

rtde_error rtde_decode(rtde_conversation *c, const uint8_t *msg, size_t length, bool from_robot,
                       rtde_message *out, size_t *offset)
{
    rtde__reader r;
    rtde_error e;
    size_t size;
    uint8_t layout;
    rtde__clear_message(out, from_robot);
    *offset = 0;
    e = rtde_message_size(msg, length, &size);
    if (e != RTDE_OK) {
        memset(&out->u, 0, sizeof out->u);
        return e;
    }
    out->code = msg[2];
    layout = rtde__layout_for(msg[2], from_robot, rtde_protocol_in_force(c));
    out->layout = layout;
    if (!rtde__roles[layout].is_data)     /* a data package's members are each written below */
        memset(&out->u, 0, sizeof out->u);
    if (layout == RTDE_LAYOUT_NONE)
        return RTDE_UNKNOWN_TYPE;
    r.buf = msg;
    r.pos = RTDE_HEADER_SIZE;
    r.end = size;
    r.field = "";
    r.need = 0;
    if (rtde__roles[layout].is_data) {
        /* The data member is the last of its layout, after an optional recipe id. Each member is
         * written here or by the layout's decoder: the union was not cleared. */
        int id = RTDE__NO_ID;
        const rtde_recipe *recipe;
        rtde_data *data = layout == RTDE_LAYOUT_DATA_PACKAGE ? &out->u.data_package.values
                        : layout == RTDE_LAYOUT_DATA_PACKAGE_V1 ? &out->u.data_package_v1.values
                        : &out->u.input_data_package.values;
        uint8_t *recipe_id = !rtde__roles[layout].has_recipe_id ? NULL
                           : layout == RTDE_LAYOUT_DATA_PACKAGE ? &out->u.data_package.recipe_id
                           : &out->u.input_data_package.recipe_id;
        data->recipe = NULL;
        data->bytes = NULL;                 /* until its values are there: none are read */
        if (recipe_id != NULL) {
            *recipe_id = 0;
            if (size <= RTDE_HEADER_SIZE) {     /* no id to look up: no recipe */
                *offset = RTDE_HEADER_SIZE;
                return RTDE_UNKNOWN_RECIPE;
            }
            id = msg[RTDE_HEADER_SIZE];
        }
        recipe = rtde_recipe_of(c, from_robot, id);
        if (recipe == NULL) {
            if (recipe_id != NULL)
                *recipe_id = (uint8_t)id;
            *offset = RTDE_HEADER_SIZE;
            return RTDE_UNKNOWN_RECIPE;
        }
        data->recipe = recipe;
    }
    e = rtde__decode_layout(layout, &r, out);
    if (e != RTDE_OK) {
        *offset = r.pos;
        out->error_field = r.field;
        out->error_need = r.need;
        return e;
    }
    return rtde__follow(c, out);
}

size_t rtde_data_count(const rtde_data *d)
{
    return d->recipe ? d->recipe->count : 0;
}

rtde_text rtde_data_name(const rtde_data *d, size_t index)
{
    rtde_text t = {NULL, 0};
    if (d->recipe && index < d->recipe->count) {
        t.data = (const uint8_t *)d->recipe->names + d->recipe->name_at[index];
        t.length = d->recipe->name_length[index];
    }
    return t;
}

/* n items of 8, 4 or 1 bytes: with n and the size constants where they are inlined, each item is
 * one load and a byte swap, and the loop unrolled. */
URWIRE__INLINE void rtde__f64s(rtde_value *out, const uint8_t *p, size_t n)
{
    size_t k;
    for (k = 0; k < n; k++)
        out->item[k].f64 = urwire__f64(p + 8 * k);
}

URWIRE__INLINE void rtde__i32s(rtde_value *out, const uint8_t *p, size_t n)
{
    size_t k;
    for (k = 0; k < n; k++)
        out->item[k].i64 = rtde__as_i32(urwire__u32(p + 4 * k));
}

URWIRE__INLINE void rtde__u32s(rtde_value *out, const uint8_t *p, size_t n)
{
    size_t k;
    for (k = 0; k < n; k++)
        out->item[k].u64 = urwire__u32(p + 4 * k);
}

/* A value's items, each type's by loads of its fixed size and count (the value type table's). */
URWIRE__INLINE void rtde__items(rtde_value *out, const uint8_t *p, uint8_t type)
{
    switch (type) {
    case RTDE_VT_BOOL: case RTDE_VT_UINT8: out->item[0].u64 = p[0]; break;
    case RTDE_VT_UINT32: rtde__u32s(out, p, 1); break;
    case RTDE_VT_UINT64: out->item[0].u64 = urwire__u64(p); break;
    case RTDE_VT_INT32: rtde__i32s(out, p, 1); break;
    case RTDE_VT_DOUBLE: rtde__f64s(out, p, 1); break;
    case RTDE_VT_VECTOR3D: rtde__f64s(out, p, 3); break;
    case RTDE_VT_VECTOR6D: rtde__f64s(out, p, 6); break;
    case RTDE_VT_VECTOR6INT32: rtde__i32s(out, p, 6); break;
    default: rtde__u32s(out, p, 6); break;
    }
}

/* The value at an index of a recipe (checked by the caller), its values at bytes. */
URWIRE__INLINE void rtde__value_at(const rtde_recipe *recipe, const uint8_t *bytes, size_t index, rtde_value *out)
{
    uint8_t t = recipe->types[index];
    out->type = t;
    out->count = rtde__value_types[t].count;
    rtde__items(out, bytes + recipe->offset[index], t);
}

bool rtde_data_value(const rtde_data *d, size_t index, rtde_value *out)
{
    if (!d->recipe || !d->bytes || index >= d->recipe->count)
        return false;
    rtde__value_at(d->recipe, d->bytes, index, out);
    return true;
}

bool rtde_data_values(const rtde_data *d, const size_t *indexes, size_t count, rtde_value *out)
{
    size_t i;
    if (!d->recipe || !d->bytes)
        return false;
    for (i = 0; i < count; i++) {
        if (indexes[i] >= d->recipe->count)
            return false;
        rtde__value_at(d->recipe, d->bytes, indexes[i], &out[i]);
    }
    return true;
}

size_t rtde_recipe_index(const rtde_recipe *recipe, const char *name)
{
    size_t i, n = strlen(name);
    for (i = 0; recipe && i < recipe->count; i++)
        if (recipe->name_length[i] == n && memcmp(recipe->names + recipe->name_at[i], name, n) == 0)
            return i;
    return RTDE_NO_INDEX;
}

bool rtde_data_find(const rtde_data *d, const char *name, rtde_value *out)
{
    size_t i = rtde_recipe_index(d->recipe, name);
    return i != RTDE_NO_INDEX && rtde_data_value(d, i, out);
}

/* ---- what a client sends ---- */

static size_t rtde__header(uint8_t *out, size_t cap, size_t size, uint8_t code)
{
    if (size > cap || size > 0xffffu)
        return 0;
    out[0] = (uint8_t)(size >> 8);
    out[1] = (uint8_t)(size & 0xffu);
    out[2] = code;
    return size;
}

static void rtde__store(uint8_t *p, uint64_t v, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++)
        p[i] = (uint8_t)((v >> (8 * (n - 1 - i))) & 0xffu);
}

static uint64_t rtde__f64_bits(double d)
{
    uint64_t bits;
    memcpy(&bits, &d, sizeof bits);
    return bits;
}

static size_t rtde__names_length(const char *const *names, size_t count)
{
    size_t i, n = 0;
    for (i = 0; i < count; i++)
        n += strlen(names[i]) + (i ? 1u : 0u);
    return n;
}

static void rtde__put_names(uint8_t *p, const char *const *names, size_t count)
{
    size_t i;
    for (i = 0; i < count; i++) {
        size_t n = strlen(names[i]);
        if (i)
            *p++ = ',';
        memcpy(p, names[i], n);
        p += n;
    }
}

size_t rtde_build_request_protocol_version(uint8_t *out, size_t cap, uint16_t version)
{
    if (!rtde__header(out, cap, 5, 'V'))
        return 0;
    rtde__store(out + 3, version, 2);
    return 5;
}

size_t rtde_build_get_controller_version(uint8_t *out, size_t cap)
{
    return rtde__header(out, cap, 3, 'v');
}

size_t rtde_build_setup_outputs(uint8_t *out, size_t cap, uint8_t protocol, double frequency,
                                const char *const *names, size_t count)
{
    size_t n = rtde__names_length(names, count), head = protocol == 1 ? 3u : 11u;
    if (!rtde__header(out, cap, head + n, 'O'))
        return 0;
    if (protocol != 1)
        rtde__store(out + 3, rtde__f64_bits(frequency), 8);
    rtde__put_names(out + head, names, count);
    return head + n;
}

size_t rtde_build_setup_inputs(uint8_t *out, size_t cap, const char *const *names, size_t count)
{
    size_t n = rtde__names_length(names, count);
    if (!rtde__header(out, cap, 3 + n, 'I'))
        return 0;
    rtde__put_names(out + 3, names, count);
    return 3 + n;
}

size_t rtde_build_start(uint8_t *out, size_t cap)
{
    return rtde__header(out, cap, 3, 'S');
}

size_t rtde_build_pause(uint8_t *out, size_t cap)
{
    return rtde__header(out, cap, 3, 'P');
}

size_t rtde_build_input_data(uint8_t *out, size_t cap, const rtde_recipe *recipe, const rtde_value *values)
{
    size_t size = 4u + recipe->size, i, k, at = 4;
    if (recipe->id < 0 || !rtde__header(out, cap, size, 'U'))
        return 0;
    out[3] = (uint8_t)recipe->id;
    for (i = 0; i < recipe->count; i++) {
        uint8_t t = recipe->types[i];
        size_t n = rtde__value_types[t].size;
        for (k = 0; k < rtde__value_types[t].count; k++) {
            uint64_t v = rtde__value_types[t].kind == 'f' ? rtde__f64_bits(values[i].item[k].f64)
                       : rtde__value_types[t].kind == 'i' ? (uint64_t)values[i].item[k].i64
                       : values[i].item[k].u64;
            rtde__store(out + at, v, n);
            at += n;
        }
    }
    return size;
}

const char *rtde_error_text(rtde_error e)
{
    switch (e) {
    case RTDE_OK: return "ok";
    case RTDE_NEED_MORE: return "needs more bytes";
    case RTDE_BAD_HEADER: return "bad message header";
    case RTDE_SHORT: return "message shorter than its layout";
    case RTDE_EXTRA: return "bytes after the layout";
    case RTDE_UNKNOWN_TYPE: return "no layout for this type";
    case RTDE_UNKNOWN_RECIPE: return "data package of a recipe this connection did not set up";
    case RTDE_TOO_MANY: return "more names, variables or recipes than this decoder's limits hold";
    case RTDE_NO_ROOM: return "output buffer too small";
    }
    return "unknown error";
}

/* RTDE's state of one conversation: the protocol version negotiated, the setup requests waiting
 * for their replies, and the recipes the replies make, per recipe kind (one kind per direction of
 * data packages). runtime/epan/typed_messages/rtde_dissect.c keeps one per conversation in wmem_file_scope() and
 * calls rtde_follow on each whole message, in capture order, on the first pass: the rules of
 * runtime/lua/typed_messages/state.lua, so that both dissectors show the same.
 *
 * Each protocol version and recipe keeps the message that set it and the one it replaced, so that
 * a later pass (tshark -2, the GUI) finds what was in force at any message without the first pass
 * keeping anything per message: a conversation of data packages costs no memory per package. */

/* Where a message sits in the capture: its frame, then its place among the frame's bytes (the raw
 * offset of its first byte: a message reassembled from earlier segments has place 0, the messages
 * after it in the frame's own bytes come later), which is the order of the first pass. */
typedef struct {
    guint32 frame;
    guint32 place;
} rtde_when;

static gboolean
rtde_before(rtde_when a, rtde_when b)
{
    return a.frame < b.frame || (a.frame == b.frame && a.place < b.place);
}

/* Protocol 1's one output recipe has no id: it is kept after the 256 ids. */
#define RTDE_NO_ID 256

/* A setup request's variable names: their bytes, kept for the reply (empty names dropped). */
typedef struct {
    guint8 *text;
    guint n;
    guint *start;
    guint *length;
} rtde_request;

/* A recipe: for each value, its variable's field (-1: a name the table does not have), unit and type.
 * A recipe of n 0 and `gone` marks a reply whose names are unknown: from it on, its id has none. */
typedef struct rtde_recipe {
    rtde_when when;             /* the setup reply that made it */
    const struct rtde_recipe *previous;     /* the recipe of the same id before it */
    gboolean gone;
    guint n;
    int *field;
    const char **name;          /* " (name)" after a name the table lacks or one retyped, else NULL */
    const char **retyped;       /* what the expert says of a variable the reply types otherwise, else NULL */
    const char **unit;
    const rtde_variable **variable;     /* its row of the variable table (its flags); NULL for none or retyped */
    guint8 *type;
    guint size;                 /* the bytes of all its values */
} rtde_recipe;

/* A protocol version a version exchange set. */
typedef struct rtde_protocol_change {
    rtde_when when;
    guint protocol;
    const struct rtde_protocol_change *previous;
} rtde_protocol_change;

typedef struct {
    const rtde_protocol_change *protocol;   /* the newest, NULL before any exchange */
    guint asked[RTDE_MAX_PENDING_VERSIONS]; /* protocol versions requested, awaiting their replies */
    guint asked_first, asked_count;
    guint64 asked_lost;         /* requests not kept (the queue was full), awaiting replies */
    rtde_request *pending[RTDE_N_KINDS][RTDE_MAX_PENDING_SETUPS];
    guint pending_first[RTDE_N_KINDS];
    guint pending_count[RTDE_N_KINDS];
    guint64 pending_lost[RTDE_N_KINDS];
    rtde_recipe *recipes[RTDE_N_KINDS][RTDE_NO_ID + 1];
    struct rtde_exchanges *exchanges;       /* request/response links: rtde_exchanges.c */
} rtde_state;

#define RTDE_TEXT(x) #x
#define RTDE_NUMBER(x) RTDE_TEXT(x)
#define RTDE_SETUPS_OVERFLOW "more than " RTDE_NUMBER(RTDE_MAX_PENDING_SETUPS) " setups awaited replies"
#define RTDE_VERSIONS_OVERFLOW "more than " RTDE_NUMBER(RTDE_MAX_PENDING_VERSIONS) \
    " protocol version requests awaited replies"

/* The fields of one message that the state reads, as its steps found them; texts as the Lua
 * dissector reads them (rtde_text_of). */
typedef struct {
    guint32 protocol_version;
    guint32 accepted;
    int recipe_id;              /* -1: the layout has none */
    const guint8 *variables;
    guint variables_length;
    const guint8 *types;
    guint types_length;
} rtde_values;

/* What a message changed that the dissector shows: a warning, the variables a setup refused
 * ("name: WORD" each) or types otherwise than the table, a request not kept or the reply to one,
 * a protocol version accepted that has no layouts, and the request whose names a setup reply's
 * types answer, one for one. */
typedef struct {
    const char *warning;
    guint n_refused;
    char **refused;
    guint n_retyped;
    const char **retyped;
    const char *not_kept;
    const char *protocol_error;
    const rtde_request *request;
} rtde_notes;

static rtde_state *
rtde_state_new(void)
{
    return wmem_new0(wmem_file_scope(), rtde_state);
}

/* The protocol version in force before a message: negotiated, or (assumed) the spec's default for
 * a capture that starts later. */
static guint
rtde_protocol_at(const rtde_state *state, rtde_when when, gboolean *assumed)
{
    const rtde_protocol_change *change = state->protocol;
    while (change && !rtde_before(change->when, when))
        change = change->previous;
    *assumed = change == NULL;
    return change ? change->protocol : RTDE_DEFAULT_PROTOCOL;
}

static void
rtde_set_protocol(rtde_state *state, rtde_when when, guint protocol)
{
    rtde_protocol_change *change = wmem_new(wmem_file_scope(), rtde_protocol_change);
    change->when = when;
    change->protocol = protocol;
    change->previous = state->protocol;
    state->protocol = change;
}

/* The pieces of "a,b,c" between commas ("" has none): how many, and (when start is given) where. */
static guint
rtde_split(const guint8 *text, guint length, guint *start, guint *piece_length)
{
    guint n = 0, at = 0, i;
    if (length == 0)
        return 0;
    for (i = 0; i <= length; i++) {
        if (i == length || text[i] == ',') {
            if (start) {
                start[n] = at;
                piece_length[n] = i - at;
            }
            n++;
            at = i + 1;
        }
    }
    return n;
}

static gboolean
rtde_same(const guint8 *bytes, guint length, const char *word)
{
    return strlen(word) == length && memcmp(bytes, word, length) == 0;
}

/* The value type a reply names, or -1 for a refusal or a word that is no type. */
static int
rtde_value_type_named(const guint8 *bytes, guint length)
{
    guint i;
    for (i = 0; i < G_N_ELEMENTS(rtde_refusals); i++)
        if (rtde_same(bytes, length, rtde_refusals[i]))
            return -1;
    for (i = 0; i < G_N_ELEMENTS(rtde_value_types); i++)
        if (rtde_same(bytes, length, rtde_value_types[i].name))
            return (int)i;
    return -1;
}

/* The entry of a variable name: a binary search of the sorted table. */
static const rtde_variable *
rtde_variable_named(const guint8 *bytes, guint length)
{
    guint low = 0, high = G_N_ELEMENTS(rtde_variables);
    while (low < high) {
        guint mid = low + (high - low) / 2;
        const char *name = rtde_variables[mid].name;
        size_t name_length = strlen(name);
        int order = memcmp(bytes, name, MIN(length, name_length));
        if (order == 0)
            order = length < name_length ? -1 : (length > name_length ? 1 : 0);
        if (order == 0)
            return &rtde_variables[mid];
        if (order < 0)
            high = mid;
        else
            low = mid + 1;
    }
    return NULL;
}

/* The recipe in force before a data package, by its direction and id (-1: protocol 1's, which has none). */
static const rtde_recipe *
rtde_recipe_at(const rtde_state *state, gboolean from_robot, int recipe_id, rtde_when when)
{
    const rtde_recipe *recipe = state->recipes[rtde_data_kind[from_robot ? 1 : 0]][recipe_id < 0 ? RTDE_NO_ID
                                                                                                  : recipe_id];
    while (recipe && !rtde_before(recipe->when, when))
        recipe = recipe->previous;
    return recipe && !recipe->gone ? recipe : NULL;
}

static void
rtde_keep_recipe(rtde_state *state, int kind, int recipe_id, rtde_recipe *recipe)
{
    recipe->previous = state->recipes[kind][recipe_id < 0 ? RTDE_NO_ID : recipe_id];
    state->recipes[kind][recipe_id < 0 ? RTDE_NO_ID : recipe_id] = recipe;
}

static void
rtde_remember_request(rtde_state *state, int kind, const rtde_values *values)
{
    rtde_request *request = wmem_new0(wmem_file_scope(), rtde_request);
    guint n = rtde_split(values->variables, values->variables_length, NULL, NULL), i, kept = 0;
    guint *start = wmem_alloc_array(wmem_file_scope(), guint, n + 1);
    guint *length = wmem_alloc_array(wmem_file_scope(), guint, n + 1);
    rtde_split(values->variables, values->variables_length, start, length);
    for (i = 0; i < n; i++) {
        if (length[i] > 0) {            /* an empty name names no variable */
            start[kept] = start[i];
            length[kept] = length[i];
            kept++;
        }
    }
    request->text = (guint8 *)wmem_memdup(wmem_file_scope(), values->variables, values->variables_length);
    request->n = kept;
    request->start = start;
    request->length = length;
    state->pending[kind][(state->pending_first[kind] + state->pending_count[kind]) % RTDE_MAX_PENDING_SETUPS] = request;
    state->pending_count[kind]++;
}

/* Whether a request of this kind can be kept: not while the queue is full or a request not kept is
 * ahead of it (replies come in the order of the requests). One not kept is counted. */
static gboolean
rtde_keeps_request(rtde_state *state, int kind)
{
    if (state->pending_lost[kind] > 0 || state->pending_count[kind] >= RTDE_MAX_PENDING_SETUPS) {
        state->pending_lost[kind]++;
        return FALSE;
    }
    return TRUE;
}

static rtde_request *
rtde_take_request(rtde_state *state, int kind)
{
    rtde_request *request;
    if (state->pending_count[kind] == 0)
        return NULL;
    request = state->pending[kind][state->pending_first[kind]];
    state->pending_first[kind] = (state->pending_first[kind] + 1) % RTDE_MAX_PENDING_SETUPS;
    state->pending_count[kind]--;
    return request;
}

/* "name: WORD", of a refusal or of a type paired with its name (a NUL in either ends it, as it ends
 * any C text, and the Lua dissector's text). */
static char *
rtde_pair_text(wmem_allocator_t *scope, const rtde_request *request, guint i, const guint8 *word,
               guint word_length)
{
    guint name_length = request->length[i];
    char *text = (char *)wmem_alloc(scope, name_length + 2 + word_length + 1);
    memcpy(text, request->text + request->start[i], name_length);
    memcpy(text + name_length, ": ", 2);
    memcpy(text + name_length + 2, word, word_length);
    text[name_length + 2 + word_length] = '\0';
    return text;
}

/* " (name)", the text after the value of a variable the table lacks. */
static const char *
rtde_name_text(const rtde_request *request, guint i)
{
    guint length = request->length[i];
    char *text = (char *)wmem_alloc(wmem_file_scope(), length + 4);
    memcpy(text, " (", 2);
    memcpy(text + 2, request->text + request->start[i], length);
    memcpy(text + 2 + length, ")", 2);
    return text;
}

/* "name: REPLY by the setup reply, TABLE in the variable table", for a variable retyped. */
static const char *
rtde_retyped_text(const rtde_request *request, guint i, const rtde_value_type *reply, const rtde_value_type *table)
{
    return wmem_strdup_printf(wmem_file_scope(), "%.*s: %s by the setup reply, %s in the variable table",
                              (int)request->length[i], (const char *)request->text + request->start[i], reply->name,
                              table->name);
}

/* A reply the robot set up something with but whose recipe cannot be made (its request not kept or
 * unknown, names and types differing in number): its names are unknown, and its id has no recipe
 * from here on, rather than the one the reply replaced. A refusal sets up nothing (recipe id 0) and
 * does not come here. */
static void
rtde_forget_recipe(rtde_state *state, int kind, int recipe_id, rtde_when when)
{
    rtde_recipe *gone = wmem_new0(wmem_file_scope(), rtde_recipe);
    gone->when = when;
    gone->gone = TRUE;
    rtde_keep_recipe(state, kind, recipe_id, gone);
}

static void
rtde_make_recipe(rtde_state *state, int kind, const rtde_values *values, rtde_when when, rtde_notes *notes)
{
    rtde_request *request = rtde_take_request(state, kind);
    rtde_recipe *recipe;
    guint n, i, *start, *length;
    int *type;
    if (!request && state->pending_lost[kind] > 0) {
        state->pending_lost[kind]--;
        notes->not_kept = "reply to a setup that was not kept: " RTDE_SETUPS_OVERFLOW;
        rtde_forget_recipe(state, kind, values->recipe_id, when);
        return;
    }
    if (!request) {
        notes->warning = "a setup reply without a request seen: its recipe's names are unknown";
        rtde_forget_recipe(state, kind, values->recipe_id, when);
        return;
    }
    n = rtde_split(values->types, values->types_length, NULL, NULL);
    if (n != request->n) {
        notes->warning = "names asked and types answered differ in number";
        rtde_forget_recipe(state, kind, values->recipe_id, when);
        return;
    }
    notes->request = request;
    start = wmem_alloc_array(wmem_packet_scope(), guint, n + 1);
    length = wmem_alloc_array(wmem_packet_scope(), guint, n + 1);
    type = wmem_alloc_array(wmem_packet_scope(), int, n + 1);
    rtde_split(values->types, values->types_length, start, length);
    for (i = 0; i < n; i++) {
        type[i] = rtde_value_type_named(values->types + start[i], length[i]);
        if (type[i] < 0)
            notes->n_refused++;
    }
    if (notes->n_refused > 0) {
        guint k = 0;
        notes->refused = wmem_alloc_array(wmem_file_scope(), char *, notes->n_refused);
        for (i = 0; i < n; i++)
            if (type[i] < 0)
                notes->refused[k++] = rtde_pair_text(wmem_file_scope(), request, i, values->types + start[i],
                                                     length[i]);
        return;
    }
    recipe = wmem_new0(wmem_file_scope(), rtde_recipe);
    recipe->n = n;
    recipe->field = wmem_alloc_array(wmem_file_scope(), int, n + 1);
    recipe->unit = wmem_alloc_array(wmem_file_scope(), const char *, n + 1);
    recipe->variable = wmem_alloc_array(wmem_file_scope(), const rtde_variable *, n + 1);
    recipe->name = wmem_alloc_array(wmem_file_scope(), const char *, n + 1);
    recipe->retyped = wmem_alloc_array(wmem_file_scope(), const char *, n + 1);
    recipe->type = wmem_alloc_array(wmem_file_scope(), guint8, n + 1);
    recipe->when = when;
    notes->retyped = wmem_alloc_array(wmem_file_scope(), const char *, n + 1);
    for (i = 0; i < n; i++) {
        const rtde_value_type *vt = &rtde_value_types[type[i]];
        const rtde_variable *variable = rtde_variable_named(request->text + request->start[i], request->length[i]);
        gboolean retyped = variable && variable->type != (guint8)type[i];
        recipe->field[i] = !variable ? -1 : retyped ? vt->field : variable->field;
        recipe->unit[i] = variable && !retyped ? variable->unit : NULL;
        recipe->variable[i] = retyped ? NULL : variable;
        recipe->name[i] = variable && !retyped ? NULL : rtde_name_text(request, i);
        recipe->retyped[i] = retyped ? rtde_retyped_text(request, i, vt, &rtde_value_types[variable->type]) : NULL;
        if (retyped)
            notes->retyped[notes->n_retyped++] = recipe->retyped[i];
        recipe->type[i] = (guint8)type[i];
        recipe->size += (guint)vt->size * vt->count;
    }
    rtde_keep_recipe(state, kind, values->recipe_id, recipe);
}

/* Whether the spec lays out any message in this protocol version. */
static gboolean
rtde_protocol_has_layouts(guint protocol)
{
    guint i;
    for (i = 0; i < G_N_ELEMENTS(rtde_protocol_versions); i++)
        if (rtde_protocol_versions[i] == protocol)
            return TRUE;
    return FALSE;
}

/* A protocol version reply: only a version with layouts is taken (a robot accepting 0 or 300
 * leaves the one in force, and the reply says so). */
static void
rtde_version_reply(rtde_state *state, const rtde_values *values, rtde_when when, rtde_notes *notes)
{
    gboolean asked = state->asked_count > 0, assumed;
    guint version = asked ? state->asked[state->asked_first] : 0;
    if (asked) {
        state->asked_first = (state->asked_first + 1) % RTDE_MAX_PENDING_VERSIONS;
        state->asked_count--;
    } else if (state->asked_lost > 0) {
        state->asked_lost--;
        notes->not_kept = "reply to a protocol version request that was not kept: " RTDE_VERSIONS_OVERFLOW;
    }
    if (values->accepted != 0 && asked) {
        if (rtde_protocol_has_layouts(version))
            rtde_set_protocol(state, when, version);
        else
            notes->protocol_error = wmem_strdup_printf(wmem_file_scope(), "protocol version %u accepted, which has "
                                                       "no layouts: protocol %u stays in force", version,
                                                       rtde_protocol_at(state, when, &assumed));
    } else if (values->accepted == 0 && !state->protocol) {
        rtde_set_protocol(state, when, 1);      /* the robot keeps protocol 1 until a request is accepted */
    }
}

/* What a whole message changes, and what the dissector should show of it. */
static void
rtde_follow(rtde_state *state, const rtde_layout *layout, const rtde_values *values, rtde_when when,
            rtde_notes *notes)
{
    switch (layout->role) {
    case RTDE_ROLE_VERSION_REQUEST:
        if (state->asked_lost > 0 || state->asked_count >= RTDE_MAX_PENDING_VERSIONS) {
            state->asked_lost++;                /* not kept: its reply will say so */
            notes->not_kept = "protocol version request not kept: " RTDE_VERSIONS_OVERFLOW;
        } else {
            state->asked[(state->asked_first + state->asked_count) % RTDE_MAX_PENDING_VERSIONS] =
                values->protocol_version;
            state->asked_count++;
        }
        break;
    case RTDE_ROLE_VERSION_REPLY:
        rtde_version_reply(state, values, when, notes);
        break;
    case RTDE_ROLE_SETUP_REQUEST:
        if (rtde_keeps_request(state, layout->kind))
            rtde_remember_request(state, layout->kind, values);
        else
            notes->not_kept = "setup not kept: " RTDE_SETUPS_OVERFLOW;
        break;
    case RTDE_ROLE_SETUP_REPLY:
        rtde_make_recipe(state, layout->kind, values, when, notes);
        break;
    case RTDE_ROLE_START_REPLY:
        if (values->accepted == 0)
            notes->warning = "the robot refused to start";
        break;
    case RTDE_ROLE_NONE:
    case RTDE_ROLE_DATA:
        break;
    }
}

/* RTDE's state of one conversation: the protocol version negotiated, the setup requests waiting
 * for their replies, and the recipes the replies make, per recipe kind (one kind per direction of
 * data packages). runtime/epan/rtde_dissect.c keeps one per conversation in wmem_file_scope() and
 * calls rtde_follow on each whole message, in capture order, on the first pass: the rules of
 * runtime/lua/rtde_state.lua, so that both dissectors show the same.
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

/* A recipe: for each value, its variable's field (-1: a name the table does not have), unit and type. */
typedef struct rtde_recipe {
    rtde_when when;             /* the setup reply that made it */
    const struct rtde_recipe *previous;     /* the recipe of the same id before it */
    guint n;
    int *field;
    const char **name;          /* " (name)" after a name the table lacks, else NULL (a NUL in it ends it) */
    const char **unit;
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
    wmem_queue_t *asked;        /* protocol versions requested, awaiting their replies */
    rtde_request *pending[RTDE_N_KINDS][RTDE_MAX_PENDING_SETUPS];
    guint pending_first[RTDE_N_KINDS];
    guint pending_count[RTDE_N_KINDS];
    rtde_recipe *recipes[RTDE_N_KINDS][RTDE_NO_ID + 1];
} rtde_state;

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

/* What a message changed that the dissector shows: a warning, or the variables a setup refused
 * ("name: WORD" each). */
typedef struct {
    const char *warning;
    guint n_refused;
    char **refused;
} rtde_notes;

static rtde_state *
rtde_state_new(void)
{
    rtde_state *state = wmem_new0(wmem_file_scope(), rtde_state);
    state->asked = wmem_queue_new(wmem_file_scope());
    return state;
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
    return recipe;
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
    if (state->pending_count[kind] >= RTDE_MAX_PENDING_SETUPS) {    /* the oldest goes */
        state->pending_first[kind] = (state->pending_first[kind] + 1) % RTDE_MAX_PENDING_SETUPS;
        state->pending_count[kind]--;
    }
    state->pending[kind][(state->pending_first[kind] + state->pending_count[kind]) % RTDE_MAX_PENDING_SETUPS] = request;
    state->pending_count[kind]++;
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

/* "name: WORD" (a NUL in either ends it, as it ends any C text). */
static char *
rtde_refusal_text(const rtde_request *request, guint i, const guint8 *word, guint word_length)
{
    guint name_length = request->length[i];
    char *text = (char *)wmem_alloc(wmem_file_scope(), name_length + 2 + word_length + 1);
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

static void
rtde_make_recipe(rtde_state *state, int kind, const rtde_values *values, rtde_when when, rtde_notes *notes)
{
    rtde_request *request = rtde_take_request(state, kind);
    rtde_recipe *recipe;
    guint n, i, *start, *length;
    int *type;
    if (!request) {
        notes->warning = "a setup reply without a request seen: its recipe's names are unknown";
        return;
    }
    n = rtde_split(values->types, values->types_length, NULL, NULL);
    if (n != request->n) {
        notes->warning = "names asked and types answered differ in number";
        return;
    }
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
                notes->refused[k++] = rtde_refusal_text(request, i, values->types + start[i], length[i]);
        return;
    }
    recipe = wmem_new0(wmem_file_scope(), rtde_recipe);
    recipe->n = n;
    recipe->field = wmem_alloc_array(wmem_file_scope(), int, n + 1);
    recipe->unit = wmem_alloc_array(wmem_file_scope(), const char *, n + 1);
    recipe->name = wmem_alloc_array(wmem_file_scope(), const char *, n + 1);
    recipe->type = wmem_alloc_array(wmem_file_scope(), guint8, n + 1);
    recipe->when = when;
    for (i = 0; i < n; i++) {
        const rtde_value_type *vt = &rtde_value_types[type[i]];
        const rtde_variable *variable = rtde_variable_named(request->text + request->start[i], request->length[i]);
        recipe->field[i] = variable ? variable->field : -1;
        recipe->unit[i] = variable ? variable->unit : NULL;
        recipe->name[i] = variable ? NULL : rtde_name_text(request, i);
        recipe->type[i] = (guint8)type[i];
        recipe->size += (guint)vt->size * vt->count;
    }
    recipe->previous = state->recipes[kind][values->recipe_id < 0 ? RTDE_NO_ID : values->recipe_id];
    state->recipes[kind][values->recipe_id < 0 ? RTDE_NO_ID : values->recipe_id] = recipe;
}

/* What a whole message changes, and what the dissector should show of it. */
static void
rtde_follow(rtde_state *state, const rtde_layout *layout, const rtde_values *values, rtde_when when,
            rtde_notes *notes)
{
    switch (layout->role) {
    case RTDE_ROLE_VERSION_REQUEST:
        wmem_queue_push(state->asked, GUINT_TO_POINTER(values->protocol_version));
        break;
    case RTDE_ROLE_VERSION_REPLY: {
        gboolean asked = wmem_queue_count(state->asked) > 0;
        guint version = asked ? GPOINTER_TO_UINT(wmem_queue_pop(state->asked)) : 0;
        if (values->accepted != 0 && asked)
            rtde_set_protocol(state, when, version);
        else if (values->accepted == 0 && !state->protocol)
            rtde_set_protocol(state, when, 1);      /* the robot keeps protocol 1 until a request is accepted */
        break;
    }
    case RTDE_ROLE_SETUP_REQUEST:
        rtde_remember_request(state, layout->kind, values);
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

/* The RTDE dissector: frames the messages of a TCP stream, shows each by its layout (chosen by type
 * code, direction and the protocol version in force), a data package's values by the variables of
 * its recipe with a link to the frame that set the recipe up, each reply linked with its request
 * both ways (runtime/epan/typed_messages/rtde_exchanges.c), and expert infos for refused setups,
 * unknown recipes, a refused start and bad framing. The state (runtime/epan/typed_messages/rtde_state.c) is kept
 * per conversation on the first pass, and each message's view of it is kept for later passes and
 * the GUI. The twin of runtime/lua/typed_messages/dissect.lua: the same tree, Info column and experts.
 *
 * It frames by hand rather than with tcp_dissect_pdus: a bad header (a size below the header or a
 * type code no layout has) is shown and skipped up to the next plausible header, as the Lua
 * dissector does, where tcp_dissect_pdus would give up on the rest of the segment. */

static expert_field ei_rtde_bad_header = EI_INIT;
static expert_field ei_rtde_short = EI_INIT;
static expert_field ei_rtde_extra = EI_INIT;
static expert_field ei_rtde_refused = EI_INIT;
static expert_field ei_rtde_unknown_recipe = EI_INIT;
static expert_field ei_rtde_start_refused = EI_INIT;
static expert_field ei_rtde_setup_warning = EI_INIT;
static expert_field ei_rtde_undocumented = EI_INIT;
static expert_field ei_rtde_unknown_type = EI_INIT;
static expert_field ei_rtde_not_kept = EI_INIT;
static expert_field ei_rtde_protocol_unknown = EI_INIT;
static expert_field ei_rtde_retyped = EI_INIT;
/* The Lua twin's guard, registered alike (a message this dissector has framed is read within its
 * bytes and cannot fail). */
static expert_field ei_rtde_internal_error = EI_INIT;

static void
rtde_register_experts(int proto)
{
    static ei_register_info ei[] = {
        { &ei_rtde_bad_header, { "rtde.bad_header", PI_MALFORMED, PI_ERROR, "Bad message header", EXPFILL } },
        { &ei_rtde_short, { "rtde.short", PI_MALFORMED, PI_ERROR, "Message shorter than its layout", EXPFILL } },
        { &ei_rtde_extra, { "rtde.extra", PI_PROTOCOL, PI_WARN, "Bytes after the layout", EXPFILL } },
        { &ei_rtde_refused, { "rtde.refused", PI_RESPONSE_CODE, PI_WARN,
            "Setup refused a variable (NOT_FOUND or IN_USE)", EXPFILL } },
        { &ei_rtde_unknown_recipe, { "rtde.unknown_recipe", PI_SEQUENCE, PI_WARN,
            "Data package of a recipe this conversation did not set up", EXPFILL } },
        { &ei_rtde_start_refused, { "rtde.start_refused", PI_RESPONSE_CODE, PI_WARN, "The robot refused to start",
            EXPFILL } },
        { &ei_rtde_setup_warning, { "rtde.setup_warning", PI_SEQUENCE, PI_WARN, "Setup exchange out of order",
            EXPFILL } },
        { &ei_rtde_undocumented, { "rtde.undocumented", PI_UNDECODED, PI_NOTE, "Message type with no public layout",
            EXPFILL } },
        { &ei_rtde_unknown_type, { "rtde.unknown_type", PI_UNDECODED, PI_WARN,
            "Message type with no layout in this direction", EXPFILL } },
        { &ei_rtde_not_kept, { "rtde.not_kept", PI_SEQUENCE, PI_ERROR,
            "More requests awaited replies than a conversation keeps", EXPFILL } },
        { &ei_rtde_protocol_unknown, { "rtde.protocol_unknown", PI_PROTOCOL, PI_ERROR,
            "Accepted protocol version with no layouts", EXPFILL } },
        { &ei_rtde_retyped, { "rtde.retyped", PI_PROTOCOL, PI_WARN,
            "Setup reply types a variable otherwise than the table", EXPFILL } },
        { &ei_rtde_internal_error, { "rtde.internal_error", PI_MALFORMED, PI_ERROR, "Dissector error", EXPFILL } },
    };
    expert_register_field_array(expert_register_protocol(proto), ei, array_length(ei));
}

/* What the state says about one message: the protocol in force and a data package's recipe, found
 * in the state's history on any pass; what the message changed (its notes), kept from the first
 * pass for the others when there is something to show. */
typedef struct {
    guint protocol;
    gboolean assumed;           /* no version exchange seen: the spec's default */
    const rtde_recipe *recipe;  /* a data package's */
    const rtde_notes *notes;
} rtde_view;

static const rtde_notes rtde_no_notes = { NULL, 0, NULL, 0, NULL, NULL, NULL, NULL };

static const rtde_layout *
rtde_layout_for(guint8 code, gboolean from_robot, guint protocol)
{
    guint8 layout;
    if (protocol > RTDE_MAX_PROTOCOL)
        return NULL;
    layout = rtde_layout_of[code][from_robot ? 1 : 0][protocol];
    return layout ? &rtde_layouts[layout - 1] : NULL;
}

static const rtde_undocumented *
rtde_undocumented_for(guint8 code)
{
    guint i;
    for (i = 0; i < G_N_ELEMENTS(rtde_undocumented_types); i++)
        if (rtde_undocumented_types[i].code == code)
            return &rtde_undocumented_types[i];
    return NULL;
}

static gboolean
rtde_plausible(tvbuff_t *tvb, int at)
{
    return tvb_get_ntohs(tvb, at) >= RTDE_HEADER_SIZE && rtde_type_known[tvb_get_guint8(tvb, at + 2)];
}

/* The notes a message left on the first pass (rtde_follow), kept under its place in the frame. */
static const rtde_notes *
rtde_kept_notes(packet_info *pinfo, rtde_when when)
{
    const rtde_notes *notes = (const rtde_notes *)p_get_proto_data(wmem_file_scope(), pinfo, proto_rtde, when.place);
    return notes ? notes : &rtde_no_notes;
}

static void
rtde_keep_notes(packet_info *pinfo, rtde_when when, const rtde_notes *notes)
{
    if (notes->warning || notes->n_refused || notes->n_retyped || notes->not_kept || notes->protocol_error
        || notes->request)
        p_add_proto_data(wmem_file_scope(), pinfo, proto_rtde, when.place,
                         wmem_memdup(wmem_file_scope(), notes, sizeof *notes));
}

/* The text of n bytes as the Lua dissector reads it (TvbRange:string() in 4.0): their ASCII decoding,
 * a byte above 127 as U+FFFD, cut to n bytes, NULs kept; NUL-terminated for the C calls that show it. */
static const guint8 *
rtde_text_of(tvbuff_t *tvb, int pos, guint n)
{
    static const guint8 replacement[3] = { 0xEF, 0xBF, 0xBD };
    const guint8 *bytes = n ? tvb_get_ptr(tvb, pos, n) : NULL;
    guint8 *text = (guint8 *)wmem_alloc(wmem_packet_scope(), n + 1);
    guint in = 0, out = 0;
    while (out < n) {
        if (bytes[in] < 0x80) {
            text[out++] = bytes[in];
        } else {
            guint k;
            for (k = 0; k < 3 && out < n; k++)
                text[out++] = replacement[k];
        }
        in++;
    }
    text[n] = '\0';
    return text;
}

/* Whether an item's label may be printed: not in a tshark -T fields run, which prints values only,
 * so that the units and indexes appended below (which make Wireshark write each label at once)
 * cost nothing there. */
static gboolean
rtde_labels_shown(void)
{
    return ur_tshark_fields_arguments() == NULL;
}

/* The flags of a variable's bits, under its item. */
static void
rtde_add_flags(proto_item *item, tvbuff_t *tvb, int pos, guint size, const rtde_variable *variable)
{
    proto_tree *flags = proto_item_add_subtree(item, ett_rtde_item);
    guint k;
    for (k = 0; k < variable->n_flags; k++)
        proto_tree_add_item(flags, hf_rtde[variable->field + 1 + (int)k], tvb, pos, (int)size, ENC_BIG_ENDIAN);
}

/* A vector whose items the spec names: a subtree of one field per item, each with its unit. */
static void
rtde_add_named_items(proto_tree *tree, tvbuff_t *tvb, int pos, const rtde_value_type *vt, int field,
                     const rtde_variable *variable, gboolean labels)
{
    proto_tree *group = proto_tree_add_subtree(tree, tvb, pos, vt->size * vt->count, ett_rtde_item, NULL,
                                               variable->group);
    guint j;
    for (j = 0; j < vt->count; j++) {
        proto_item *item = proto_tree_add_item(group, hf_rtde[field + (int)j], tvb, pos + (int)(j * vt->size), vt->size,
                                               ENC_BIG_ENDIAN);
        if (labels && variable->units && variable->units[j])
            proto_item_append_text(item, "%s", variable->units[j]);
    }
}

/* A recipe's values, an item per scalar (a vector's items in order, each by the variable's field,
 * with its index). A name the variable table lacks (a newer controller's) shows its value's bytes
 * whole, with the name. A variable the setup reply types otherwise than the table is read by the
 * reply's type, under the field of that type, with its name and an expert. */
static void
rtde_add_values(proto_tree *tree, packet_info *pinfo, tvbuff_t *tvb, int pos, const rtde_recipe *recipe)
{
    guint i, j;
    gboolean labels = rtde_labels_shown();
    for (i = 0; i < recipe->n; i++) {
        const rtde_value_type *vt = &rtde_value_types[recipe->type[i]];
        if (recipe->variable[i] && recipe->variable[i]->group) {
            rtde_add_named_items(tree, tvb, pos, vt, recipe->field[i], recipe->variable[i], labels);
        } else if (recipe->field[i] < 0) {
            proto_item_append_text(proto_tree_add_item(tree, hf_rtde[RTDE_HF_UNKNOWN_VARIABLE], tvb, pos,
                                                       vt->size * vt->count, ENC_NA), "%s", recipe->name[i]);
        } else {
            for (j = 0; j < vt->count; j++) {
                proto_item *item = proto_tree_add_item(tree, hf_rtde[recipe->field[i]], tvb, pos + (int)(j * vt->size),
                                                       vt->size, ENC_BIG_ENDIAN);
                if (labels && recipe->name[i])
                    proto_item_append_text(item, "%s", recipe->name[i]);
                if (labels && recipe->unit[i])
                    proto_item_append_text(item, "%s", recipe->unit[i]);
                if (labels && vt->count > 1)
                    proto_item_append_text(item, " [%u]", j);
                if (recipe->retyped[i] && j == 0)
                    expert_add_info_format(pinfo, item, &ei_rtde_retyped, "%s", recipe->retyped[i]);
                if (recipe->variable[i] && recipe->variable[i]->n_flags)
                    rtde_add_flags(item, tvb, pos + (int)(j * vt->size), vt->size, recipe->variable[i]);
            }
        }
        pos += vt->size * vt->count;
    }
}

/* Without a tree (the expert tap, -z expert, builds none), the experts rtde_add_values adds to
 * the values of retyped variables, as the Lua twin adds them always. */
static void
rtde_retyped_experts(packet_info *pinfo, const rtde_recipe *recipe)
{
    guint i;
    for (i = 0; i < recipe->n; i++) {
        if (recipe->field[i] >= 0 && recipe->retyped[i] && rtde_value_types[recipe->type[i]].count > 0)
            expert_add_info_format(pinfo, NULL, &ei_rtde_retyped, "%s", recipe->retyped[i]);
    }
}

/* A setup reply's types, each paired with the variable the request named in its place: under the
 * types' item, on each type's bytes (split at the commas of the bytes, as the state splits them). */
static void
rtde_add_pairs(proto_item *item, tvbuff_t *tvb, int pos, int stop, const rtde_request *request)
{
    guint n = (guint)(stop > pos ? stop - pos : 0), count, i;
    guint *start, *length;
    proto_tree *tree;
    if (n == 0)
        return;
    count = rtde_split(tvb_get_ptr(tvb, pos, (gint)n), n, NULL, NULL);
    if (count != request->n)
        return;
    start = wmem_alloc_array(wmem_packet_scope(), guint, count + 1);
    length = wmem_alloc_array(wmem_packet_scope(), guint, count + 1);
    rtde_split(tvb_get_ptr(tvb, pos, (gint)n), n, start, length);
    tree = proto_item_add_subtree(item, ett_rtde_item);
    for (i = 0; i < count; i++) {
        const char *name = wmem_strndup(wmem_packet_scope(), (const char *)request->text + request->start[i],
                                        request->length[i]);
        const guint8 *type = rtde_text_of(tvb, pos + (int)start[i], length[i]);
        const char *text = rtde_pair_text(wmem_packet_scope(), request, i, type, length[i]);
        proto_item_set_generated(proto_tree_add_string_format(tree, hf_rtde[RTDE_HF_VARIABLE], tvb,
                                                              pos + (int)start[i], (int)length[i], name, "%s", text));
    }
}

/* One step of a layout: adds its items (when there is a tree) and returns the next position, or -1
 * when it does not fit; `added` is the item of a names step. */
static int
rtde_step_at(const rtde_step *s, proto_tree *tree, packet_info *pinfo, tvbuff_t *tvb, int pos, int stop,
             rtde_values *values, const rtde_view *view, proto_item **added)
{
    switch (s->kind) {
    case RTDE_STEP_SCALAR: {
        if (pos + s->size > stop)
            return -1;
        if (tree) {
            proto_item *item = proto_tree_add_item(tree, hf_rtde[s->field], tvb, pos, s->size, ENC_BIG_ENDIAN);
            if (s->unit && rtde_labels_shown())
                proto_item_append_text(item, "%s", s->unit);
        }
        if (s->integer) {
            guint32 value = s->size == 1 ? tvb_get_guint8(tvb, pos)
                          : s->size == 2 ? tvb_get_ntohs(tvb, pos) : tvb_get_ntohl(tvb, pos);
            if (s->slot == RTDE_SLOT_PROTOCOL_VERSION)
                values->protocol_version = value;
            else if (s->slot == RTDE_SLOT_ACCEPTED)
                values->accepted = value;
            else if (s->slot == RTDE_SLOT_RECIPE_ID)
                values->recipe_id = (int)value;
        }
        return pos + s->size;
    }
    case RTDE_STEP_PREFIXED_TEXT: {
        guint n;
        if (pos + s->size > stop)
            return -1;
        n = s->size == 1 ? tvb_get_guint8(tvb, pos) : tvb_get_ntohs(tvb, pos);
        if (pos + s->size + (int)n > stop)
            return -1;
        if (tree)
            proto_tree_add_string(tree, hf_rtde[s->field], tvb, pos, s->size + n,
                                  (const char *)rtde_text_of(tvb, pos + s->size, n));
        return pos + s->size + (int)n;
    }
    case RTDE_STEP_REST_TEXT:
    case RTDE_STEP_NAMES: {
        guint n = (guint)(stop > pos ? stop - pos : 0);
        if (s->slot == RTDE_SLOT_VARIABLES) {
            values->variables = rtde_text_of(tvb, pos, n);
            values->variables_length = n;
        } else if (s->slot == RTDE_SLOT_TYPES) {
            values->types = rtde_text_of(tvb, pos, n);
            values->types_length = n;
        }
        if (n)
            *added = proto_tree_add_item(tree, hf_rtde[s->field], tvb, pos, n, ENC_ASCII);
        else
            *added = proto_tree_add_string(tree, hf_rtde[s->field], tvb, pos, 0, "");
        return stop;
    }
    case RTDE_STEP_VALUES: {
        const rtde_recipe *recipe = view->recipe;
        if (pos + (int)recipe->size > stop)
            return -1;
        if (tree) {
            proto_item_set_generated(proto_tree_add_uint(tree, hf_rtde[RTDE_HF_RECIPE_FRAME], tvb, pos, 0,
                                                         recipe->when.frame));
            rtde_add_values(tree, pinfo, tvb, pos, recipe);
        } else {
            rtde_retyped_experts(pinfo, recipe);
        }
        return pos + (int)recipe->size;
    }
    }
    return -1;
}

/* One message: its items, what it changes in the state, and its label for the Info column. */
static const char *
rtde_dissect_message(tvbuff_t *tvb, packet_info *pinfo, proto_tree *tree, int offset, int size, guint8 code,
                     rtde_state *state, gboolean from_robot)
{
    int stop = offset + size, pos = offset + RTDE_HEADER_SIZE;
    proto_item *item = proto_tree_add_item(tree, proto_rtde, tvb, offset, size, ENC_NA);
    proto_tree *msg_tree = proto_item_add_subtree(item, ett_rtde);
    const rtde_layout *layout;
    rtde_values values = { 0, 0, -1, NULL, 0, NULL, 0 };
    rtde_when when = { pinfo->num, (guint32)(tvb_raw_offset(tvb) + offset) };
    gboolean first = !pinfo->fd->visited;
    rtde_view view = { 0, FALSE, NULL, &rtde_no_notes };
    rtde_notes notes = { NULL, 0, NULL, 0, NULL, NULL, NULL, NULL };
    proto_item *names_item = NULL;
    int names_pos = 0;
    guint i;

    proto_tree_add_item(msg_tree, hf_rtde[RTDE_HF_LENGTH], tvb, offset, 2, ENC_BIG_ENDIAN);
    proto_tree_add_item(msg_tree, hf_rtde[RTDE_HF_TYPE], tvb, offset + 2, 1, ENC_BIG_ENDIAN);
    if (msg_tree)
        proto_item_set_generated(proto_tree_add_string(msg_tree, hf_rtde[RTDE_HF_DIRECTION], tvb, offset + 2, 1,
                                                       from_robot ? "robot to client" : "client to robot"));
    view.protocol = rtde_protocol_at(state, when, &view.assumed);
    layout = rtde_layout_for(code, from_robot, view.protocol);
    if (msg_tree) {
        proto_item *shown = proto_tree_add_uint(msg_tree, hf_rtde[RTDE_HF_PROTOCOL], tvb, offset + 2, 1,
                                                view.protocol);
        proto_item_set_generated(shown);
        if (view.assumed)
            proto_item_append_text(shown, " (assumed: no version exchange seen)");
    }
    if (!layout) {
        const rtde_undocumented *named = rtde_undocumented_for(code);
        if (msg_tree)
            proto_item_set_generated(proto_tree_add_string(msg_tree, hf_rtde[RTDE_HF_KIND], tvb, offset + 2, 1,
                                                           named ? named->name : "unknown"));
        expert_add_info(pinfo, item, named ? &ei_rtde_undocumented : &ei_rtde_unknown_type);
        return named ? named->label : wmem_strdup_printf(wmem_packet_scope(), "Unknown type %u", code);
    }
    if (msg_tree) {
        proto_item_set_generated(proto_tree_add_string(msg_tree, hf_rtde[RTDE_HF_KIND], tvb, offset + 2, 1,
                                                       layout->name));
        proto_item_append_text(item, ": %s", layout->label);
    }
    if (first)
        rtde_follow_exchange(state, layout, pinfo, when);
    rtde_show_exchange(state, layout, msg_tree, tvb, offset + 2, when);
    if (layout->role == RTDE_ROLE_DATA) {
        gboolean has_id = layout->recipe_id_first && size > RTDE_HEADER_SIZE;
        view.recipe = rtde_recipe_at(state, from_robot, has_id ? tvb_get_guint8(tvb, pos) : -1, when);
        if (!view.recipe) {
            if (has_id)
                proto_tree_add_item(msg_tree, hf_rtde[RTDE_HF_RECIPE_ID], tvb, pos, 1, ENC_BIG_ENDIAN);
            expert_add_info(pinfo, item, &ei_rtde_unknown_recipe);
            return layout->label;
        }
    }
    for (i = 0; i < layout->n_steps; i++) {
        const rtde_step *s = &layout->steps[i];
        proto_item *added = NULL;
        int next = rtde_step_at(s, msg_tree, pinfo, tvb, pos, stop, &values, &view, &added);
        if (next < 0) {
            expert_add_info_format(pinfo, item, &ei_rtde_short, "%s at offset %d: does not fit", s->name,
                                   pos - offset);
            return layout->label;
        }
        if (s->kind == RTDE_STEP_NAMES) {
            names_item = added;
            names_pos = pos;
        }
        pos = next;
    }
    if (pos < stop)
        expert_add_info_format(pinfo, item, &ei_rtde_extra, "%d bytes after the layout", stop - pos);
    if (first) {
        rtde_follow(state, layout, &values, when, &notes);
        rtde_keep_notes(pinfo, when, &notes);
        view.notes = &notes;
    } else {
        view.notes = rtde_kept_notes(pinfo, when);
    }
    if (view.notes->request && names_item)
        rtde_add_pairs(names_item, tvb, names_pos, pos, view.notes->request);
    for (i = 0; i < view.notes->n_refused; i++)
        expert_add_info_format(pinfo, item, &ei_rtde_refused, "%s", view.notes->refused[i]);
    for (i = 0; i < view.notes->n_retyped; i++)
        expert_add_info_format(pinfo, item, &ei_rtde_retyped, "%s", view.notes->retyped[i]);
    if (view.notes->warning)
        expert_add_info_format(pinfo, item, layout->role == RTDE_ROLE_START_REPLY ? &ei_rtde_start_refused
                                                                                  : &ei_rtde_setup_warning,
                               "%s", view.notes->warning);
    if (view.notes->not_kept)
        expert_add_info_format(pinfo, item, &ei_rtde_not_kept, "%s", view.notes->not_kept);
    if (view.notes->protocol_error)
        expert_add_info_format(pinfo, item, &ei_rtde_protocol_unknown, "%s", view.notes->protocol_error);
    return layout->label;
}

static rtde_state *
rtde_conversation_state(packet_info *pinfo)
{
    conversation_t *conversation = find_or_create_conversation(pinfo);
    rtde_state *state = (rtde_state *)conversation_get_proto_data(conversation, proto_rtde);
    if (!state) {
        state = rtde_state_new();
        conversation_add_proto_data(conversation, proto_rtde, state);
    }
    return state;
}

static int
dissect_rtde(tvbuff_t *tvb, packet_info *pinfo, proto_tree *tree, void *data _U_)
{
    int len = (int)tvb_captured_length(tvb), offset = 0;
    gboolean from_robot = pinfo->srcport == pinfo->match_uint;
    rtde_state *state = rtde_conversation_state(pinfo);
    wmem_strbuf_t *info = NULL;

    col_set_str(pinfo->cinfo, COL_PROTOCOL, "RTDE");
    while (offset < len) {
        guint size;
        guint8 code;
        const char *label;
        if (len - offset < RTDE_HEADER_SIZE) {
            pinfo->desegment_offset = offset;
            pinfo->desegment_len = DESEGMENT_ONE_MORE_SEGMENT;
            break;
        }
        size = tvb_get_ntohs(tvb, offset);
        code = tvb_get_guint8(tvb, offset + 2);
        if (size < RTDE_HEADER_SIZE || size > RTDE_MAX_MESSAGE_LENGTH || !rtde_type_known[code]) {
            int at = offset + 1;
            proto_item *item;
            while (len - at >= RTDE_HEADER_SIZE && !rtde_plausible(tvb, at))
                at++;
            /* Fewer bytes than a header left: the scan ends with this segment (it is not carried
             * over, or its next part would show the same fault again). */
            if (len - at < RTDE_HEADER_SIZE)
                at = len;
            item = proto_tree_add_item(tree, proto_rtde, tvb, offset, at - offset, ENC_NA);
            expert_add_info_format(pinfo, item, &ei_rtde_bad_header, "size %u, type %u", size, code);
            label = "Bad header";
            offset = at;
        } else if ((guint)(len - offset) < size) {
            pinfo->desegment_offset = offset;
            pinfo->desegment_len = size - (guint)(len - offset);
            break;
        } else {
            label = rtde_dissect_message(tvb, pinfo, tree, offset, (int)size, code, state, from_robot);
            offset += (int)size;
        }
        if (!info)
            info = wmem_strbuf_new(wmem_packet_scope(), label);
        else {
            wmem_strbuf_append(info, ", ");
            wmem_strbuf_append(info, label);
        }
    }
    if (info)
        col_add_str(pinfo->cinfo, COL_INFO, wmem_strbuf_get_str(info));
    return len;
}

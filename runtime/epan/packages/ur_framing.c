/* Framing: split the robot's bytes into messages over TCP, reassemble the split ones, and
 * resynchronise after a bad header; client-to-robot bytes are URScript text. The loop asks TCP
 * for more bytes itself (desegment_offset/len) rather than through tcp_dissect_pdus: once a call
 * has met a bad header the rest of the stream is carried by hand until it is back in step, as
 * the Lua dissector does, so that every pass hands the same bytes and shows the same fault.
 * As runtime/lua/packages/framing.lua. */
static guint32 ur_pref_version = UR_VERSION_NONE;   /* the ur.version preference, parsed */

/* The call being dissected: the stream's version (UR_VERSION_NONE: none yet) and, when the
 * layout sizes told it, the versions of the form that did; whether the next message is the
 * call's first; whether fields are wanted; whether the Info column is built. */
typedef struct {
    guint32 version;
    const char *implied;
    gboolean first, detail, columns;
} ur_call;

/* The Info text this frame's calls have written so far (frame data in packet scope). */
#define UR_INFO_KEY 1u

/* TCP may call the dissector twice for one frame (a reassembled message, then the rest of the
 * segment): the first message of the later call appends to what the earlier one wrote, when the
 * column still holds just that. */
static void
ur_set_info(packet_info *pinfo, gboolean first, const wmem_strbuf_t *text)
{
    wmem_strbuf_t *written = (wmem_strbuf_t *)p_get_proto_data(pinfo->pool, pinfo, proto_ur, UR_INFO_KEY);
    const char *now = col_get_text(pinfo->cinfo, COL_INFO);
    gboolean same = written != NULL && now != NULL && strlen(now) == wmem_strbuf_get_len(written)
                    && memcmp(now, wmem_strbuf_get_str(written), strlen(now)) == 0;
    if (first && !same) {
        written = wmem_strbuf_new(pinfo->pool, "");
        wmem_strbuf_append_len(written, wmem_strbuf_get_str(text), wmem_strbuf_get_len(text));
        col_add_str(pinfo->cinfo, COL_INFO, wmem_strbuf_get_str(text));
        p_remove_proto_data(pinfo->pool, pinfo, proto_ur, UR_INFO_KEY);
        p_add_proto_data(pinfo->pool, pinfo, proto_ur, UR_INFO_KEY, written);
    } else {
        if (written == NULL) {
            written = wmem_strbuf_new(pinfo->pool, "");
            p_add_proto_data(pinfo->pool, pinfo, proto_ur, UR_INFO_KEY, written);
        }
        wmem_strbuf_append(written, "; ");
        wmem_strbuf_append_len(written, wmem_strbuf_get_str(text), wmem_strbuf_get_len(text));
        col_append_str(pinfo->cinfo, COL_INFO, "; ");
        col_append_str(pinfo->cinfo, COL_INFO, wmem_strbuf_get_str(text));
    }
}

static void
ur_set_info_text(packet_info *pinfo, gboolean first, const char *text)
{
    ur_set_info(pinfo, first, wmem_strbuf_new(pinfo->pool, text));
}

static gboolean
ur_plausible(tvbuff_t *tvb, int o)
{
    gint64 size = ur_int_at(tvb, o, UR_LENGTH_SIZE, TRUE);
    return size >= UR_HEADER_SIZE && size <= ur_max_length && ur_known_type[tvb_get_guint8(tvb, o + UR_LENGTH_SIZE)];
}

/* What is wrong with an implausible header at o: its expert and text. */
static expert_field *
ur_header_fault(packet_info *pinfo, tvbuff_t *tvb, int o, const char **text)
{
    gint64 size = ur_int_at(tvb, o, UR_LENGTH_SIZE, TRUE);
    if (size < UR_HEADER_SIZE) {
        *text = wmem_strdup_printf(pinfo->pool, "length %" G_GINT64_MODIFIER "d is below %d", size, UR_HEADER_SIZE);
        return &ei_ur_bad_length;
    }
    if (size > ur_max_length) {
        *text = wmem_strdup_printf(pinfo->pool, "length %" G_GINT64_MODIFIER "d is above %u", size, ur_max_length);
        return &ei_ur_bad_length;
    }
    *text = wmem_strdup_printf(pinfo->pool, "unknown message type %u", tvb_get_guint8(tvb, o + UR_LENGTH_SIZE));
    return &ei_ur_bad_type;
}

/* How many bytes a carry must hold before a call can go on with it: its message's length once
 * its header is whole (a carry only starts at a plausible header), else a header's. */
static gint64
ur_carry_need(const ur_carry *c)
{
    if (ur_carry_size(c) >= UR_HEADER_SIZE) {
        const guint8 *head = (const guint8 *)wmem_array_get_raw(c->bytes);
        gint64 size = (gint32)pntoh32(head);
        if (size >= UR_HEADER_SIZE && size <= ur_max_length && ur_known_type[head[UR_LENGTH_SIZE]])
            return size;
    }
    return UR_HEADER_SIZE;
}

/* Resynchronising: the next plausible header from p, or -1 and the first position not tested. */
static int
ur_scan(tvbuff_t *tvb, int p, int n, int *stop)
{
    while (n - p >= UR_HEADER_SIZE) {
        if (ur_plausible(tvb, p))
            return p;
        p++;
    }
    *stop = p;
    return -1;
}

/* Client to robot: URScript text, not UR messages. */
static int
ur_dissect_client(tvbuff_t *tvb, packet_info *pinfo, proto_tree *tree)
{
    int n = tvb_captured_length(tvb);
    col_set_str(pinfo->cinfo, COL_PROTOCOL, "UR");
    proto_item *item = proto_tree_add_item(tree, proto_ur, tvb, 0, -1, ENC_NA);
    proto_tree_add_item(proto_item_add_subtree(item, ett_ur), hf_ur[UR_HF_URSCRIPT], tvb, 0, -1, ENC_UTF_8);
    if (pinfo->cinfo != NULL) {
        int len = n > 60 ? 60 : n;
        char *line = (char *)tvb_get_string_enc(pinfo->pool, tvb, 0, len, ENC_UTF_8);
        char *nl = strchr(line, '\n');
        if (strlen(line) > (size_t)len)
            line[len] = '\0';   /* as many bytes as were read, as the Lua twin shows them */
        if (nl != NULL)
            *nl = '\0';
        col_add_fstr(pinfo->cinfo, COL_INFO, "URScript: %s", line);
    }
    return n;
}

/* The Info column of a message type the spec names but does not lay out. */
static wmem_strbuf_t *
ur_unlaid_info(packet_info *pinfo, guint8 type, guint32 v)
{
    const value_string *names = ur_message_type_tables ? ur_enum_names(ur_message_type_tables, v)
                                                       : ur_message_type_names;
    const char *name = try_val_to_str(type, names);
    return ur_strbuf_printf(pinfo->pool, "Type %u (%s)", type, name ? name : "named in another version");
}

/* The message state as a message starts, from the stream's version and how it was found. */
static void
ur_begin(ur_msg *st, guint32 version, const char *implied)
{
    st->version = version != UR_VERSION_NONE ? version
                : ur_pref_version != UR_VERSION_NONE ? ur_pref_version : UR_DEFAULT_VERSION;
    st->implied = implied;
    st->announced = version != UR_VERSION_NONE && implied == NULL;
    st->from_pref = !st->announced && ur_pref_version != UR_VERSION_NONE;
    st->known = st->announced || st->from_pref;
}

/* The version a Version message from o to e announces (UR_VERSION_NONE when it is not one or is
 * malformed). A bugfix below 0 or above UR_BUGFIX_ANY: the version is then major.minor.0, and
 * the bugfix number and its offset come back for the message to flag. */
static guint32
ur_announced_version(tvbuff_t *tvb, int o, int e, gint64 *bad_bugfix, int *bugfix_at)
{
    *bugfix_at = -1;
    if (e - o <= UR_VERSION_SUBTYPE_OFFSET || tvb_get_guint8(tvb, o + UR_VERSION_SUBTYPE_OFFSET) != UR_VERSION_SUBTYPE)
        return UR_VERSION_NONE;
    gint64 p = o;
    for (unsigned i = 0; i < array_length(ur_version_steps); i++) {
        const ur_version_step *s = &ur_version_steps[i];
        p += s->fixed;
        if (p + s->prefix > e)
            return UR_VERSION_NONE;
        gint64 n = ur_int_at(tvb, (int)p, s->prefix, s->is_signed);
        if (n < 0)
            return UR_VERSION_NONE;
        p += s->prefix + n;
    }
    p += UR_VERSION_TAIL;
    if (p + 2 + UR_VERSION_REST > e)
        return UR_VERSION_NONE;
    guint8 major = tvb_get_guint8(tvb, (int)p), minor = tvb_get_guint8(tvb, (int)p + 1);
    guint32 v = ur_version_number(major, minor, 0);
    if (UR_BUGFIX_SIZE > 0 && ur_version_in(v, UR_BUGFIX_LOW, UR_BUGFIX_HIGH) && p + 2 + UR_BUGFIX_SIZE <= e) {
        gint64 bugfix = ur_int_at(tvb, (int)p + 2, UR_BUGFIX_SIZE, UR_BUGFIX_SIGNED);
        if (bugfix < 0 || bugfix > UR_BUGFIX_ANY) {
            *bad_bugfix = bugfix;
            *bugfix_at = (int)p + 2;
            return v;
        }
        v = ur_version_number(major, minor, bugfix);
    }
    return v;
}

/* One whole message from o to e (its declared length): version, Info column, tree. */
static void
ur_dissect_message(tvbuff_t *tvb, tvbuff_t *call_tvb, packet_info *pinfo, proto_tree *tree, ur_call *cur, int o,
                   int e, guint8 type)
{
    const ur_message *m = ur_messages[type];
    gint64 bad_bugfix = 0;
    int bugfix_at = -1;
    if (type == UR_VERSION_MESSAGE) {
        guint32 v = ur_announced_version(tvb, o, e, &bad_bugfix, &bugfix_at);
        if (v != UR_VERSION_NONE) {
            cur->version = v;
            cur->implied = NULL;
        }
    }
    guint32 version = cur->version;
    const char *implied = cur->implied;
    ur_msg st;
    memset(&st, 0, sizeof st);
    st.pinfo = pinfo;
    st.tvb = tvb;
    st.call_tvb = call_tvb;
    st.base = o;
    ur_begin(&st, version, implied);
    wmem_strbuf_t *text = m ? ur_message_info(&st, m, o, e, cur->columns) : NULL;
    if (cur->columns)
        ur_set_info(pinfo, cur->first, text ? text : ur_unlaid_info(pinfo, type, st.version));
    cur->first = FALSE;
    /* Layout sizes told the version of a stream that had not: this message and the next ones. */
    if (st.implied != NULL && !st.known) {
        cur->version = st.version;
        cur->implied = st.implied;
    }
    if (!cur->detail)
        return;
    proto_item *item = proto_tree_add_item(tree, proto_ur, tvb, o, e - o, ENC_NA);
    proto_tree *sub = proto_item_add_subtree(item, ett_ur);
    st.visible = PTREE_DATA(tree)->visible;
    st.only = st.visible && ur_only_named_packages();
    proto_tree_add_item(sub, hf_ur[UR_HF_LENGTH], tvb, o, UR_LENGTH_SIZE, ENC_BIG_ENDIAN);
    proto_item *type_item = proto_tree_add_item(sub, hf_ur[UR_HF_TYPE], tvb, o + UR_LENGTH_SIZE,
                                                UR_HEADER_SIZE - UR_LENGTH_SIZE, ENC_BIG_ENDIAN);
    if (ur_message_type_tables != NULL)
        ur_rename(type_item, "Type", ur_message_type_tables, st.version, type);
    /* The tree walks the message again from the version it started with. */
    st.message_version = st.version;
    st.message_implied = st.implied;
    ur_begin(&st, version, implied);
    if (m != NULL) {
        proto_item_append_text(item, "%s", m->suffix);
        ur_items_begin(&st, item);
        proto_item *fields = ur_message_tree(&st, m, item, o, e);
        if (fields == NULL)
            fields = item;
        if (bugfix_at >= 0) {
            char buf[UR_VERSION_TEXT];
            proto_tree_add_expert_format(ur_sub(fields), pinfo, &ei_ur_version_range, tvb, bugfix_at, UR_BUGFIX_SIZE,
                                         "bugfix version %" G_GINT64_MODIFIER "d is out of range (0 to %d); the "
                                         "stream is read as %s", bad_bugfix, UR_BUGFIX_ANY,
                                         ur_version_text(cur->version, buf));
        }
        if (st.hidden > 0)
            expert_add_info_format(pinfo, item, &ei_ur_items_hidden, "%d more items not shown (a message shows at "
                                   "most %d)", st.hidden, UR_MAX_TREE_ITEMS);
    } else if (e - o > UR_HEADER_SIZE) {
        /* A known type without a layout (e.g. 24): kept raw, not an error. */
        proto_tree_add_item(sub, hf_ur[UR_HF_RAW], tvb, o + UR_HEADER_SIZE, e - o - UR_HEADER_SIZE, ENC_NA);
    }
}

/* Bytes skipped while resynchronising. */
static void
ur_data_item(proto_tree *tree, tvbuff_t *data, int o, int len)
{
    proto_item *item = proto_tree_add_item(tree, proto_ur, data, o, len, ENC_NA);
    proto_tree_add_item(proto_item_add_subtree(item, ett_ur), hf_ur[UR_HF_SKIPPED], data, o, len, ENC_NA);
}

static int
dissect_ur(tvbuff_t *tvb, packet_info *pinfo, proto_tree *tree, void *data _U_)
{
    if (pinfo->srcport != pinfo->match_uint)
        return ur_dissect_client(tvb, pinfo, tree);
    int n = tvb_captured_length(tvb);
    ur_call cur;
    /* Field work only when someone looks: a tree, or a filter or column naming ur. */
    cur.detail = tree != NULL && proto_field_is_referenced(tree, proto_ur);
    cur.first = TRUE;
    cur.columns = pinfo->cinfo != NULL;

    /* The stream's state as this call starts. */
    const ur_snap *snap = ur_stream_load(pinfo, (unsigned)n);
    cur.version = snap->version;
    cur.implied = snap->implied;
    gboolean resync = snap->resync;
    ur_carry *carry = snap->carry;

    if (cur.columns)
        col_set_str(pinfo->cinfo, COL_PROTOCOL, "UR");
    /* Once this call has met a fault, the rest of the stream is carried over by hand (in the
     * stream state) until it is back in step, instead of by TCP reassembly. Carried bytes come
     * first, in a tvb of their own, made once the message they start is whole. */
    gboolean by_hand = carry != NULL || resync;
    tvbuff_t *buf = tvb;
    if (carry != NULL) {
        if (!resync && snap->carried + (gint64)n < ur_carry_need(carry)) {
            /* Still inside the carried message: keep these bytes too, and show nothing yet. */
            if (!PINFO_FD_VISITED(pinfo))
                wmem_array_append(carry->bytes, tvb_get_ptr(tvb, 0, n), n);
            ur_stream_save(pinfo, cur.version, cur.implied, resync, carry);
            return n;
        }
        guint8 *joined = (guint8 *)wmem_alloc(pinfo->pool, snap->carried + n);
        memcpy(joined, wmem_array_get_raw(carry->bytes), snap->carried);
        tvb_memcpy(tvb, joined + snap->carried, 0, n);
        buf = tvb_new_child_real_data(tvb, joined, snap->carried + n, snap->carried + n);
        add_new_data_source(pinfo, buf, "UR bytes carried over");
    }
    int len = tvb_captured_length(buf);
    carry = NULL;
    int o = 0, stop = 0;
    if (resync) {
        /* Go on scanning for the next plausible header. */
        int p = ur_scan(buf, 0, len, &stop);
        if (p >= 0) {
            if (p > 0 && cur.detail)
                ur_data_item(tree, buf, 0, p);
            o = p;
            resync = FALSE;
        } else {
            /* Nothing yet: keep the last bytes, which may start a header. */
            if (stop > 0 && cur.detail)
                ur_data_item(tree, buf, 0, stop);
            if (cur.columns)
                ur_set_info_text(pinfo, TRUE, "Resynchronising: no message header yet");
            cur.first = FALSE;
            carry = ur_carry_new(tvb_get_ptr(buf, stop, len - stop), len - stop);
            o = len;
        }
    }
    while (o < len) {
        int left = len - o;
        gint64 size = 0;
        guint8 type = 0;
        if (left >= UR_HEADER_SIZE) {
            size = ur_int_at(buf, o, UR_LENGTH_SIZE, TRUE);
            type = tvb_get_guint8(buf, o + UR_LENGTH_SIZE);
        }
        if (left >= UR_HEADER_SIZE && (size < UR_HEADER_SIZE || size > ur_max_length || !ur_known_type[type])) {
            const char *text;
            expert_field *ei = ur_header_fault(pinfo, buf, o, &text);
            proto_item *item = proto_tree_add_item(tree, proto_ur, buf, o, UR_HEADER_SIZE, ENC_NA);
            proto_tree *sub = proto_item_add_subtree(item, ett_ur);
            proto_tree_add_item(sub, hf_ur[UR_HF_LENGTH], buf, o, UR_LENGTH_SIZE, ENC_BIG_ENDIAN);
            proto_tree_add_item(sub, hf_ur[UR_HF_TYPE], buf, o + UR_LENGTH_SIZE, UR_HEADER_SIZE - UR_LENGTH_SIZE,
                                ENC_BIG_ENDIAN);
            expert_add_info_format(pinfo, item, ei, "%s", text);
            if (cur.columns)
                ur_set_info(pinfo, cur.first, ur_strbuf_printf(pinfo->pool, "Bad header: %s", text));
            cur.first = FALSE;
            by_hand = TRUE;
            /* Scan forward from the next byte; the skipped bytes belong to this fault. */
            int p = ur_scan(buf, o + 1, len, &stop);
            if (p >= 0) {
                if (p > o + 1 && cur.detail)
                    ur_data_item(tree, buf, o + 1, p - o - 1);
                o = p;
            } else {
                if (stop > o + 1 && cur.detail)
                    ur_data_item(tree, buf, o + 1, stop - o - 1);
                resync = TRUE;
                carry = ur_carry_new(tvb_get_ptr(buf, stop, len - stop), len - stop);
                o = len;
            }
        } else if ((left < UR_HEADER_SIZE || size > left) && by_hand) {
            /* Carried as it is until the message is whole. */
            carry = ur_carry_new(tvb_get_ptr(buf, o, left), left);
            o = len;
        } else if (left < UR_HEADER_SIZE) {
            /* A header split inside its first bytes: ask for one more segment. */
            if (pinfo->can_desegment > 0) {
                pinfo->desegment_offset = o;
                pinfo->desegment_len = DESEGMENT_ONE_MORE_SEGMENT;
            }
            break;
        } else if (size > left) {
            if (pinfo->can_desegment > 0) {
                pinfo->desegment_offset = o;
                pinfo->desegment_len = (guint32)(size - left);
                break;
            }
            /* No reassembly possible (preference off): show what is there. */
            proto_item *item = proto_tree_add_item(tree, proto_ur, buf, o, left, ENC_NA);
            proto_tree_add_item(proto_item_add_subtree(item, ett_ur), hf_ur[UR_HF_RAW], buf, o, left, ENC_NA);
            if (cur.columns)
                ur_set_info_text(pinfo, cur.first, "Continuation");
            break;
        } else {
            ur_dissect_message(buf, tvb, pinfo, tree, &cur, o, o + (int)size, type);
            o += (int)size;
        }
    }
    ur_stream_save(pinfo, cur.version, cur.implied, resync, carry);
    return n;
}

static void
ur_prefs_changed(void)
{
    static range_t *registered;
    ur_pref_version = ur_parse_version(ur_version_pref);
    if (ur_handle == NULL)
        return;
    if (registered != NULL) {
        dissector_delete_uint_range("tcp.port", registered, ur_handle);
        wmem_free(wmem_epan_scope(), registered);
    }
    registered = range_copy(wmem_epan_scope(), ur_ports);
    dissector_add_uint_range("tcp.port", registered, ur_handle);
}

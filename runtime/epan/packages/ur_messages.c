/* Messages: ur_messages holds one table per message type, and its kind says how it is
 * dissected: packages (a list of sub-packages, each framed by its own length: robot state),
 * subtypes (a header, then a subtype byte that chooses the layout of the rest) and body (one
 * layout right after the message header: message types 5, 22, 23, 24). Each kind has an Info
 * text (from the bytes; NULL when no column is built) and a tree. As runtime/lua/packages/messages.lua. */
/* The body of a package or message from body to stop, walked with its layout for version v; what
 * cannot be read is kept raw, what is left over is shown as extra bytes, each with its expert. */
static void
ur_walk_body(ur_msg *st, proto_item *item, int body, int stop, const ur_part *part, guint32 v)
{
    guint32 keep = st->version;
    const char *err = NULL;
    proto_tree *tree = ur_sub(item);
    st->version = v;
    int used = ur_walk(st, tree, body, stop, part->layout, NULL, &err);
    st->version = keep;
    if (used < 0) {
        ur_add(st, tree, UR_HF_RAW, body, stop - body, ENC_NA);
        ur_expert(st, item, &ei_ur_malformed, wmem_strdup_printf(st->pinfo->pool, "%s: %s", part->name, err));
    } else if (used < stop) {
        ur_add(st, tree, UR_HF_EXTRA, used, stop - used, ENC_NA);
        ur_expert(st, item, &ei_ur_extra,
                  wmem_strdup_printf(st->pinfo->pool, "%s: %d bytes after the layout", part->name, stop - used));
    }
}

/* A type or subtype code: its field, and under a version whose table names it otherwise, that name. */
static proto_item *
ur_add_code(ur_msg *st, proto_tree *tree, int field, int o, int n, const char *label, const ur_names *tables,
            guint32 v, guint32 code)
{
    proto_item *item = ur_add(st, tree, field, o, n, ENC_BIG_ENDIAN);
    if (tables != NULL && st->visible)
        ur_rename(item, label, tables, v, code);
    return item;
}

/* The name of a code for version v (NULL: none), and whether the spec names it in any version. */
static const char *
ur_code_name(const value_string *names, const ur_names *tables, guint32 v, guint32 code, gboolean *named)
{
    const char *name = try_val_to_str(code, tables ? ur_enum_names(tables, v) : names);
    *named = name != NULL || (tables != NULL && ur_named_in_any(tables, code));
    return name;
}

/* What the message was read with: the version, and how it was found when no Version message
 * told it (from layout sizes, the ur.version preference, or the default), each with a note. */
static void
ur_show_version(ur_msg *st, proto_item *item)
{
    char buf[UR_VERSION_TEXT];
    wmem_allocator_t *pool = st->pinfo->pool;
    proto_tree *tree = ur_sub(item);
    const char *text = st->message_implied
        ? wmem_strdup_printf(pool, "%s (from layout sizes)", st->message_implied)
        : ur_version_text(st->message_version, buf);
    if (ur_room(st, tree))
        proto_item_set_generated(proto_tree_add_string(tree, ur_hf(UR_HF_SOFTWARE_VERSION), st->call_tvb, 0, 0, text));
    if (st->announced)
        return;
    if (ur_room(st, tree))
        proto_item_set_generated(proto_tree_add_boolean(tree, ur_hf(UR_HF_VERSION_ASSUMED), st->call_tvb, 0, 0, TRUE));
    if (st->message_implied)
        text = wmem_strdup_printf(pool, "no Version message seen on this stream: software %s, as the layout sizes "
                                  "show", st->message_implied);
    else if (st->from_pref)
        text = wmem_strdup_printf(pool, "no Version message seen on this stream: assuming software %s "
                                  "(preference ur.version)", ur_version_text(st->message_version, buf));
    else
        text = wmem_strdup_printf(pool, "no Version message seen on this stream: assuming software %s "
                                  "(the default; preference ur.version)", ur_version_text(st->message_version, buf));
    ur_expert(st, item, &ei_ur_assumed, text);
}

/* A form chosen by its length, not by the version: a note on its item. */
static void
ur_note_length(ur_msg *st, proto_item *item, const ur_form *form, int length)
{
    ur_expert(st, item, &ei_ur_by_length, wmem_strdup_printf(st->pinfo->pool, "laid out as software %s "
                                                             "(chosen by length %d)", form->versions, length));
}

/* One package of a robot state at p, of size bytes, its form chosen (NULL: a type the spec does
 * not lay out): its item, header and fields. */
static void
ur_package(ur_msg *st, const ur_message *m, proto_tree *tree, int p, int size, guint8 code, const ur_form *form,
           guint32 use, gboolean by_length)
{
    const ur_part *pk = form ? form->of : NULL;
    guint32 v = form ? use : st->version;
    proto_item *item = ur_add(st, tree, pk ? pk->item : UR_HF_UNKNOWN_PACKAGE, p, size, ENC_NA);
    gboolean named;
    const char *name = ur_code_name(m->names, m->tables, v, code, &named);
    if (pk == NULL && item != NULL && st->visible)
        proto_item_set_text(item, "Unknown package %u (%s)", code, name ? name : "not in the spec");
    proto_tree *sub = ur_sub(item);
    ur_add(st, sub, m->length_hf, p, UR_PACKAGE_LENGTH_SIZE, ENC_BIG_ENDIAN);
    ur_add_code(st, sub, m->type_hf, p + UR_PACKAGE_LENGTH_SIZE, UR_PACKAGE_HEADER_SIZE - UR_PACKAGE_LENGTH_SIZE,
                "Type", m->tables, v, code);
    if (by_length)
        ur_note_length(st, item, form, size);
    int body = p + UR_PACKAGE_HEADER_SIZE, stop = p + size;
    if (pk != NULL) {
        ur_walk_body(st, item, body, stop, pk, use);
    } else {
        ur_add(st, sub, UR_HF_RAW, body, stop - body, ENC_NA);
        /* Types the spec names but does not lay out (e.g. 14) are normal: no expert. */
        if (!named)
            ur_expert(st, item, &ei_ur_unknown,
                      wmem_strdup_printf(st->pinfo->pool, "package type %u is not in the spec, kept raw", code));
    }
}

static wmem_strbuf_t *
ur_packages_info(ur_msg *st, const ur_message *m, int o, int e, gboolean text)
{
    wmem_strbuf_t *summary = ur_package_summary(st, o + UR_HEADER_SIZE, e, m, text);
    return text ? ur_labelled(st->pinfo->pool, m->label, summary) : NULL;
}

static proto_item *
ur_packages_tree(ur_msg *st, const ur_message *m, proto_item *item, int o, int e)
{
    tvbuff_t *tvb = st->tvb;
    proto_tree *tree = ur_sub(item);
    if (m->needs_version)
        ur_show_version(st, item);
    int p = o + UR_HEADER_SIZE;
    while (p < e) {
        int left = e - p;
        gint64 size = left >= UR_PACKAGE_HEADER_SIZE ? ur_int_at(tvb, p, UR_PACKAGE_LENGTH_SIZE, TRUE) : 0;
        const char *err = NULL;
        if (left < UR_PACKAGE_HEADER_SIZE)
            err = wmem_strdup_printf(st->pinfo->pool, "package at offset %d: needs %d bytes, %d left", p - st->base,
                                     UR_PACKAGE_HEADER_SIZE, left);
        else if (size < UR_PACKAGE_HEADER_SIZE)
            err = wmem_strdup_printf(st->pinfo->pool, "package at offset %d: length %" G_GINT64_MODIFIER "d is "
                                     "below %d", p - st->base, size, UR_PACKAGE_HEADER_SIZE);
        else if (size > left)
            err = wmem_strdup_printf(st->pinfo->pool, "package at offset %d: length %" G_GINT64_MODIFIER "d "
                                     "exceeds the %d bytes left", p - st->base, size, left);
        if (err != NULL) {
            ur_add(st, tree, UR_HF_RAW, p, left, ENC_NA);
            ur_expert(st, item, &ei_ur_malformed, err);
            return NULL;
        }
        guint8 code = tvb_get_guint8(tvb, p + UR_PACKAGE_LENGTH_SIZE);
        const ur_forms *forms = m->forms[code];
        const ur_form *form = NULL;
        guint32 use = st->version;
        gboolean by_length = FALSE;
        if (forms != NULL)
            form = ur_pick(forms, (unsigned)size - UR_PACKAGE_HEADER_SIZE, st, &use, &by_length);
        /* A tshark -T fields run that names no field of this package: not built at all. */
        if (form == NULL || !st->only || ur_package_wanted(form->of))
            ur_package(st, m, tree, p, (int)size, code, form, use, by_length);
        p += (int)size;
    }
    return NULL;
}

static wmem_strbuf_t *
ur_subtypes_info(ur_msg *st, const ur_message *m, int o, int e, gboolean text)
{
    if (!text)
        return NULL;
    wmem_allocator_t *pool = st->pinfo->pool;
    if (e - o < (int)m->body_offset)
        return ur_strbuf_printf(pool, "%s (too short)", m->label);
    guint8 code = tvb_get_guint8(st->tvb, o + (int)m->body_offset - 1);
    const ur_forms *forms = m->forms[code];
    if (forms == NULL)
        return ur_strbuf_printf(pool, "%s subtype %u", m->label, code);
    guint32 use;
    gboolean by_length;
    const ur_form *form = ur_choose(forms, (unsigned)(e - o - (int)m->body_offset), st->version, &use, &by_length);
    return ur_labelled(pool, form->of->label,
                       ur_layout_summary(st->tvb, pool, o + (int)m->body_offset, e, form->of->layout, use));
}

static proto_item *
ur_subtypes_tree(ur_msg *st, const ur_message *m, proto_item *item, int o, int e)
{
    proto_tree *tree = ur_sub(item);
    int body = o + (int)m->body_offset;
    const char *err = NULL;
    if (e < body) {
        ur_walk(st, tree, o + UR_HEADER_SIZE, e, m->header, NULL, &err);
        if (e - o > UR_HEADER_SIZE)
            ur_add(st, tree, UR_HF_RAW, o + UR_HEADER_SIZE, e - o - UR_HEADER_SIZE, ENC_NA);
        ur_expert(st, item, &ei_ur_malformed, err ? err : "too short");
        return NULL;
    }
    guint8 code = tvb_get_guint8(st->tvb, body - 1);
    const ur_forms *forms = m->forms[code];
    if (forms == NULL) {
        gboolean named;
        ur_walk(st, tree, o + UR_HEADER_SIZE, body, m->header, NULL, &err);
        if (body < e)
            ur_add(st, tree, UR_HF_RAW, body, e - body, ENC_NA);
        ur_code_name(m->names, m->tables, st->version, code, &named);
        if (!named) {
            char *lower = ascii_strdown_inplace(wmem_strdup(st->pinfo->pool, m->label));
            ur_expert(st, item, &ei_ur_unknown,
                      wmem_strdup_printf(st->pinfo->pool, "%s subtype %u is not in the spec, kept raw", lower, code));
        }
        return NULL;
    }
    guint32 use;
    gboolean by_length;
    const ur_form *form = ur_choose(forms, (unsigned)(e - body), st->version, &use, &by_length);
    const ur_part *s = form->of;
    proto_item *sub_item = ur_add(st, tree, s->item, o + UR_HEADER_SIZE, e - o - UR_HEADER_SIZE, ENC_NA);
    proto_tree *sub = ur_sub(sub_item);
    /* The header again, under the subtype's own names (ur.key.timestamp). */
    ur_walk(st, sub, o + UR_HEADER_SIZE, body - 1, s->header, NULL, &err);
    ur_add_code(st, sub, m->subtype_hf, body - 1, 1, m->subtype_label, m->tables, use, code);
    if (by_length)
        ur_note_length(st, sub_item, form, e - o);
    if (s->needs_version)
        ur_show_version(st, sub_item);
    ur_walk_body(st, sub_item, body, e, s, use);
    return sub_item;   /* where the subtype's fields are */
}

static wmem_strbuf_t *
ur_body_info(ur_msg *st, const ur_message *m, int o, int e, gboolean text)
{
    if (!text)
        return NULL;
    guint32 use;
    gboolean by_length;
    const ur_form *form = ur_choose(m->forms[m->code], (unsigned)(e - o - (int)m->body_offset), st->version, &use,
                                    &by_length);
    return ur_labelled(st->pinfo->pool, form->of->label,
                       ur_layout_summary(st->tvb, st->pinfo->pool, o + (int)m->body_offset, e, form->of->layout,
                                         use));
}

static proto_item *
ur_body_tree(ur_msg *st, const ur_message *m, proto_item *item, int o, int e)
{
    int body = o + (int)m->body_offset;
    guint32 use;
    gboolean by_length;
    const ur_form *form = ur_choose(m->forms[m->code], (unsigned)(e - body), st->version, &use, &by_length);
    const ur_part *s = form->of;
    proto_item *sub_item = ur_add(st, ur_sub(item), s->item, body, e - body, ENC_NA);
    if (by_length)
        ur_note_length(st, sub_item, form, e - o);
    if (s->needs_version)
        ur_show_version(st, sub_item);
    ur_walk_body(st, sub_item, body, e, s, use);
    return sub_item;
}

static wmem_strbuf_t *
ur_message_info(ur_msg *st, const ur_message *m, int o, int e, gboolean text)
{
    switch (m->kind) {
    case UR_M_PACKAGES:
        return ur_packages_info(st, m, o, e, text);
    case UR_M_SUBTYPES:
        return ur_subtypes_info(st, m, o, e, text);
    default:
        return ur_body_info(st, m, o, e, text);
    }
}

/* The message's fields under its item; the item where a subtype's fields are, or NULL. */
static proto_item *
ur_message_tree(ur_msg *st, const ur_message *m, proto_item *item, int o, int e)
{
    switch (m->kind) {
    case UR_M_PACKAGES:
        return ur_packages_tree(st, m, item, o, e);
    case UR_M_SUBTYPES:
        return ur_subtypes_tree(st, m, item, o, e);
    default:
        return ur_body_tree(st, m, item, o, e);
    }
}

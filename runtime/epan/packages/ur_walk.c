/* The generic walk of a layout: a list of field descriptors in wire order, each added to the
 * tree by the function of its kind. Offsets are tvb offsets; o is where a field starts and e where
 * the layout ends. A walk returns the offset after the layout, or -1 with the canonical error text
 * in *err ("joints[2].q_actual at offset 31: needs 8 bytes, 3 left", offsets from the message's
 * first byte, as every target words it). As runtime/lua/packages/walk.lua. */
/* Where a field stands, for error texts only: made as the walk goes down (a group's item
 * "joints[2].", a value "variables[1][0]"), written out only when an error names it. */
typedef struct ur_path {
    const struct ur_path *up;
    const char *name;           /* NULL: an index of what `up` names */
    gint64 position;            /* -1: none */
    gboolean dot;               /* a group item: its fields follow after a dot */
} ur_path;

static void
ur_path_write(wmem_strbuf_t *out, const ur_path *at)
{
    if (at == NULL)
        return;
    ur_path_write(out, at->up);
    if (at->name != NULL)
        wmem_strbuf_append(out, at->name);
    if (at->position >= 0)
        wmem_strbuf_append_printf(out, "[%" G_GINT64_MODIFIER "d]", at->position);
    if (at->dot)
        wmem_strbuf_append_c(out, '.');
}

/* The path `at`, then `name`, as text. */
static const char *
ur_path_text(ur_msg *st, const ur_path *at, const char *name)
{
    wmem_strbuf_t *out = wmem_strbuf_new(st->pinfo->pool, "");
    ur_path_write(out, at);
    wmem_strbuf_append(out, name);
    return wmem_strbuf_get_str(out);
}

static int ur_walk(ur_msg *st, proto_tree *tree, int o, int e, const ur_layout *layout, const ur_path *pre,
                   const char **err);

static const char *
ur_short(ur_msg *st, const ur_path *pre, const char *path, int o, gint64 need, int e)
{
    int left = e - o < 0 ? 0 : e - o;
    return wmem_strdup_printf(st->pinfo->pool, "%s at offset %d: needs %" G_GINT64_MODIFIER "d bytes, %d left",
                              ur_path_text(st, pre, path), o - st->base, need, left);
}

static const char *
ur_negative(ur_msg *st, const ur_path *pre, const char *path, int o, gint64 n)
{
    return wmem_strdup_printf(st->pinfo->pool, "%s at offset %d: negative length %" G_GINT64_MODIFIER "d",
                              ur_path_text(st, pre, path), o - st->base, n);
}

/* An integer of n bytes (1 to 8) at o, big-endian, signed or not. */
static gint64
ur_int_at(tvbuff_t *tvb, int o, unsigned n, gboolean is_signed)
{
    guint64 v;
    switch (n) {
    case 1:
        v = tvb_get_guint8(tvb, o);
        break;
    case 2:
        v = tvb_get_ntohs(tvb, o);
        break;
    case 4:
        v = tvb_get_ntohl(tvb, o);
        break;
    case 8:
        v = tvb_get_ntoh64(tvb, o);
        break;
    default:
        v = tvb_get_bits64(tvb, (guint)o * 8, (gint)n * 8, ENC_BIG_ENDIAN);
        break;
    }
    if (is_signed && n < 8 && (v >> (n * 8 - 1)) & 1)
        return (gint64)(v | ~((G_GUINT64_CONSTANT(1) << (n * 8)) - 1));
    return (gint64)v;
}

/* A text field (UTF-8); a zero-length one still shows, at its offset. */
static proto_item *
ur_add_text(ur_msg *st, proto_tree *tree, int field, int o, int n)
{
    return ur_add(st, tree, field, o, n, ENC_UTF_8);
}

/* An enum item whose names depend on the software version v: its field shows the newest
 * table's name; under another version's table the item says that table's name instead. */
static void
ur_rename(proto_item *item, const char *label, const ur_names *tables, guint32 v, gint64 value)
{
    const value_string *names = ur_enum_names(tables, v);
    if (item != NULL && names != tables->newest) {
        const char *name = try_val_to_str((guint32)value, names);
        proto_item_set_text(item, "%s: %s (%" G_GINT64_MODIFIER "d)", label, name ? name : "Unknown", value);
    }
}

/* A number added explicitly: the wire type is narrower than the field's. */
static proto_item *
ur_add_value(ur_msg *st, proto_tree *tree, int field, int o, int n, gint64 value, double real)
{
    if (!ur_room(st, tree))
        return NULL;
    int hf = ur_hf(field);
    switch (proto_registrar_get_ftype(hf)) {
    case FT_FLOAT:
    case FT_DOUBLE:
        return proto_tree_add_double(tree, hf, st->tvb, o, n, real);
    case FT_INT8: case FT_INT16: case FT_INT24: case FT_INT32:
        return proto_tree_add_int(tree, hf, st->tvb, o, n, (gint32)value);
    case FT_INT64:
        return proto_tree_add_int64(tree, hf, st->tvb, o, n, value);
    case FT_UINT64:
        return proto_tree_add_uint64(tree, hf, st->tvb, o, n, (guint64)value);
    case FT_BOOLEAN:
        return proto_tree_add_boolean(tree, hf, st->tvb, o, n, (guint32)(value != 0));
    default:
        return proto_tree_add_uint(tree, hf, st->tvb, o, n, (guint32)value);
    }
}

/* One scalar into the tree: explicitly when its wire type is narrower than its field's, named
 * by the version when its enum needs it; kept when a later field depends on it. */
static proto_item *
ur_add_scalar(ur_msg *st, proto_tree *tree, int o, const ur_desc *d)
{
    if (!(d->flags & UR_VALUE) && d->names == NULL && d->keep == 0)
        return ur_add(st, tree, d->hf, o, (int)d->n, ENC_BIG_ENDIAN);
    gint64 v = 0;
    double real = 0;
    if (d->flags & UR_FLOAT)
        real = d->n == 4 ? (double)tvb_get_ntohieee_float(st->tvb, o) : tvb_get_ntohieee_double(st->tvb, o);
    else
        v = ur_int_at(st->tvb, o, d->n, (d->flags & UR_SIGNED) != 0);
    proto_item *item = (d->flags & UR_VALUE) ? ur_add_value(st, tree, d->hf, o, (int)d->n, v, real)
                                            : ur_add(st, tree, d->hf, o, (int)d->n, ENC_BIG_ENDIAN);
    if (d->names != NULL && st->visible)
        ur_rename(item, d->label, d->names, st->version, v);
    if (d->keep != 0) {
        st->kept[d->keep] = v;
        st->kept_set[d->keep] = TRUE;
    }
    return item;
}

static int
ur_walk_scalar(ur_msg *st, proto_tree *tree, int o, int e, const ur_desc *d, const ur_path *pre, const char **err)
{
    if (o + (int)d->n > e) {
        *err = ur_short(st, pre, d->path, o, (int)d->n, e);
        return -1;
    }
    ur_add_scalar(st, tree, o, d);
    return o + (int)d->n;
}

/* An integer whose bits are shown one by one; the bits read the integer's own bytes. */
static int
ur_walk_bits(ur_msg *st, proto_tree *tree, int o, int e, const ur_desc *d, const ur_path *pre, const char **err)
{
    if (o + (int)d->n > e) {
        *err = ur_short(st, pre, d->path, o, (int)d->n, e);
        return -1;
    }
    proto_tree *bits = ur_sub(ur_add_scalar(st, tree, o, d));
    for (unsigned i = 0; i < d->count; i++)
        ur_add(st, bits, d->bits[i], o, (int)d->n, ENC_BIG_ENDIAN);
    return o + (int)d->n;
}

/* count scalars in a row; an error names the element ("q_actual[3]"). */
static int
ur_walk_array(ur_msg *st, proto_tree *tree, int o, int e, const ur_desc *d, const ur_path *pre, const char **err)
{
    for (unsigned i = 0; i < d->count; i++) {
        if (o + (int)d->n > e) {
            ur_path element = { pre, d->path, i, FALSE };
            *err = ur_short(st, &element, "", o, (int)d->n, e);
            return -1;
        }
        ur_add_scalar(st, tree, o, d);
        o += (int)d->n;
    }
    return o;
}

/* A repeated group ("Joint 0".."Joint 5"), count times or to the end of the layout. */
static int
ur_walk_group(ur_msg *st, proto_tree *tree, int o, int e, const ur_desc *d, const ur_path *pre, const char **err)
{
    for (unsigned i = 0; d->count ? i < d->count : o < e; i++) {
        int start = o;
        gboolean fits = d->size && o + (int)d->size <= e;
        proto_item *item = ur_add(st, tree, d->hf, o, fits ? (int)d->size : 0, ENC_NA);
        if (item && st->visible)        /* formatted once, and only where the tree is shown */
            proto_item_set_text(item, "%s %u", d->label, i);
        ur_path at = { pre, d->path, i, TRUE };
        o = ur_walk(st, ur_sub(item), o, e, d->inner, &at, err);
        if (o < 0) {
            proto_item_set_len(item, e - start);
            return -1;
        }
        if (!fits)
            proto_item_set_len(item, o - start);
    }
    return o;
}

/* A text with a length prefix. */
static int
ur_walk_pstring(ur_msg *st, proto_tree *tree, int o, int e, const ur_desc *d, const ur_path *pre, const char **err)
{
    if (o + (int)d->n > e) {
        *err = ur_short(st, pre, d->path, o, (int)d->n, e);
        return -1;
    }
    gint64 n = ur_int_at(st->tvb, o, d->n, (d->flags & UR_SIGNED) != 0);
    if (n < 0) {
        *err = ur_negative(st, pre, d->path, o, n);
        return -1;
    }
    o += (int)d->n;
    if (o + n > e) {
        *err = ur_short(st, pre, d->path, o, n, e);
        return -1;
    }
    ur_add_text(st, tree, d->hf, o, (int)n);
    return o + (int)n;
}

/* Texts each ended by a terminator; bytes after the last terminator are extra. */
static int
ur_walk_strings(ur_msg *st, proto_tree *tree, int o, int e, const ur_desc *d)
{
    int start = o;
    for (int i = o; i < e; i++) {
        if (tvb_get_guint8(st->tvb, i) == d->n) {
            ur_add_text(st, tree, d->hf, start, i - start);
            start = i + 1;
        }
    }
    return start;
}

/* One scalar whose type follows an earlier field. */
static int
ur_walk_switch(ur_msg *st, proto_tree *tree, int o, int e, const ur_desc *d, const ur_path *pre, const char **err)
{
    int hf = d->sw->default_hf;
    unsigned n = d->sw->default_n;
    if (st->kept_set[d->keep]) {
        for (unsigned i = 0; i < d->sw->n_cases; i++) {
            if (d->sw->cases[i].code == st->kept[d->keep]) {
                hf = d->sw->cases[i].hf;
                n = d->sw->cases[i].n;
            }
        }
    }
    if (o + (int)n > e) {
        *err = ur_short(st, pre, d->path, o, n, e);
        return -1;
    }
    ur_add(st, tree, hf, o, (int)n, ENC_BIG_ENDIAN);
    return o + (int)n;
}

static int ur_walk_values(ur_msg *st, proto_tree *tree, int o, int e, const ur_desc *d, const ur_path *pre,
                          const char **err);

/* Walk a layout from o to at most e. pre is the error path of the enclosing group item
 * ("joints[2]."), NULL at the top. */
static int
ur_walk(ur_msg *st, proto_tree *tree, int o, int e, const ur_layout *layout, const ur_path *pre, const char **err)
{
    for (unsigned i = 0; i < layout->n && o >= 0; i++) {
        const ur_desc *d = &layout->d[i];
        switch (d->kind) {
        case UR_D_SCALAR:
            o = ur_walk_scalar(st, tree, o, e, d, pre, err);
            break;
        case UR_D_BITS:
            o = ur_walk_bits(st, tree, o, e, d, pre, err);
            break;
        case UR_D_ARRAY:
            o = ur_walk_array(st, tree, o, e, d, pre, err);
            break;
        case UR_D_GROUP:
            o = ur_walk_group(st, tree, o, e, d, pre, err);
            break;
        case UR_D_PSTRING:
            o = ur_walk_pstring(st, tree, o, e, d, pre, err);
            break;
        case UR_D_STRING:
            ur_add_text(st, tree, d->hf, o, e - o);
            o = e;
            break;
        case UR_D_BYTES:
            ur_add(st, tree, d->hf, o, e - o, ENC_NA);
            o = e;
            break;
        case UR_D_STRINGS:
            o = ur_walk_strings(st, tree, o, e, d);
            break;
        case UR_D_SWITCH:
            o = ur_walk_switch(st, tree, o, e, d, pre, err);
            break;
        case UR_D_VALUES:
            o = ur_walk_values(st, tree, o, e, d, pre, err);
            break;
        case UR_D_COND:
            if (d->keep != 0 && (!st->kept_set[d->keep] || st->kept[d->keep] == 0))
                break;
            if (!ur_version_in(st->version, d->low, d->high))
                break;
            o = ur_walk(st, tree, o, e, d->inner, pre, err);
            break;
        default:
            DISSECTOR_ASSERT_NOT_REACHED();
        }
    }
    return o;
}

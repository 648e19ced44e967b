/* Typed values of global variables: a type byte, then its data, nested for LIST and MATRIX.
 * The meaning of a type byte depends on the software version (ur_value_tables: one table per
 * version range). As runtime/lua/packages/values.lua. */
/* Items that cannot fit in the bytes from o to e (each takes at least vt->min_size) are refused
 * before any is read; at is the offset of their count. */
static const char *
ur_too_many(ur_msg *st, const ur_value_table *vt, const ur_path *path, int at, gint64 items, int o, int e)
{
    if (items * (gint64)vt->min_size > e - o)
        return wmem_strdup_printf(st->pinfo->pool,
                                  "%s at offset %d: %" G_GINT64_MODIFIER "d items need more than the %d bytes left",
                                  ur_path_text(st, path, ""), at - st->base, items, e - o);
    return NULL;
}

/* One typed value at o, under tree; label is what its item reads ("Variable 2", "Item 0"), path
 * names it in errors ("variables[2][0]"). The offset after it, or -1 and the error in *err. */
static int
ur_walk_value(ur_msg *st, proto_tree *tree, int o, int e, const ur_value_fields *vf, const ur_value_table *vt,
              const char *label, const ur_path *path, int depth, const char **err)
{
    wmem_allocator_t *pool = st->pinfo->pool;
    if (o >= e) {
        *err = ur_short(st, path, ".type", o, 1, e);
        return -1;
    }
    guint8 code = tvb_get_guint8(st->tvb, o);
    if (depth > UR_MAX_VALUE_DEPTH) {
        *err = wmem_strdup_printf(pool, "%s at offset %d: nesting deeper than %d", ur_path_text(st, path, ""),
                                  o - st->base,
                                  UR_MAX_VALUE_DEPTH);
        return -1;
    }
    const ur_value_kind *kind = &vt->kinds[code];
    if (kind->name == NULL) {
        *err = wmem_strdup_printf(pool, "%s at offset %d: unknown value type %u", ur_path_text(st, path, ".type"),
                                  o - st->base, code);
        return -1;
    }
    int start = o;
    char text[80];
    snprintf(text, sizeof text, "%s: %s", label, kind->name);
    proto_item *item = ur_add_labelled(st, tree, vf->item, o, 1, text);
    proto_tree *sub = ur_sub(item);
    if (ur_room(st, sub))
        proto_tree_add_string(sub, ur_hf(vf->type), st->tvb, o, 1, kind->name);
    ur_add(st, sub, vf->code, o, 1, ENC_BIG_ENDIAN);
    o += 1;
    int len = (int)kind->len;
    if (kind->layout == UR_V_SCALAR || kind->layout == UR_V_ARRAY) {
        int need = (int)(kind->n * kind->count);
        if (o + need > e) {
            *err = ur_short(st, path, "", o, need, e);
            return -1;
        }
        for (unsigned i = 0; i < kind->count; i++) {
            ur_add(st, sub, vf->kinds[kind->item], o, (int)kind->n, ENC_BIG_ENDIAN);
            o += (int)kind->n;
        }
    } else if (kind->layout == UR_V_STRING) {
        if (o + len > e) {
            *err = ur_short(st, path, "", o, len, e);
            return -1;
        }
        gint64 n = ur_int_at(st->tvb, o, kind->len, TRUE);
        if (n < 0) {
            *err = ur_negative(st, path, "", o, n);
            return -1;
        }
        ur_add(st, sub, vf->count, o, len, ENC_BIG_ENDIAN);
        o += len;
        if (o + n > e) {
            *err = ur_short(st, path, "", o, n, e);
            return -1;
        }
        ur_add_text(st, sub, vf->string, o, (int)n);
        o += (int)n;
    } else if (kind->layout == UR_V_LIST) {
        if (o + len > e) {
            *err = ur_short(st, path, "", o, len, e);
            return -1;
        }
        gint64 n = ur_int_at(st->tvb, o, kind->len, TRUE);
        if (n < 0) {
            *err = ur_negative(st, path, "", o, n);
            return -1;
        }
        if ((*err = ur_too_many(st, vt, path, o, n, o + len, e)) != NULL)
            return -1;
        ur_add(st, sub, vf->count, o, len, ENC_BIG_ENDIAN);
        o += len;
        for (gint64 i = 0; i < n; i++) {
            char item_label[32];
            ur_path at = { path, NULL, i, FALSE };
            snprintf(item_label, sizeof item_label, "Item %" G_GINT64_MODIFIER "d", i);
            o = ur_walk_value(st, sub, o, e, vf, vt, item_label, &at, depth + 1, err);
            if (o < 0)
                return -1;
        }
    } else if (kind->layout == UR_V_MATRIX) {
        if (o + 2 * len > e) {
            *err = ur_short(st, path, "", o, 2 * len, e);
            return -1;
        }
        gint64 rows = ur_int_at(st->tvb, o, kind->len, TRUE), cols = ur_int_at(st->tvb, o + len, kind->len, TRUE);
        if (rows < 0) {
            *err = ur_negative(st, path, "", o, rows);
            return -1;
        }
        if (cols < 0) {
            *err = ur_negative(st, path, "", o + len, cols);
            return -1;
        }
        /* Rows of no items would take no bytes at all: any number of them fits in none. */
        if (rows > 0 && cols == 0) {
            *err = wmem_strdup_printf(pool, "%s at offset %d: %" G_GINT64_MODIFIER "d rows of 0 columns",
                                      ur_path_text(st, path, ""), o - st->base, rows);
            return -1;
        }
        if ((*err = ur_too_many(st, vt, path, o, rows * cols, o + 2 * len, e)) != NULL)
            return -1;
        ur_add(st, sub, vf->rows, o, len, ENC_BIG_ENDIAN);
        ur_add(st, sub, vf->cols, o + len, len, ENC_BIG_ENDIAN);
        o += 2 * len;
        for (gint64 r = 0; r < rows; r++) {
            char text[32];
            snprintf(text, sizeof text, "Row %" G_GINT64_MODIFIER "d", r);
            proto_item *row = ur_add_labelled(st, sub, vf->row, o, 0, text);
            ur_path row_at = { path, NULL, r, FALSE };
            int row_start = o;
            for (gint64 c = 0; c < cols; c++) {
                ur_path at = { &row_at, NULL, c, FALSE };
                snprintf(text, sizeof text, "Column %" G_GINT64_MODIFIER "d", c);
                o = ur_walk_value(st, ur_sub(row), o, e, vf, vt, text, &at, depth + 1, err);
                if (o < 0)
                    return -1;
            }
            proto_item_set_len(row, o - row_start);
        }
    }
    proto_item_set_len(item, o - start);
    return o;
}

/* Typed values, each followed by a terminator, to the end of the layout. */
static int
ur_walk_values(ur_msg *st, proto_tree *tree, int o, int e, const ur_desc *d, const ur_path *pre,
               const char **err)
{
    const ur_value_table *vt = ur_value_table_of(st->version);
    wmem_allocator_t *pool = st->pinfo->pool;
    for (unsigned i = 0; o < e; i++) {
        char label[64];
        ur_path at = { pre, d->path, i, FALSE };
        snprintf(label, sizeof label, "%s %u", d->label, i);
        o = ur_walk_value(st, tree, o, e, d->values, vt, label, &at, 1, err);
        if (o < 0)
            return -1;
        if (o >= e) {
            *err = ur_short(st, &at, "", o, 1, e);
            return -1;
        }
        guint8 b = tvb_get_guint8(st->tvb, o);
        if (b != d->n) {
            *err = wmem_strdup_printf(pool, "%s at offset %d: expected terminator 0x%02x, found 0x%02x",
                                      ur_path_text(st, &at, ""), o - st->base, d->n, b);
            return -1;
        }
        o++;
    }
    return o;
}

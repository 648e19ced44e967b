/* The Info column. It is written on every pass, tree or not, so it reads the bytes and builds no
 * tree: the descriptors marked `show` of a layout (a message's, or a robot-state package's whose
 * layout has a summary). As runtime/lua/packages/info.lua. */
/* A text field's bytes into the Info text as the Lua twin puts them there: UTF-8 with invalid
 * bytes replaced, cut at as many bytes as the field has (Wireshark's TvbRange:string keeps that
 * many bytes of the converted text), NUL bytes kept (the column then ends at the first). */
static void
ur_info_text(tvbuff_t *tvb, wmem_allocator_t *pool, int o, int len, wmem_strbuf_t *out)
{
    wmem_strbuf_t *text = wmem_strbuf_new(pool, "");
    int end = o + len;
    while (o < end) {
        int nul = tvb_find_guint8(tvb, o, end - o, 0);
        int stop = nul < 0 ? end : nul;
        wmem_strbuf_append(text, (const char *)tvb_get_string_enc(pool, tvb, o, stop - o, ENC_UTF_8));
        if (nul >= 0)
            wmem_strbuf_append_len(text, "", 1);
        o = stop + (nul >= 0 ? 1 : 0);
    }
    size_t n = wmem_strbuf_get_len(text);
    wmem_strbuf_append_len(out, wmem_strbuf_get_str(text), n > (size_t)len ? (size_t)len : n);
}

/* A new byte string in pool, formatted. */
static wmem_strbuf_t *
ur_strbuf_printf(wmem_allocator_t *pool, const char *format, ...) G_GNUC_PRINTF(2, 3);

static wmem_strbuf_t *
ur_strbuf_printf(wmem_allocator_t *pool, const char *format, ...)
{
    va_list ap;
    wmem_strbuf_t *out = wmem_strbuf_new(pool, "");
    va_start(ap, format);
    wmem_strbuf_append_vprintf(out, format, ap);
    va_end(ap);
    return out;
}

static gboolean
ur_shown_in(const ur_layout *layout)
{
    for (unsigned i = 0; i < layout->n; i++) {
        const ur_desc *d = &layout->d[i];
        if (d->show != NULL || (d->kind == UR_D_COND && ur_shown_in(d->inner)))
            return TRUE;
    }
    return FALSE;
}

/* How many descriptors of a layout the summary walks: up to its last shown one. */
static unsigned
ur_reach(const ur_layout *layout)
{
    unsigned n = 0;
    for (unsigned i = 0; i < layout->n; i++) {
        const ur_desc *d = &layout->d[i];
        if (d->show != NULL || (d->kind == UR_D_COND && ur_shown_in(d->inner)))
            n = i + 1;
    }
    return n;
}

/* The fields marked `show` of descriptors 0..last-1 from o to e, for version v, each after its
 * text, appended to out ("PROGRAM_STARTED: demo"). The offset after them, or -1 where it stopped
 * at a field it cannot step over without walking it, or one that does not fit. */
static int
ur_summarise(tvbuff_t *tvb, wmem_allocator_t *pool, int o, int e, const ur_layout *layout, unsigned last,
             guint32 v, wmem_strbuf_t *out)
{
    for (unsigned i = 0; i < last; i++) {
        const ur_desc *d = &layout->d[i];
        int size = -1;
        if (d->kind == UR_D_SCALAR || d->kind == UR_D_BITS)
            size = (int)d->n;
        else if (d->kind == UR_D_ARRAY)
            size = (int)(d->n * d->count);
        else if (d->kind == UR_D_GROUP && d->count && d->size)
            size = (int)(d->count * d->size);
        if (size >= 0) {
            if (o + size > e)
                return -1;
            if (d->show != NULL) {
                gint64 x = ur_int_at(tvb, o, d->n, (d->flags & UR_SIGNED) != 0);
                const value_string *names = d->names ? ur_enum_names(d->names, v) : d->vs;
                const char *name = names ? try_val_to_str((guint32)x, names) : NULL;
                wmem_strbuf_append(out, d->show);
                if (name != NULL)
                    wmem_strbuf_append(out, name);
                else
                    wmem_strbuf_append_printf(out, "%" G_GINT64_MODIFIER "d", x);
            }
            o += size;
        } else if (d->kind == UR_D_PSTRING) {
            if (o + (int)d->n > e)
                return -1;
            gint64 len = ur_int_at(tvb, o, d->n, (d->flags & UR_SIGNED) != 0);
            if (len < 0 || o + (int)d->n + len > e)
                return -1;
            if (d->show != NULL) {
                wmem_strbuf_append(out, d->show);
                ur_info_text(tvb, pool, o + (int)d->n, (int)len, out);
            }
            o += (int)d->n + (int)len;
        } else if (d->kind == UR_D_STRING) {
            if (d->show != NULL && e > o) {
                int len = e - o > 120 ? 120 : e - o;
                wmem_strbuf_append(out, d->show);
                ur_info_text(tvb, pool, o, len, out);
            }
            o = e;
        } else if (d->kind == UR_D_COND && d->keep == 0) {
            if (ur_version_in(v, d->low, d->high)) {
                o = ur_summarise(tvb, pool, o, e, d->inner, d->inner->n, v, out);
                if (o < 0)
                    return -1;
            }
        } else {
            return -1;
        }
    }
    return o;
}

/* The summary of a layout from o to e for version v. Info texts are byte strings (a text field
 * may hold NUL bytes: the column ends at the first, as the Lua twin's does). */
static wmem_strbuf_t *
ur_layout_summary(tvbuff_t *tvb, wmem_allocator_t *pool, int o, int e, const ur_layout *layout, guint32 v)
{
    wmem_strbuf_t *out = wmem_strbuf_new(pool, "");
    ur_summarise(tvb, pool, o, e, layout, ur_reach(layout), v, out);
    return out;
}

/* A form chosen for the message being dissected: when the stream's version is not known (no
 * Version message, no preference), a form chosen by length sets it for the rest of the message
 * (st->version), and says so (st->implied: the form's versions). */
static const ur_form *
ur_pick(const ur_forms *forms, unsigned size, ur_msg *st, guint32 *use, gboolean *by_length)
{
    const ur_form *form = ur_choose(forms, size, st->version, use, by_length);
    if (*by_length && !st->known) {
        st->version = *use;
        st->implied = form->versions;
    }
    return form;
}

/* The summaries of the robot-state packages from p to e, joined by ", ". Each package's form is
 * chosen as the tree chooses it (ur_pick), so that layout sizes set the version of a stream that
 * has not told it, tree or not; with `text` FALSE, only that is done. Stops at the first package
 * whose length does not fit: such a robot state is malformed, and what its sizes showed is not
 * taken for the stream. */
static wmem_strbuf_t *
ur_package_summary(ur_msg *st, int p, int e, const ur_message *m, gboolean text)
{
    if (!(text || !st->known))
        return NULL;
    tvbuff_t *tvb = st->tvb;
    wmem_allocator_t *pool = st->pinfo->pool;
    wmem_strbuf_t *out = text ? wmem_strbuf_new(pool, "") : NULL;
    guint32 version = st->version;
    const char *implied = st->implied;
    gboolean any = FALSE;
    while (e - p >= UR_PACKAGE_HEADER_SIZE) {
        gint64 size = ur_int_at(tvb, p, UR_PACKAGE_LENGTH_SIZE, TRUE);
        guint8 code = tvb_get_guint8(tvb, p + UR_PACKAGE_LENGTH_SIZE);
        if (size < UR_PACKAGE_HEADER_SIZE || size > e - p)
            break;
        const ur_forms *forms = m->forms[code];
        if (forms != NULL && ((text && forms->summary) || !st->known)) {
            guint32 use;
            gboolean by_length;
            const ur_form *form = ur_pick(forms, (unsigned)size - UR_PACKAGE_HEADER_SIZE, st, &use, &by_length);
            if (text && form->of->summary) {
                wmem_strbuf_t *part = wmem_strbuf_new(pool, "");
                ur_summarise(tvb, pool, p + UR_PACKAGE_HEADER_SIZE, p + (int)size, form->of->layout,
                             ur_reach(form->of->layout), use, part);
                if (wmem_strbuf_get_len(part) > 0) {
                    if (any)
                        wmem_strbuf_append(out, ", ");
                    wmem_strbuf_append_len(out, wmem_strbuf_get_str(part), wmem_strbuf_get_len(part));
                    any = TRUE;
                }
            }
        }
        p += (int)size;
    }
    if (p < e) {
        st->version = version;
        st->implied = implied;
    }
    return out;
}

/* "Label" alone, or "Label: text". */
static wmem_strbuf_t *
ur_labelled(wmem_allocator_t *pool, const char *label, const wmem_strbuf_t *text)
{
    wmem_strbuf_t *out = wmem_strbuf_new(pool, label);
    if (text != NULL && wmem_strbuf_get_len(text) > 0) {
        wmem_strbuf_append(out, ": ");
        wmem_strbuf_append_len(out, wmem_strbuf_get_str(text), wmem_strbuf_get_len(text));
    }
    return out;
}

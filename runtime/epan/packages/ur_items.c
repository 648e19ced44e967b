/* The message being dissected, and its tree items: at most UR_MAX_TREE_ITEMS under the
 * message's item. A message of a megabyte can hold hundreds of thousands of values; Wireshark
 * slows down long before it stops at a million items per packet. Past the cap the fields are
 * still walked, so that errors are still found, but they are counted instead of added (a NULL
 * item stands for them); the first expert info one of them is given goes to the message's item,
 * so that a malformed message still reads as one. As runtime/lua/packages/items.lua. */
typedef struct {
    packet_info *pinfo;
    tvbuff_t *tvb;              /* the message's bytes (carried-over bytes first, when there are) */
    tvbuff_t *call_tvb;         /* the bytes the call was handed: generated items stand at its start */
    int base;                   /* the message's first byte: error offsets count from it */
    guint32 version;            /* the version it is read with (moves on when layout sizes tell it) */
    gboolean known;             /* announced or from the preference */
    gboolean announced;         /* a Version message told it */
    gboolean from_pref;
    const char *implied;        /* the versions of the form whose size told the version, or NULL */
    guint32 message_version;    /* what the message's tree shows */
    const char *message_implied;
    gboolean visible;           /* the tree is shown: item texts are worth writing */
    gboolean only;              /* a tshark -T fields run: only the packages it names (ur_only_named_packages) */
    gint64 kept[UR_KEEP_SLOTS]; /* values later fields depend on (present_if, switch) */
    gboolean kept_set[UR_KEEP_SLOTS];
    /* the tree cap */
    int left, hidden;
    proto_item *top;
    gboolean expert_moved;
} ur_msg;

static void
ur_items_begin(ur_msg *st, proto_item *top)
{
    st->left = UR_MAX_TREE_ITEMS;
    st->hidden = 0;
    st->top = top;
    st->expert_moved = FALSE;
}

/* The subtree of an item; NULL (past the cap) stays NULL. */
static inline proto_tree *
ur_sub(proto_item *item)
{
    return item ? proto_item_add_subtree(item, ett_ur_item) : NULL;
}

/* Room for one more item under tree (NULL: its parent was past the cap); counted. */
static inline gboolean
ur_room(ur_msg *st, proto_tree *tree)
{
    if (tree != NULL && st->left > 0) {
        st->left--;
        return TRUE;
    }
    st->hidden++;
    return FALSE;
}

static inline int
ur_hf(int field)
{
    return field < 0 ? -1 : hf_ur[field];
}

/* tree:add(f, tvb(o, n)); counted. */
static proto_item *
ur_add(ur_msg *st, proto_tree *tree, int field, int o, int n, guint encoding)
{
    if (!ur_room(st, tree))
        return NULL;
    return proto_tree_add_item(tree, ur_hf(field), st->tvb, o, n, encoding);
}

/* A subtree item with its own text (a group's "Joint 0"); counted. Item texts are written only
 * where the tree is shown: a field no one asked for is the parent's item, faked by Wireshark. */
static proto_item *
ur_add_labelled(ur_msg *st, proto_tree *tree, int field, int o, int n, const char *label)
{
    proto_item *item = ur_add(st, tree, field, o, n, ENC_NA);
    if (item && st->visible)
        proto_item_set_text(item, "%s", label);
    return item;
}

/* An expert info on item; past the cap, the first goes to the message's item. */
static void
ur_expert(ur_msg *st, proto_item *item, expert_field *ei, const char *text)
{
    if (item == NULL) {
        if (st->expert_moved) {
            st->hidden++;
            return;
        }
        st->expert_moved = TRUE;
        item = st->top;
    }
    expert_add_info_format(st->pinfo, item, ei, "%s", text);
}

/* State of each TCP conversation: the software version its Version message announced or its
 * layout sizes showed (UR_VERSION_NONE: none yet; `implied` names the versions of the form whose
 * size showed it), whether the dissector is resynchronising after a bad header, and the bytes
 * carried over from earlier segments while it does. First pass: the state moves along. Later
 * passes (tshark -2, clicks in the GUI, in any order) start each dissector call (frame and tvb
 * length) with the state its first-pass call started with. That state changes rarely, so it is
 * kept only where it changes: a frame in which some call starts with another state than the call
 * before it keeps a snapshot per call (frame data); a frame that keeps nothing starts with the
 * state the last call of the last kept frame before it started with (a tree by frame number). A
 * capture in step costs memory per conversation, not per frame. As runtime/lua/packages/stream.lua. */
/* Bytes carried over by hand while a stream is out of step with TCP reassembly: only appended
 * to, so its first k bytes, where a call started, stay the same for later passes. */
typedef struct {
    wmem_array_t *bytes;
} ur_carry;

typedef struct {
    guint32 version;
    const char *implied;
    gboolean resync;
    ur_carry *carry;
    unsigned carried;           /* how many bytes the carry held */
} ur_snap;

#define UR_PENDING 16           /* calls of one frame remembered before the frame is kept */

typedef struct {
    guint32 version;            /* the state now */
    const char *implied;
    gboolean resync;
    ur_carry *carry;
    const ur_snap *last;        /* the snapshot the latest call started with */
    guint32 frame;              /* that call's frame */
    gboolean keeping;           /* whether that frame is kept */
    unsigned n;                 /* while it is not: its calls so far */
    guint32 keys[UR_PENDING];
    const ur_snap *snaps[UR_PENDING];
    wmem_tree_t *after;         /* kept frame -> the snapshot its last call started with */
} ur_stream;

static const ur_snap ur_none = { UR_VERSION_NONE, NULL, FALSE, NULL, 0 };

#define UR_FRAME_KEY 0u         /* frame data: the snapshot of a kept frame's first call */

static unsigned
ur_carry_size(const ur_carry *c)
{
    return wmem_array_get_count(c->bytes);
}

static ur_carry *
ur_carry_new(const guint8 *bytes, unsigned n)
{
    ur_carry *c = wmem_new(wmem_file_scope(), ur_carry);
    c->bytes = wmem_array_sized_new(wmem_file_scope(), 1, n > 64 ? n : 64);
    if (n > 0)
        wmem_array_append(c->bytes, bytes, n);
    return c;
}

static ur_stream *
ur_stream_of(packet_info *pinfo)
{
    conversation_t *conv = find_or_create_conversation(pinfo);
    ur_stream *s = (ur_stream *)conversation_get_proto_data(conv, proto_ur);
    if (s == NULL) {
        s = wmem_new0(wmem_file_scope(), ur_stream);
        s->version = UR_VERSION_NONE;
        s->last = &ur_none;
        s->frame = G_MAXUINT32;
        s->after = wmem_tree_new(wmem_file_scope());
        conversation_add_proto_data(conv, proto_ur, s);
    }
    return s;
}

static gboolean
ur_same(const ur_snap *snap, const ur_stream *s, unsigned carried)
{
    return snap->version == s->version && snap->implied == s->implied && snap->resync == s->resync
        && snap->carry == s->carry && snap->carried == carried;
}

static void
ur_keep_call(packet_info *pinfo, guint32 key, const ur_snap *snap)
{
    if (p_get_proto_data(wmem_file_scope(), pinfo, proto_ur, key) == NULL)
        p_add_proto_data(wmem_file_scope(), pinfo, proto_ur, key, (void *)snap);
}

/* The first pass: the call starts with the stream's state now; kept when it differs from the
 * state the call before it started with, and so is every call of its frame. */
static const ur_snap *
ur_note(packet_info *pinfo, ur_stream *s, guint32 key)
{
    guint32 frame = pinfo->num;
    unsigned carried = s->carry ? ur_carry_size(s->carry) : 0;
    const ur_snap *snap = s->last;
    gboolean changed = FALSE;
    if (!ur_same(snap, s, carried)) {
        ur_snap *made = wmem_new(wmem_file_scope(), ur_snap);
        made->version = s->version;
        made->implied = s->implied;
        made->resync = s->resync;
        made->carry = s->carry;
        made->carried = carried;
        snap = made;
        changed = TRUE;
    }
    s->last = snap;
    if (frame != s->frame) {
        s->frame = frame;
        s->keeping = FALSE;
        s->n = 0;
    }
    if ((changed || s->n == UR_PENDING) && !s->keeping) {
        s->keeping = TRUE;
        for (unsigned i = 0; i < s->n; i++)
            ur_keep_call(pinfo, s->keys[i], s->snaps[i]);
        if (s->n > 0)
            ur_keep_call(pinfo, UR_FRAME_KEY, s->snaps[0]);
    }
    if (s->keeping) {
        ur_keep_call(pinfo, key, snap);
        ur_keep_call(pinfo, UR_FRAME_KEY, snap);
        wmem_tree_insert32(s->after, frame, (void *)snap);
    } else {
        s->keys[s->n] = key;
        s->snaps[s->n] = snap;
        s->n++;
    }
    return snap;
}

/* A later pass: the snapshot of the call, else of its frame's first call, else of the frames
 * before it. */
static const ur_snap *
ur_recall(packet_info *pinfo, guint32 key)
{
    const ur_snap *snap = (const ur_snap *)p_get_proto_data(wmem_file_scope(), pinfo, proto_ur, key);
    if (snap == NULL)
        snap = (const ur_snap *)p_get_proto_data(wmem_file_scope(), pinfo, proto_ur, UR_FRAME_KEY);
    if (snap != NULL)
        return snap;
    ur_stream *s = ur_stream_of(pinfo);
    if (pinfo->num == 0)
        return &ur_none;
    snap = (const ur_snap *)wmem_tree_lookup32_le(s->after, pinfo->num - 1);
    return snap ? snap : &ur_none;
}

/* The state as a call with n bytes starts. */
static const ur_snap *
ur_stream_load(packet_info *pinfo, unsigned n)
{
    guint32 key = n % 1048576u + 1;
    if (PINFO_FD_VISITED(pinfo))
        return ur_recall(pinfo, key);
    return ur_note(pinfo, ur_stream_of(pinfo), key);
}

/* The state as a call ends; kept on the first pass only. */
static void
ur_stream_save(packet_info *pinfo, guint32 version, const char *implied, gboolean resync, ur_carry *carry)
{
    if (PINFO_FD_VISITED(pinfo))
        return;
    ur_stream *s = ur_stream_of(pinfo);
    s->version = version;
    s->implied = implied;
    s->resync = resync;
    s->carry = carry;
}

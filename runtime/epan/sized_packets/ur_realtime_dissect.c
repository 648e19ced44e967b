/* The real-time dissector's runtime: frames the robot's TCP stream by each packet's int32 size
 * (asking TCP to reassemble a packet split over segments), chooses the packet's layout by the
 * spec's same-size rule over the generated ur_realtime_sizes and ur_realtime_forms, and walks the
 * layout's slots into the tree. What a client sends to the port is URScript text. The interface
 * has no version message: the only state is the software-version preference, and nothing is kept
 * per conversation. Without a tree only the framing and the Info column's words are worked out.
 *
 * It is the twin of runtime/lua/sized_packets/dissect.lua: the same fields, tree, Info column,
 * expert infos and preferences, so that either dissector can stand for the other. */
/* <standalone> */
#include <ws_version.h>
#include <epan/packet.h>
#include <epan/expert.h>
#include <epan/prefs.h>
#include <epan/proto_data.h>
#include <epan/dissectors/packet-tcp.h>
#include "ur_realtime_types.h"
#include "../../c/common/version_text.c"
#define UR_REALTIME_SIZE_BYTES 4
#define UR_REALTIME_MIN_SIZE 12
#define UR_REALTIME_MAX_SIZE 12200
#define UR_REALTIME_PORTS "30003"
static int proto_ur_realtime = -1;
static int hf_ur_realtime_message_size = -1;
static gint ett_ur_realtime = -1;
static const ur_realtime_form ur_realtime_forms[1];
static const ur_realtime_size_forms ur_realtime_sizes[1];
/* </standalone> */

/* The dissector's own fields and experts, beside the spec's. */
static int hf_ur_realtime_layout = -1;
static int hf_ur_realtime_urscript = -1;
static int hf_ur_realtime_raw = -1;

/* A size no layout has (framed and kept: a layout the spec does not know yet, not a broken
 * stream), and a size that cannot frame a packet; and the Lua twin's guard, registered alike (a
 * packet this dissector has framed is read within its bytes and cannot fail). */
static expert_field ei_ur_realtime_unknown_size = EI_INIT;
static expert_field ei_ur_realtime_bad_size = EI_INIT;
static expert_field ei_ur_realtime_internal_error = EI_INIT;

static dissector_handle_t ur_realtime_handle;

/* Preferences: the ports, and the software version that chooses among layouts of one size. */
static range_t *ur_realtime_pref_ports;
static range_t *ur_realtime_registered_ports;
static const char *ur_realtime_pref_version = "";
static gboolean ur_realtime_version_known;
static double ur_realtime_version;

/* The version preference's text -> the version number the forms are written in (a bugfix above
 * 999 counts as 999); FALSE for text that is not a version. */
static gboolean ur_realtime_parse_version(const char *text, double *number)
{
    urwire__version_text v;

    if (text == NULL || !urwire__read_version(text, text + strlen(text), true, false, &v))
        return FALSE;
    *number = ((double)v.part[0] * 1000 + (double)v.part[1]) * 1000 + (double)MIN(v.part[2], 999);
    return TRUE;
}

/* The same-size rule: the first form of the size whose versions hold the version, else the last;
 * NULL for a size no layout has. */
static const ur_realtime_form *ur_realtime_form_of(gint32 size)
{
    guint i, j;

    for (i = 0; i < G_N_ELEMENTS(ur_realtime_sizes); i++) {
        const ur_realtime_size_forms *entry = &ur_realtime_sizes[i];
        if (entry->size != size)
            continue;
        if (ur_realtime_version_known) {
            for (j = entry->first; j < entry->first + entry->count; j++) {
                if (ur_realtime_forms[j].low <= ur_realtime_version && ur_realtime_version <= ur_realtime_forms[j].high)
                    return &ur_realtime_forms[j];
            }
        }
        return &ur_realtime_forms[entry->first + entry->count - 1];
    }
    return NULL;
}

/* An enum code's name: a double that holds a whole code the table names, else NULL. */
static const char *ur_realtime_name_of(double value, const value_string *names)
{
    if (names == NULL || !(value >= G_MININT32 && value <= G_MAXINT32) || (double)(gint32)value != value)
        return NULL;
    return try_val_to_str((guint32)(gint32)value, names);
}

/* The flags of a whole value from 0 up to 2^32 - 1 (none for another): one per named bit. */
static void ur_realtime_add_flags(proto_item *item, const ur_realtime_slot *slot, tvbuff_t *tvb, gint at, double value)
{
    proto_tree *tree;
    guint i;

    if (!(value >= 0 && value < 4294967296.0) || (double)(guint32)value != value)
        return;
    tree = proto_item_add_subtree(item, *slot->flags_ett);
    for (i = 0; i < slot->n_flags; i++)
        proto_tree_add_boolean(tree, slot->flags[i], tvb, at, 8, (guint32)value);
}

/* One double, the k-th of its slot (its field's label shows its unit: a named item's own); an enum
 * code's name after it where the form has one, and its flags where the field names its bits. */
static void ur_realtime_add_value(proto_tree *tree, const ur_realtime_slot *slot, guint k, tvbuff_t *tvb, gint at,
                                  const value_string *names)
{
    proto_item *item = proto_tree_add_item(tree, slot->hf[slot->named ? k : 0], tvb, at, 8, ENC_BIG_ENDIAN);
    const char *name;

    if (slot->flags != NULL)
        ur_realtime_add_flags(item, slot, tvb, at, tvb_get_ntohieee_double(tvb, at));
    if (names == NULL)
        return;
    name = ur_realtime_name_of(tvb_get_ntohieee_double(tvb, at), names);
    if (name != NULL)
        proto_item_append_text(item, " (%s)", name);
}

/* The Info column's words for a packet of a known layout: its name, and its robot mode's. */
static const char *ur_realtime_info_of(tvbuff_t *tvb, packet_info *pinfo, const ur_realtime_form *form)
{
    const ur_realtime_layout *layout = form->layout;
    const char *mode;

    if (layout->info_at < 0 || layout->info_names < 0)
        return layout->name;
    mode = ur_realtime_name_of(tvb_get_ntohieee_double(tvb, layout->info_at), form->names[layout->info_names]);
    return mode ? wmem_strdup_printf(pinfo->pool, "%s, %s", layout->name, mode) : layout->name;
}

/* What one call of the dissector shows in the Info column: the first packet's words and how many
 * packets there were (the words of the others are never formatted). */
typedef struct {
    const char *first;
    guint count;
} ur_realtime_infos;

/* TCP calls the dissector once per reassembled packet and again for the rest of a segment: a
 * later call of the same frame adds its words to the earlier one's, when the column still holds
 * them (what this dissection of the frame showed is kept in packet scope). */
static void ur_realtime_show_info(packet_info *pinfo, const char *words)
{
    const char *shown = (const char *)p_get_proto_data(pinfo->pool, pinfo, proto_ur_realtime, 0);
    const char *column = col_get_text(pinfo->cinfo, COL_INFO);

    if (shown != NULL && column != NULL && g_strcmp0(shown, column) == 0) {
        col_append_str(pinfo->cinfo, COL_INFO, ", ");
        col_append_str(pinfo->cinfo, COL_INFO, words);
        shown = wmem_strdup_printf(pinfo->pool, "%s, %s", shown, words);
    } else {
        col_add_str(pinfo->cinfo, COL_INFO, words);
        shown = words;
    }
    p_set_proto_data(pinfo->pool, pinfo, proto_ur_realtime, 0, (void *)shown);
}

/* A packet of a size no layout has: its bytes, kept, and a warning. */
static void ur_realtime_unknown(tvbuff_t *tvb, packet_info *pinfo, proto_item *item, proto_tree *tree, gint32 size)
{
    proto_item_append_text(item, ", unknown size %d", size);
    proto_tree_add_item(tree, hf_ur_realtime_raw, tvb, UR_REALTIME_SIZE_BYTES, size - UR_REALTIME_SIZE_BYTES, ENC_NA);
    expert_add_info_format(pinfo, item, &ei_ur_realtime_unknown_size, "Packet size %d matches no layout", size);
}

/* The slots of a known layout, each double under the packet's tree or its array's subtree. */
static void ur_realtime_walk(tvbuff_t *tvb, proto_tree *tree, const ur_realtime_form *form)
{
    const ur_realtime_layout *layout = form->layout;
    guint i, k;

    for (i = 0; i < layout->n_slots; i++) {
        const ur_realtime_slot *slot = &layout->slots[i];
        const value_string *names = slot->names >= 0 ? form->names[slot->names] : NULL;
        if (slot->ett == NULL) {
            ur_realtime_add_value(tree, slot, 0, tvb, slot->offset, names);
            continue;
        }
        proto_tree *group = proto_tree_add_subtree(tree, tvb, slot->offset, 8 * slot->count, *slot->ett, NULL,
                                                   slot->group);
        for (k = 0; k < slot->count; k++)
            ur_realtime_add_value(group, slot, k, tvb, slot->offset + 8 * k, names);
    }
}

/* One whole packet. */
static int dissect_ur_realtime_packet(tvbuff_t *tvb, packet_info *pinfo, proto_tree *tree, void *data)
{
    ur_realtime_infos *infos = (ur_realtime_infos *)data;
    gint32 size = tvb_get_ntohil(tvb, 0);
    gboolean first = infos->count++ == 0;
    const ur_realtime_form *form;
    proto_item *item;
    proto_tree *sub;

    form = ur_realtime_form_of(size);
    if (first && form != NULL)
        infos->first = ur_realtime_info_of(tvb, pinfo, form);
    if (form != NULL && tree == NULL)
        return size;
    item = proto_tree_add_item(tree, proto_ur_realtime, tvb, 0, size, ENC_NA);
    sub = proto_item_add_subtree(item, ett_ur_realtime);
    proto_tree_add_item(sub, hf_ur_realtime_message_size, tvb, 0, UR_REALTIME_SIZE_BYTES, ENC_BIG_ENDIAN);
    if (form == NULL) {
        ur_realtime_unknown(tvb, pinfo, item, sub, size);
        if (first)
            infos->first = wmem_strdup_printf(pinfo->pool, "Unknown size %d", size);
        return size;
    }
    proto_item_append_text(item, ", %s", form->layout->name);
    proto_item_set_generated(proto_tree_add_string(sub, hf_ur_realtime_layout, tvb, 0, 0, form->layout->name));
    ur_realtime_walk(tvb, sub, form);
    return size;
}

/* Where the next plausible packet starts from `offset` on: the next size some layout has (a size
 * no layout has is not trusted, since a packet's doubles hold small int32s often enough); -1 when
 * the bytes up to `end` hold none whole. */
static gint ur_realtime_next_packet(tvbuff_t *tvb, gint offset, gint end)
{
    for (; end - offset >= UR_REALTIME_SIZE_BYTES; offset++) {
        gint32 size = tvb_get_ntohil(tvb, offset);
        if (size >= UR_REALTIME_MIN_SIZE && size <= UR_REALTIME_MAX_SIZE && ur_realtime_form_of(size) != NULL)
            return offset;
    }
    return -1;
}

/* The bytes skipped after a size that cannot frame a packet, named by one error. */
static void ur_realtime_bad_size(tvbuff_t *tvb, packet_info *pinfo, proto_tree *tree, gint offset, gint length,
                                 gint32 size, ur_realtime_infos *infos)
{
    proto_item *item = proto_tree_add_item(tree, proto_ur_realtime, tvb, offset, length, ENC_NA);

    expert_add_info_format(pinfo, item, &ei_ur_realtime_bad_size, "Packet size %d cannot frame a packet (%d to %d)",
                           size, UR_REALTIME_MIN_SIZE, UR_REALTIME_MAX_SIZE);
    if (infos->count++ == 0)
        infos->first = wmem_strdup_printf(pinfo->pool, "Bad size %d", size);
}

/* TCP asks for this: the bytes from `offset` on wait for `more` bytes of the next segments
 * (ignored when TCP reassembly is off, where a packet split over segments is not shown). */
static void ur_realtime_desegment(packet_info *pinfo, gint offset, guint32 more)
{
    pinfo->desegment_offset = offset;
    pinfo->desegment_len = more;
}

/* The segment's (or reassembled bytes') whole packets, as the Lua twin frames them: a packet the
 * segment does not hold whole waits for the next; after a size that cannot frame a packet (the
 * middle of one, after a lost segment) the bytes up to the next size some layout has are skipped,
 * and where the segment holds none its last 3 bytes, which may begin one, wait. (tcp_dissect_pdus
 * cannot scan.) */
static void ur_realtime_frame(tvbuff_t *tvb, packet_info *pinfo, proto_tree *tree, ur_realtime_infos *infos)
{
    gint offset = 0, end = (gint)tvb_captured_length(tvb);

    while (offset < end) {
        gint left = end - offset, next;
        gint32 size;

        if (left < UR_REALTIME_SIZE_BYTES) {
            ur_realtime_desegment(pinfo, offset, DESEGMENT_ONE_MORE_SEGMENT);
            return;
        }
        size = tvb_get_ntohil(tvb, offset);
        if (size < UR_REALTIME_MIN_SIZE || size > UR_REALTIME_MAX_SIZE) {
            next = ur_realtime_next_packet(tvb, offset + 1, end);
            if (next < 0) {     /* none here: the last bytes may open a size the next segment ends */
                gint kept = end - (UR_REALTIME_SIZE_BYTES - 1);
                ur_realtime_bad_size(tvb, pinfo, tree, offset, kept - offset, size, infos);
                ur_realtime_desegment(pinfo, kept, DESEGMENT_ONE_MORE_SEGMENT);
                return;
            }
            ur_realtime_bad_size(tvb, pinfo, tree, offset, next - offset, size, infos);
            offset = next;
        } else if (left < size) {
            ur_realtime_desegment(pinfo, offset, (guint32)(size - left));
            return;
        } else {
            offset += dissect_ur_realtime_packet(tvb_new_subset_length(tvb, offset, size), pinfo, tree, infos);
        }
    }
}

static int dissect_ur_realtime(tvbuff_t *tvb, packet_info *pinfo, proto_tree *tree, void *data _U_)
{
    ur_realtime_infos infos = {NULL, 0};

    col_set_str(pinfo->cinfo, COL_PROTOCOL, "UR real-time");
    if (pinfo->srcport != pinfo->match_uint) {
        /* Client to robot: URScript text, not decoded. */
        proto_item *item = proto_tree_add_item(tree, proto_ur_realtime, tvb, 0, -1, ENC_NA);
        proto_tree_add_item(proto_item_add_subtree(item, ett_ur_realtime), hf_ur_realtime_urscript, tvb, 0, -1,
                            ENC_ASCII);
        ur_realtime_show_info(pinfo, "URScript");
        return tvb_captured_length(tvb);
    }
    ur_realtime_frame(tvb, pinfo, tree, &infos);
    if (infos.count == 1)
        ur_realtime_show_info(pinfo, infos.first);
    else if (infos.count > 1)
        ur_realtime_show_info(pinfo, wmem_strdup_printf(pinfo->pool, "%s (+%u)", infos.first, infos.count - 1));
    return tvb_captured_length(tvb);
}

/* The ports preference, applied: the dissector leaves the ports it had and takes the new ones;
 * the version preference is read once here, not per packet. */
static void ur_realtime_apply_prefs(void)
{
    ur_realtime_version_known = ur_realtime_parse_version(ur_realtime_pref_version, &ur_realtime_version);
    if (ur_realtime_registered_ports != NULL) {
        dissector_delete_uint_range("tcp.port", ur_realtime_registered_ports, ur_realtime_handle);
        wmem_free(wmem_epan_scope(), ur_realtime_registered_ports);
    }
    ur_realtime_registered_ports = range_copy(wmem_epan_scope(), ur_realtime_pref_ports);
    dissector_add_uint_range("tcp.port", ur_realtime_registered_ports, ur_realtime_handle);
}

/* What proto_register_ur_realtime adds to the spec's fields: the dissector, its own fields and
 * experts, and the preferences. */
static void ur_realtime_register_runtime(void)
{
    static hf_register_info hf[] = {
        { &hf_ur_realtime_layout,
          { "Layout", "ur_realtime.layout", FT_STRING, BASE_NONE, NULL, 0x0,
            "The packet layout its size names, and the versions that send it.", HFILL } },
        { &hf_ur_realtime_urscript,
          { "URScript", "ur_realtime.urscript", FT_STRING, BASE_NONE, NULL, 0x0,
            "URScript text the client sends to the robot.", HFILL } },
        { &hf_ur_realtime_raw,
          { "Bytes of a packet of unknown size", "ur_realtime.raw", FT_BYTES, BASE_NONE, NULL, 0x0,
            "A packet whose size names no layout of the spec, shown whole.", HFILL } },
    };
    static ei_register_info ei[] = {
        { &ei_ur_realtime_unknown_size,
          { "ur_realtime.unknown_size", PI_PROTOCOL, PI_WARN, "Packet size matches no layout", EXPFILL } },
        { &ei_ur_realtime_bad_size,
          { "ur_realtime.bad_size", PI_MALFORMED, PI_ERROR, "Packet size cannot frame a packet", EXPFILL } },
        { &ei_ur_realtime_internal_error,
          { "ur_realtime.internal_error", PI_MALFORMED, PI_ERROR, "Dissector error", EXPFILL } },
    };
    module_t *module;

    proto_register_field_array(proto_ur_realtime, hf, array_length(hf));
    expert_register_field_array(expert_register_protocol(proto_ur_realtime), ei, array_length(ei));
    ur_realtime_handle = register_dissector("ur_realtime", dissect_ur_realtime, proto_ur_realtime);

    module = prefs_register_protocol(proto_ur_realtime, ur_realtime_apply_prefs);
    range_convert_str(wmem_epan_scope(), &ur_realtime_pref_ports, UR_REALTIME_PORTS, 65535);
    prefs_register_range_preference(module, "ports", "Ports", "TCP ports of the real-time interface",
                                    &ur_realtime_pref_ports, 65535);
    prefs_register_string_preference(module, "version", "Software version",
                                     "The controller's software version (5.9, 3.15.2): chooses among layouts that "
                                     "share a size; empty: the newest of them", &ur_realtime_pref_version);
}

/* Ports and Decode As. */
static void ur_realtime_handoff_runtime(void)
{
    dissector_add_for_decode_as("tcp.port", ur_realtime_handle);
    ur_realtime_apply_prefs();
}

/* A dissector of fixed int32 records (the ROS driver's reverse, trajectory and script command
 * sockets): each direction cut into records of the size the driver release gives (a preference;
 * a capture does not tell it), reassembled across TCP segments by tcp_dissect_pdus, every int32
 * shown as its field, scaled fields with their value and their raw int32, enums by name. The
 * control PC listens on the port and the robot's script connects, so bytes to the port come from
 * the robot. Without a tree only the framing and the Info column's count are worked out.
 *
 * The twin of runtime/lua/int32_records.lua: the same fields, tree, Info column, expert infos
 * and preference, so that either dissector can stand for the other. The generated part of the
 * file gives INT32_RECORDS_NAME, _COLUMN, _PORTS, _DEFAULT_RELEASE, _DEFAULT_TEXT and int32_records_spec. */
/* <standalone> */
#include <epan/packet.h>
#include <epan/expert.h>
#include <epan/prefs.h>
#include <epan/dissectors/packet-tcp.h>
#include "int32_records_types.h"
#include "../../c/common/version_text.c"
#define INT32_RECORDS_NAME "ur_reverse"
#define INT32_RECORDS_COLUMN "UR reverse"
#define INT32_RECORDS_PORTS "50001"
#define INT32_RECORDS_DEFAULT_RELEASE 2014000
#define INT32_RECORDS_DEFAULT_TEXT "2.14"
static const int32_records_interface int32_records_spec;
/* </standalone> */

/* Bytes in a direction where the spec has no record; and the Lua twin's guard, registered alike
 * (a record this dissector has framed is read within its bytes and cannot fail). */
static expert_field ei_int32_records_unspecified = EI_INIT;
static expert_field ei_int32_records_internal_error = EI_INIT;

static dissector_handle_t int32_records_handle;

/* The driver release preference, read when it changes. */
static const char *int32_records_pref_release = "";
static guint32 int32_records_release = INT32_RECORDS_DEFAULT_RELEASE;

/* The release preference's text -> (major * 1000 + minor) * 1000 + patch; the default release
 * for text that is not a release. */
static guint32 int32_records_parse_release(const char *text)
{
    urwire__version_text v;
    double number;

    if (text == NULL || !urwire__read_version(text, text + strlen(text), true, false, &v))
        return INT32_RECORDS_DEFAULT_RELEASE;
    number = ((double)v.part[0] * 1000 + (double)v.part[1]) * 1000 + (double)v.part[2];
    return number < G_MAXUINT32 ? (guint32)number : G_MAXUINT32;
}

/* The layout a release sends: the last whose first release it has reached. */
static const int32_records_layout *int32_records_layout_of(const int32_records_record *record, guint32 release)
{
    guint i, layout = 0;

    for (i = 0; i < record->n_starts; i++) {
        if (release >= record->starts[i])
            layout = i + 1;
    }
    return &record->layouts[layout];
}

/* What one call of the dissector is reading, and how many records it showed. */
typedef struct {
    const int32_records_record *record;
    const int32_records_layout *layout;
    guint count;
} int32_records_call;

static guint int32_records_size(packet_info *pinfo _U_, tvbuff_t *tvb _U_, int offset _U_, void *data)
{
    return ((const int32_records_call *)data)->layout->size;
}

static void int32_records_show_slot(proto_tree *tree, tvbuff_t *tvb, const int32_records_slot *slot)
{
    guint k;

    for (k = 0; k < slot->count; k++) {
        gint at = 4 * (slot->first + k);
        if (slot->scale != 0) {
            gint32 raw = tvb_get_ntohil(tvb, at);
            proto_item *item = proto_tree_add_double(tree, *slot->hf, tvb, at, 4, (double)raw / slot->scale);
            proto_item_append_text(item, " (raw %d, scaled by %s = %d)", raw, slot->scale_name, slot->scale);
            proto_tree_add_int(proto_item_add_subtree(item, *int32_records_spec.ett_scaled), *slot->hf_raw, tvb, at,
                               4, raw);
        } else {
            proto_tree_add_item(tree, *slot->hf, tvb, at, 4, ENC_BIG_ENDIAN);
        }
    }
}

/* One whole record; or, when TCP cannot reassemble, the part of one that this segment holds. */
static int int32_records_dissect_record(tvbuff_t *tvb, packet_info *pinfo _U_, proto_tree *tree, void *data)
{
    int32_records_call *call = (int32_records_call *)data;
    const int32_records_layout *layout = call->layout;
    proto_item *item;
    proto_tree *sub;
    guint i;

    if (tvb_captured_length(tvb) < layout->size) {
        item = proto_tree_add_item(tree, *int32_records_spec.proto, tvb, 0, -1, ENC_NA);
        proto_item_set_text(item, "Part of a record (reassembly is off)");
        return tvb_captured_length(tvb);
    }
    call->count++;
    if (tree == NULL)
        return layout->size;
    item = proto_tree_add_item(tree, *int32_records_spec.proto, tvb, 0, layout->size, ENC_NA);
    proto_item_set_text(item, "%s", call->record->label);
    sub = proto_item_add_subtree(item, *int32_records_spec.ett);
    for (i = 0; i < layout->n_slots; i++)
        int32_records_show_slot(sub, tvb, &layout->slots[i]);
    return layout->size;
}

/* Without TCP reassembly (its preference off) each segment is read on its own, as the Lua twin
 * reads it: its whole records, then the part of one it holds. (Given a cut record,
 * tcp_dissect_pdus would mark the segments after it as its continuation.) */
static void int32_records_each_whole_record(tvbuff_t *tvb, packet_info *pinfo, proto_tree *tree,
                                            int32_records_call *call)
{
    guint offset = 0;

    while (offset < tvb_captured_length(tvb))
        offset += int32_records_dissect_record(tvb_new_subset_remaining(tvb, offset), pinfo, tree, call);
}

static int dissect_int32_records(tvbuff_t *tvb, packet_info *pinfo, proto_tree *tree, void *data _U_)
{
    gboolean from_robot = pinfo->destport == pinfo->match_uint;
    int32_records_call call = {from_robot ? int32_records_spec.from_robot : int32_records_spec.to_robot, NULL, 0};

    col_set_str(pinfo->cinfo, COL_PROTOCOL, INT32_RECORDS_COLUMN);
    if (call.record == NULL) {
        proto_item *item = proto_tree_add_item(tree, *int32_records_spec.proto, tvb, 0, -1, ENC_NA);
        expert_add_info(pinfo, item, &ei_int32_records_unspecified);
        return tvb_captured_length(tvb);
    }
    call.layout = int32_records_layout_of(call.record, int32_records_release);
    /* The size is known without reading: fixed_len 1 has TCP ask for exactly the bytes a cut
     * record lacks, as the Lua twin asks. */
    if (pinfo->can_desegment)
        tcp_dissect_pdus(tvb, pinfo, tree, TRUE, 1, int32_records_size, int32_records_dissect_record, &call);
    else
        int32_records_each_whole_record(tvb, pinfo, tree, &call);
    if (call.count == 1)
        col_add_str(pinfo->cinfo, COL_INFO, call.record->label);
    else if (call.count > 1)
        col_add_fstr(pinfo->cinfo, COL_INFO, "%s x%u", call.record->label, call.count);
    return tvb_captured_length(tvb);
}

static void int32_records_apply_prefs(void)
{
    int32_records_release = int32_records_parse_release(int32_records_pref_release);
}

/* What proto_register_<name> adds to the spec's fields: the dissector, its experts and the
 * release preference. */
static void int32_records_register_runtime(void)
{
    static ei_register_info ei[] = {
        { &ei_int32_records_unspecified,
          { INT32_RECORDS_NAME ".unspecified", PI_UNDECODED, PI_WARN,
            "Bytes in a direction where no record is specified", EXPFILL } },
        { &ei_int32_records_internal_error,
          { INT32_RECORDS_NAME ".internal_error", PI_MALFORMED, PI_ERROR, "Dissector error", EXPFILL } },
    };
    int proto = *int32_records_spec.proto;
    module_t *module;

    expert_register_field_array(expert_register_protocol(proto), ei, array_length(ei));
    int32_records_handle = register_dissector(INT32_RECORDS_NAME, dissect_int32_records, proto);
    module = prefs_register_protocol(proto, int32_records_apply_prefs);
    prefs_register_string_preference(module, "release", "Driver release",
                                     "The release of the driver's client library (as 1.3.2 or 2.10.0): it chooses "
                                     "the record layouts. Empty: " INT32_RECORDS_DEFAULT_TEXT ".",
                                     &int32_records_pref_release);
}

/* The spec's ports, as the range preference <name>.tcp.port that Decode As also sets. */
static void int32_records_handoff_runtime(void)
{
    dissector_add_uint_range_with_preference("tcp.port", INT32_RECORDS_PORTS, int32_records_handle);
    int32_records_apply_prefs();
}

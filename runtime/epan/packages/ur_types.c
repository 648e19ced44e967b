/* The shapes of the tables generated from the spec (packet-ur.c, after this section) and walked
 * by the runtime after them: value strings by software version, field descriptors (one per field,
 * in wire order, as runtime/lua/packages/walk.lua walks them), the forms of every type code across
 * software versions, and the messages by type. Versions are one number,
 * (major * 1000 + minor) * 1000 + bugfix; an open bound is 0 or G_MAXUINT32. */
/* An enum whose names depend on the software version: its table for each range. */
typedef struct {
    guint32 low, high;
    const value_string *names;
} ur_names_row;

typedef struct {
    const value_string *newest;     /* the field's value string: today's firmware */
    const ur_names_row *rows;
    unsigned n_rows;
} ur_names;

/* What a descriptor reads (UR_D_*), and how (UR_SIGNED, ...). */
enum {
    UR_D_SCALAR, UR_D_BITS, UR_D_ARRAY, UR_D_GROUP, UR_D_STRING, UR_D_PSTRING, UR_D_STRINGS, UR_D_BYTES,
    UR_D_SWITCH, UR_D_VALUES, UR_D_COND
};
#define UR_SIGNED 1u   /* a two's-complement integer */
#define UR_FLOAT 2u    /* a float whose field is wider: added by value */
#define UR_VALUE 4u    /* its wire type is narrower than its field's: added by value */

typedef struct ur_desc ur_desc;

/* A list of descriptors: a layout, an item of a repeated group, the inside of a condition. */
typedef struct {
    const ur_desc *d;
    unsigned n;
} ur_layout;

/* One scalar whose type follows an earlier field (a switch): its field and size per selector. */
typedef struct {
    int code;
    int hf;
    unsigned n;
} ur_case;

typedef struct {
    int default_hf;
    unsigned default_n;
    const ur_case *cases;
    unsigned n_cases;
} ur_switch;

/* The scalar kinds a typed value holds, and the fields typed values are shown with. */
enum { UR_VK_NONE = -1, UR_VK_BOOL, UR_VK_FLOAT32, UR_VK_FLOAT64, UR_VK_INT16, UR_VK_INT32, UR_VK_INT64,
       UR_VK_INT8, UR_VK_UINT16, UR_VK_UINT32, UR_VK_UINT64, UR_VK_UINT8, UR_VK_COUNT };

typedef struct {
    int item, type, code, count, rows, cols, row, string;
    int kinds[UR_VK_COUNT];         /* by UR_VK_*; UR_HF_NONE where no value is of that kind */
} ur_value_fields;

/* How a value type is laid out after its type byte. */
enum { UR_V_EMPTY, UR_V_SCALAR, UR_V_ARRAY, UR_V_STRING, UR_V_LIST, UR_V_MATRIX };

typedef struct {
    const char *name;               /* NULL: no such type code */
    int layout;
    int item;                       /* UR_VK_* of a scalar or array */
    unsigned n, count, len;         /* item size, items, size of a length or count */
} ur_value_kind;

typedef struct {
    guint32 low, high;
    unsigned min_size;              /* the fewest bytes a value takes */
    const ur_value_kind *kinds;     /* by type code, 256 */
} ur_value_table;

struct ur_desc {
    int kind;
    int hf;                         /* the field, UR_HF_NONE for none */
    unsigned n;                     /* scalar size; pstring prefix size; terminator of strings, values */
    unsigned count;                 /* array items; group items (0: to the end); bits; cond fields */
    unsigned size;                  /* a group item's fixed size, 0 when it is not fixed */
    unsigned flags;
    unsigned keep;                  /* slot a scalar keeps its value in; cond present_if; switch selector */
    guint32 low, high;              /* cond: the versions it holds for */
    const char *path;               /* in error texts */
    const char *show;               /* Info column: the text before its value; NULL: not shown */
    const char *label;              /* group item label; the name of an enum named by version */
    const value_string *vs;         /* enum names, for the Info column */
    const ur_names *names;          /* enum names by version, NULL when they do not depend on it */
    const ur_layout *inner;         /* group item, cond fields */
    const int *bits;                /* bit fields, `count` of them */
    const ur_switch *sw;
    const ur_value_fields *values;
};

typedef struct ur_part {
    const char *name, *label;
    int item;                       /* the subtree field */
    const ur_layout *layout;
    const ur_layout *header;        /* subtypes: the header fields under the subtype's name */
    gboolean summary;               /* packages: it has an Info summary */
    gboolean needs_version;         /* subtypes and bodies: reading or choosing it depends on the version */
} ur_part;

/* One form of a type code: a layout as some versions send it. */
typedef struct {
    const ur_part *of;
    const unsigned *sizes;          /* the body sizes it can have; NULL: open-ended, at least `min` */
    unsigned n_sizes, min;
    guint32 rep;                    /* the version it stands for when its length alone chose it */
    const char *versions;           /* the versions that send it, in words */
} ur_form;

typedef struct {
    unsigned size;
    unsigned form;                  /* 1-based */
} ur_by_length;

typedef struct {
    gboolean single;                /* one form serves every version */
    gboolean summary;               /* packages: one of its forms has a summary */
    const int *segments;            /* per segment: its form, 1-based; negative: the nearest below's */
    const ur_by_length *by_length;
    unsigned n_by_length;
    const ur_form *forms;
} ur_forms;

enum { UR_M_PACKAGES, UR_M_SUBTYPES, UR_M_BODY };

typedef struct {
    int kind;
    int code;
    const char *label;
    const char *suffix;             /* appended to the message's item: ", Robot state" */
    const ur_forms *const *forms;   /* by package type, subtype or (body) the message's own code; 256 */
    /* packages */
    const value_string *names;      /* package types, subtypes */
    const ur_names *tables;         /* ... by version, NULL when they do not depend on it */
    int length_hf, type_hf;
    gboolean needs_version;
    /* subtypes, body */
    unsigned body_offset;
    const ur_layout *header;
    int subtype_hf;
    const char *subtype_label;
} ur_message;

/* ---- the RTDE connection: state, decoding, the client's messages -------------------------- */

/* A recipe of one connection: its variables' names (a copy), types and offsets in a data package's
 * values, in order, in the storage of its connection. The offsets are computed once, when the
 * setup reply makes the recipe, so that reading a value is one load at a known place. */
typedef struct rtde_recipe {
    bool used;
    bool from_robot;                        /* outputs (the robot's data) or inputs (the client's) */
    int16_t id;                             /* -1: protocol 1's one output recipe, which has no id */
    size_t count;
    size_t size;                            /* bytes of one data package's values */
    uint8_t *types;                         /* rtde_value_type, count of them */
    uint16_t *offset;                       /* where each value starts in a package's values */
    uint16_t *name_at;
    uint16_t *name_length;
    char *names;
} rtde_recipe;

/* A setup request's names, awaiting its reply. */
typedef struct rtde_pending {
    size_t length;                          /* RTDE_NAMES_NOT_KEPT: longer than the connection's limit */
    char *names;
} rtde_pending;

#define RTDE_NAMES_NOT_KEPT ((size_t)-1)

/* Everything RTDE's messages depend on, for one TCP connection: owned by the caller, never
 * allocated. Its recipes and pending names live in `own` (rtde_conversation_init) or in storage the
 * caller gives (rtde_conversation_init_in); a conversation is not copied. */
typedef struct rtde_conversation {
    uint8_t protocol;                       /* 0 until negotiated: RTDE_DEFAULT_PROTOCOL applies */
    uint16_t asked[RTDE_MAX_PENDING_VERSIONS];  /* protocol versions asked for, awaiting replies */
    uint8_t asked_count;
    uint64_t asked_lost;                    /* requests not kept (the queue was full), awaiting replies */
    rtde_pending pending[2][RTDE_MAX_PENDING];  /* [0] outputs, [1] inputs: setups awaiting replies */
    uint8_t pending_count[2];
    uint64_t pending_lost[2];
    /* After bytes lost (rtde_conversation_lost), for good: a reply with no request kept answers
     * one the gap may have held or answered, unknown, and no later request is kept. */
    bool asked_unknown, pending_unknown[2];
    rtde_pending refused;                   /* the names of the last reply's request (a view's home) */
    char said[112];                         /* the text of the last message's error (a view's home) */
    rtde_limits limits;
    rtde_recipe *recipes;                   /* limits.recipes slots */
    size_t recipes_used;                    /* slots used so far: the rest were never used */
    struct {
        rtde_recipe recipes[RTDE_MAX_RECIPES];
        uint8_t types[RTDE_MAX_RECIPES][RTDE_MAX_VARIABLES];
        uint16_t offset[RTDE_MAX_RECIPES][RTDE_MAX_VARIABLES];
        uint16_t name_at[RTDE_MAX_RECIPES][RTDE_MAX_VARIABLES];
        uint16_t name_length[RTDE_MAX_RECIPES][RTDE_MAX_VARIABLES];
        char names[RTDE_MAX_RECIPES][RTDE_MAX_NAMES];
        char pending[2 * RTDE_MAX_PENDING + 1][RTDE_MAX_NAMES];
    } own;                                  /* rtde_conversation_init's storage */
} rtde_conversation;

/* A connection with the RTDE_MAX_* limits, its state in the conversation itself. */
void rtde_conversation_init(rtde_conversation *c);
/* Bytes of storage rtde_conversation_init_in needs for these limits; 0 when a limit is 0 or above
 * the protocol's own (RTDE_PROTOCOL_*). RTDE_STORAGE_SIZE is the same as a constant expression, for
 * static storage. */
size_t rtde_storage_size(const rtde_limits *limits);
#define RTDE__ROUND16(n) ((((size_t)(n)) + 15u) & ~(size_t)15u)
#define RTDE_STORAGE_SIZE(recipes, variables, names)                                                  \
    (RTDE__ROUND16((size_t)(recipes) * sizeof(rtde_recipe))                                           \
     + 3 * RTDE__ROUND16((size_t)(recipes) * (size_t)(variables) * sizeof(uint16_t))                  \
     + RTDE__ROUND16((size_t)(recipes) * (size_t)(variables))                                          \
     + RTDE__ROUND16((size_t)(recipes) * (size_t)(names))                                              \
     + RTDE__ROUND16((size_t)(2 * RTDE_MAX_PENDING + 1) * (size_t)(names)))
/* A connection whose recipes and pending names live in the caller's storage (size bytes, aligned as
 * malloc aligns, not read before it is written): false when size is below rtde_storage_size. A
 * command sizes it to the protocol's own limits, so that every recipe a robot makes is kept; a
 * firmware to what it needs. */
bool rtde_conversation_init_in(rtde_conversation *c, const rtde_limits *limits, void *storage, size_t size);
uint8_t rtde_protocol_in_force(const rtde_conversation *c);
/* Bytes of one direction were lost (a gap in a capture; the caller frames that direction afresh
 * after them): the protocol and the recipes are kept, but lost requests leave every later reply's
 * request unknown (those kept came before them, and their replies first), and lost replies may
 * have answered the requests awaiting, unless none awaited. Such a reply pairs with none and says
 * so; a setup reply then makes no recipe and removes its id's old one. */
void rtde_conversation_lost(rtde_conversation *c, bool from_robot);

/* The size of the message that starts buf (header included), once its header is there:
 * RTDE_NEED_MORE with fewer than 3 bytes, RTDE_BAD_HEADER for a size below 3 or a type code
 * no layout has. */
rtde_error rtde_message_size(const uint8_t *buf, size_t length, size_t *size);

/* Decode one whole message (`length` is its size) sent in the given direction, and follow it:
 * a protocol version accepted, a setup request kept, a reply made into a recipe. On an error,
 * *offset is where in the message it was found; out->layout is RTDE_LAYOUT_NONE for a type with
 * no layout, and out->u.data_package.recipe_id holds an unknown recipe's id. */
rtde_error rtde_decode(rtde_conversation *c, const uint8_t *msg, size_t length, bool from_robot,
                       rtde_message *out, size_t *offset);

/* A data package's values, by index in its recipe or by variable name. Reading by index is a
 * bounds check and a byte-swapped load at the offset the recipe keeps; reading by name looks the
 * name up first, so a program reading every package resolves its names once, with
 * rtde_recipe_index, and reads by index. */
size_t rtde_data_count(const rtde_data *d);
rtde_text rtde_data_name(const rtde_data *d, size_t index);
bool rtde_data_value(const rtde_data *d, size_t index, rtde_value *out);
bool rtde_data_find(const rtde_data *d, const char *name, rtde_value *out);
/* Several values in one call: out[i] is the value at indexes[i] (the indexes a program resolved
 * once); false at the first index past the recipe, the values before it read. */
bool rtde_data_values(const rtde_data *d, const size_t *indexes, size_t count, rtde_value *out);

/* The index of a variable in a recipe (a data package's is d->recipe), or RTDE_NO_INDEX when the
 * recipe has no variable of that name. */
#define RTDE_NO_INDEX ((size_t)-1)
size_t rtde_recipe_index(const rtde_recipe *recipe, const char *name);

/* The recipe of a data package of this direction and id (-1: protocol 1 outputs), if any. */
const rtde_recipe *rtde_recipe_of(const rtde_conversation *c, bool from_robot, int id);

/* What a client sends: each writes one message into out (cap bytes) and returns its size, or 0
 * when it does not fit (or a name list is longer than the protocol's RTDE_PROTOCOL_NAMES). */
size_t rtde_build_request_protocol_version(uint8_t *out, size_t cap, uint16_t version);
size_t rtde_build_get_controller_version(uint8_t *out, size_t cap);
size_t rtde_build_setup_outputs(uint8_t *out, size_t cap, uint8_t protocol, double frequency,
                                const char *const *names, size_t count);
size_t rtde_build_setup_inputs(uint8_t *out, size_t cap, const char *const *names, size_t count);
size_t rtde_build_start(uint8_t *out, size_t cap);
size_t rtde_build_pause(uint8_t *out, size_t cap);
/* An input data package: one value per variable of the input recipe, in its order. */
size_t rtde_build_input_data(uint8_t *out, size_t cap, const rtde_recipe *recipe, const rtde_value *values);

const char *rtde_error_text(rtde_error e);

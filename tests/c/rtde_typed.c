/* The inline readers of rtde.h (rtde_data_double, rtde_data_vector6d, ...) against rtde_data_value,
 * the reader of any type, on a recipe of every value type twice over, in packages of random bytes:
 * each reader gives the items rtde_data_value gives at its type's indexes (a BOOL byte other than 0
 * as true), and refuses every other index, one past the recipe, and a package whose values did not
 * arrive, writing nothing then. Prints what it checked; any difference is printed and fails it
 * (exit 1). */
#include <stdio.h>
#include <string.h>

#include "rtde.h"

#define TYPES RTDE_VT_COUNT
#define COUNT (2 * TYPES)
#define PACKAGES 200

static rtde_conversation conversation;
static int failures;

static void fail(const char *what, size_t index, int type)
{
    if (failures++ < 20)
        printf("FAIL %s: index %lu, reader of type %d\n", what, (unsigned long)index, type);
}

/* Every reader's output, each filled with one byte before a read, to tell what a read wrote. */
typedef struct outputs {
    bool b;
    uint8_t u8;
    uint32_t u32[6];
    int32_t i32[6];
    uint64_t u64;
    double f[6];
} outputs;

/* Reads value index with the reader of `type`: whether it said it read, its items as rtde_value
 * keeps them (when it read) and how many, and whether it wrote nothing at all (*untouched). */
static bool read_as(const rtde_data *d, size_t index, int type, rtde_value *items, size_t *n, bool *untouched)
{
    outputs o, before;
    bool ok;
    size_t k;
    memset(&o, 0x5a, sizeof o);
    memcpy(&before, &o, sizeof o);
    switch (type) {
    case RTDE_VT_BOOL: ok = rtde_data_bool(d, index, &o.b); *n = 1; break;
    case RTDE_VT_UINT8: ok = rtde_data_uint8(d, index, &o.u8); *n = 1; break;
    case RTDE_VT_UINT32: ok = rtde_data_uint32(d, index, o.u32); *n = 1; break;
    case RTDE_VT_UINT64: ok = rtde_data_uint64(d, index, &o.u64); *n = 1; break;
    case RTDE_VT_INT32: ok = rtde_data_int32(d, index, o.i32); *n = 1; break;
    case RTDE_VT_DOUBLE: ok = rtde_data_double(d, index, o.f); *n = 1; break;
    case RTDE_VT_VECTOR3D: ok = rtde_data_vector3d(d, index, o.f); *n = 3; break;
    case RTDE_VT_VECTOR6D: ok = rtde_data_vector6d(d, index, o.f); *n = 6; break;
    case RTDE_VT_VECTOR6INT32: ok = rtde_data_vector6int32(d, index, o.i32); *n = 6; break;
    default: ok = rtde_data_vector6uint32(d, index, o.u32); *n = 6; break;
    }
    *untouched = memcmp(&o, &before, sizeof o) == 0;
    if (!ok)
        return false;
    for (k = 0; k < *n; k++) {
        switch (type) {
        case RTDE_VT_BOOL: items->item[k].u64 = o.b; break;
        case RTDE_VT_UINT8: items->item[k].u64 = o.u8; break;
        case RTDE_VT_UINT32: case RTDE_VT_VECTOR6UINT32: items->item[k].u64 = o.u32[k]; break;
        case RTDE_VT_UINT64: items->item[k].u64 = o.u64; break;
        case RTDE_VT_INT32: case RTDE_VT_VECTOR6INT32: items->item[k].i64 = o.i32[k]; break;
        default: items->item[k].f64 = o.f[k]; break;
        }
    }
    return true;
}

/* The setup of outputs named v0..v19 and its reply, each type twice, in the enum's order. */
static void set_up(void)
{
    static char names[COUNT][8];
    const char *list[COUNT];
    uint8_t msg[512];
    rtde_message m;
    size_t n, at, i;
    for (i = 0; i < COUNT; i++) {
        sprintf(names[i], "v%lu", (unsigned long)i);
        list[i] = names[i];
    }
    n = rtde_build_setup_outputs(msg, sizeof msg, 2, 500.0, list, COUNT);
    rtde_decode(&conversation, msg, n, false, &m, &at);
    n = 4;
    for (i = 0; i < COUNT; i++) {
        const char *t = rtde_value_type_name((uint8_t)(i % TYPES));
        if (i)
            msg[n++] = ',';
        memcpy(msg + n, t, strlen(t));
        n += strlen(t);
    }
    msg[0] = (uint8_t)(n >> 8);
    msg[1] = (uint8_t)n;
    msg[2] = 'O';
    msg[3] = 1;
    if (rtde_decode(&conversation, msg, n, true, &m, &at) != RTDE_OK || rtde_recipe_of(&conversation, true, 1) == NULL)
        fail("the recipe", 0, -1);
}

int main(void)
{
    uint8_t package[1024];
    uint64_t seed = 39;
    unsigned long reads = 0, refusals = 0;
    const rtde_recipe *recipe;
    rtde_message m;
    size_t at, i, k, p, size;
    int type;
    rtde_conversation_init(&conversation);
    set_up();
    recipe = rtde_recipe_of(&conversation, true, 1);
    if (recipe == NULL)
        return 1;
    size = 4 + recipe->size;
    for (p = 0; p < PACKAGES; p++) {
        package[0] = (uint8_t)(size >> 8);
        package[1] = (uint8_t)size;
        package[2] = 'U';
        package[3] = 1;
        for (i = 4; i < size; i++) {            /* every bit pattern: NaNs, negative integers, BOOL 2 */
            seed = seed * 6364136223846793005u + 1442695040888963407u;
            package[i] = (uint8_t)(seed >> 56);
        }
        if (rtde_decode(&conversation, package, size, true, &m, &at) != RTDE_OK) {
            fail("a package", 0, -1);
            break;
        }
        for (i = 0; i <= COUNT; i++)            /* one index past the recipe */
            for (type = 0; type < TYPES; type++) {
                rtde_value want, got;
                size_t n;
                bool untouched, ok = read_as(&m.u.data_package.values, i, type, &got, &n, &untouched);
                if (i < COUNT && recipe->types[i] == type) {
                    if (!ok || !rtde_data_value(&m.u.data_package.values, i, &want) || want.count != n)
                        fail("a value of its type not read", i, type);
                    if (type == RTDE_VT_BOOL)   /* rtde_data_value keeps the byte, rtde_data_bool says true */
                        want.item[0].u64 = want.item[0].u64 != 0;
                    for (k = 0; k < n; k++)
                        if (memcmp(&want.item[k], &got.item[k], sizeof got.item[k]) != 0)
                            fail("an item read differently from rtde_data_value", i, type);
                    reads++;
                } else {
                    if (ok || !untouched)
                        fail("a value of another type, or past the recipe, read", i, type);
                    refusals++;
                }
            }
    }
    {
        rtde_data none = {NULL, NULL};
        rtde_data unread = m.u.data_package.values;
        double x = 1.0;
        unread.bytes = NULL;                    /* a package whose values did not arrive */
        if (rtde_data_double(&none, 0, &x) || rtde_data_double(&unread, 5, &x) || x != 1.0)
            fail("a package without values read", 0, RTDE_VT_DOUBLE);
    }
    printf("%lu reads as rtde_data_value reads, %lu refusals, %d failures\n", reads, refusals, failures);
    return failures ? 1 : 0;
}

/* One RTDE data package decoded and read again and again, L1-hot: what a 500 Hz client costs per
 * package, without the file or the socket.
 *
 *     bench_rtde_hot [PACKAGES [TURNS]]
 *
 * (make bench-rtde builds it at -O2, -O3 and -Os, with UR's own library, URCL, when it finds a
 * checkout: tests/tools/urcl.py.) The package is the 12-variable, 284-byte output package of protocol 2 a
 * driver reads. Each contestant decodes it PACKAGES times and reads all 12 values:
 *   index    rtde_decode, then each value by its index in the recipe and its type (rtde_data_double,
 *            rtde_data_vector6d, ...: the inline readers)
 *   name     the same, the names resolved to indexes once (rtde_recipe_index)
 *   value    rtde_decode, then rtde_data_value by index: any type, into an rtde_value
 *   list     the same indexes, all 12 values read by one rtde_data_values call
 *   find     rtde_decode, then rtde_data_find by name for every value
 *   hand     a hand-written reader of this one layout: a size check, memcpy and a byte swap
 *   urcl     URCL's RTDEParser::parse into a preallocated DataPackage, then getData of all 12 by
 *            name and type
 * They take turns in one process, TURNS rounds, and each keeps its best round (CPU time). Every
 * contestant must read the same values, or the bench fails. Prints a line per contestant: its
 * nanoseconds per package and its time over the hand-written reader's and URCL's; then whether
 * index and name meet issue 39's goals (at most 3x the hand-written reader's time, URCL's at least
 * 3x theirs).
 */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "rtde.h"

#define VALUES 12
#define PACKAGE_SIZE 284
#define HAND 5                  /* the contestants' places */
#define URCL 6
#define GOAL 3.0                /* times the hand-written reader's, and URCL's over urwire's */

static const char *const names[VALUES] = {
    "timestamp", "actual_q", "actual_qd", "actual_TCP_pose", "actual_TCP_force", "robot_mode", "safety_mode",
    "runtime_state", "actual_digital_input_bits", "speed_scaling", "output_int_register_0", "joint_temperatures"};
static const char types[] = "DOUBLE,VECTOR6D,VECTOR6D,VECTOR6D,VECTOR6D,INT32,INT32,UINT32,UINT64,DOUBLE,INT32,"
                            "VECTOR6D";

/* Each reader returns what it read, added up: every value's items, as doubles. URCL's reader is
 * tests/bench/bench_rtde_urcl.cpp, linked in with BENCH_URCL. */
#ifdef BENCH_URCL
double urcl_read(const uint8_t *package, size_t size, long packages, const char *const *recipe, size_t count);
#define CONTESTANTS 7
#else
#define CONTESTANTS 6
static double urcl_read(const uint8_t *package, size_t size, long packages, const char *const *recipe, size_t count)
{
    (void)package, (void)size, (void)packages, (void)recipe, (void)count;
    return 0;
}
#endif

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static rtde_conversation conversation;
static uint8_t package[PACKAGE_SIZE];
/* Read through a volatile pointer, so that no round's work is hoisted out of its loop. */
static const uint8_t *volatile package_at = package;

static void must(bool ok, const char *what)
{
    if (!ok) {
        fprintf(stderr, "bench_rtde_hot: %s\n", what);
        exit(1);
    }
}

/* The session up to its data: the setup request and its reply; then one data package of varied
 * values (built with the recipe, so that every item differs). */
static void set_up(void)
{
    uint8_t msg[512];
    rtde_message m;
    rtde_value values[VALUES];
    size_t n, at, i, k;
    const rtde_recipe *recipe;
    rtde_conversation_init(&conversation);
    n = rtde_build_setup_outputs(msg, sizeof msg, 2, 500.0, names, VALUES);
    must(rtde_decode(&conversation, msg, n, false, &m, &at) == RTDE_OK, "the setup request");
    n = 4 + strlen(types);
    msg[0] = (uint8_t)(n >> 8);
    msg[1] = (uint8_t)n;
    msg[2] = 'O';
    msg[3] = 1;
    memcpy(msg + 4, types, strlen(types));
    must(rtde_decode(&conversation, msg, n, true, &m, &at) == RTDE_OK, "the setup reply");
    recipe = rtde_recipe_of(&conversation, true, 1);
    must(recipe != NULL && recipe->count == VALUES, "the recipe");
    memset(values, 0, sizeof values);
    for (i = 0; i < VALUES; i++)
        for (k = 0; k < 6; k++) {
            values[i].item[k].f64 = 0.25 * (double)(i * 6 + k) - 3.0;
            values[i].item[k].i64 = (int64_t)(i * 6 + k) - 40;
        }
    for (i = 0; i < VALUES; i++)
        if (recipe->types[i] == RTDE_VT_INT32 || recipe->types[i] == RTDE_VT_UINT32
            || recipe->types[i] == RTDE_VT_UINT64)
            values[i].item[0].i64 = recipe->types[i] == RTDE_VT_INT32 ? -(int64_t)i : (int64_t)(1000 + i);
        else
            for (k = 0; k < 6; k++)
                values[i].item[k].f64 = 0.25 * (double)(i * 6 + k) - 3.0;
    must(rtde_build_input_data(package, sizeof package, recipe, values) == PACKAGE_SIZE, "a 284-byte package");
}

/* A caller knows its recipe's types: it reads each value's items as the type it asked for. */
static double six(const rtde_value *v)
{
    return v->item[0].f64 + v->item[1].f64 + v->item[2].f64 + v->item[3].f64 + v->item[4].f64 + v->item[5].f64;
}

static double used(const rtde_value *v)
{
    return v[0].item[0].f64 + six(&v[1]) + six(&v[2]) + six(&v[3]) + six(&v[4]) + (double)v[5].item[0].i64
         + (double)v[6].item[0].i64 + (double)v[7].item[0].u64 + (double)v[8].item[0].u64 + v[9].item[0].f64
         + (double)v[10].item[0].i64 + six(&v[11]);
}

static double sum6(const double *v)
{
    return v[0] + v[1] + v[2] + v[3] + v[4] + v[5];
}

/* The 12 values, each read as its type by the inline readers, at[i] the index of names[i]. */
static double typed(const rtde_data *d, const size_t *at)
{
    double timestamp = 0, q[6], qd[6], pose[6], force[6], scaling = 0, temperatures[6];
    int32_t robot_mode = 0, safety_mode = 0, register0 = 0;
    uint32_t runtime_state = 0;
    uint64_t inputs = 0;
    bool ok = rtde_data_double(d, at[0], &timestamp) && rtde_data_vector6d(d, at[1], q)
           && rtde_data_vector6d(d, at[2], qd) && rtde_data_vector6d(d, at[3], pose)
           && rtde_data_vector6d(d, at[4], force) && rtde_data_int32(d, at[5], &robot_mode)
           && rtde_data_int32(d, at[6], &safety_mode) && rtde_data_uint32(d, at[7], &runtime_state)
           && rtde_data_uint64(d, at[8], &inputs) && rtde_data_double(d, at[9], &scaling)
           && rtde_data_int32(d, at[10], &register0) && rtde_data_vector6d(d, at[11], temperatures);
    must(ok, "a value");
    return timestamp + sum6(q) + sum6(qd) + sum6(pose) + sum6(force) + (double)robot_mode + (double)safety_mode
         + (double)runtime_state + (double)inputs + scaling + (double)register0 + sum6(temperatures);
}

/* The program knows its recipe's order: value i is names[i]. */
static double by_index(long packages)
{
    static const size_t at[VALUES] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11};
    rtde_message m;
    size_t offset;
    double sum = 0;
    long p;
    for (p = 0; p < packages; p++) {
        must(rtde_decode(&conversation, package_at, PACKAGE_SIZE, true, &m, &offset) == RTDE_OK, "a package");
        sum += typed(&m.u.data_package.values, at);
    }
    return sum;
}

static double by_name(long packages)
{
    rtde_message m;
    size_t offset, i, at[VALUES];
    double sum = 0;
    long p;
    for (i = 0; i < VALUES; i++)
        at[i] = rtde_recipe_index(rtde_recipe_of(&conversation, true, 1), names[i]);
    for (p = 0; p < packages; p++) {
        must(rtde_decode(&conversation, package_at, PACKAGE_SIZE, true, &m, &offset) == RTDE_OK, "a package");
        sum += typed(&m.u.data_package.values, at);
    }
    return sum;
}

static double by_value(long packages)
{
    rtde_message m;
    rtde_value v[VALUES];
    bool ok;
    size_t at, i;
    double sum = 0;
    long p;
    for (p = 0; p < packages; p++) {
        must(rtde_decode(&conversation, package_at, PACKAGE_SIZE, true, &m, &at) == RTDE_OK, "a package");
        for (i = 0, ok = true; i < VALUES; i++)
            ok &= rtde_data_value(&m.u.data_package.values, i, &v[i]);
        must(ok, "a value");
        sum += used(v);
    }
    return sum;
}

static double by_list(long packages)
{
    rtde_message m;
    rtde_value v[VALUES];
    size_t at, i, index[VALUES];
    double sum = 0;
    long p;
    for (i = 0; i < VALUES; i++)
        index[i] = rtde_recipe_index(rtde_recipe_of(&conversation, true, 1), names[i]);
    for (p = 0; p < packages; p++) {
        must(rtde_decode(&conversation, package_at, PACKAGE_SIZE, true, &m, &at) == RTDE_OK, "a package");
        must(rtde_data_values(&m.u.data_package.values, index, VALUES, v), "the values");
        sum += used(v);
    }
    return sum;
}

static double by_find(long packages)
{
    rtde_message m;
    rtde_value v[VALUES];
    bool ok;
    size_t at, i;
    double sum = 0;
    long p;
    for (p = 0; p < packages; p++) {
        must(rtde_decode(&conversation, package_at, PACKAGE_SIZE, true, &m, &at) == RTDE_OK, "a package");
        for (i = 0, ok = true; i < VALUES; i++)
            ok &= rtde_data_find(&m.u.data_package.values, names[i], &v[i]);
        must(ok, "a value");
        sum += used(v);
    }
    return sum;
}

/* The hand-written reader: this layout's offsets typed in, each value one big-endian load. */
static uint64_t be64(const uint8_t *p)
{
    uint64_t v;
    memcpy(&v, p, 8);
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
    return v;
#else
    return __builtin_bswap64(v);
#endif
}

static uint32_t be32(const uint8_t *p)
{
    uint32_t v;
    memcpy(&v, p, 4);
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
    return v;
#else
    return __builtin_bswap32(v);
#endif
}

static double f64(const uint8_t *p)
{
    uint64_t bits = be64(p);
    double d;
    memcpy(&d, &bits, 8);
    return d;
}

static double vector6d(const uint8_t *p)
{
    double sum = 0;
    size_t k;
    for (k = 0; k < 6; k++)
        sum += f64(p + 8 * k);
    return sum;
}

static double by_hand(long packages)
{
    double sum = 0;
    long p;
    for (p = 0; p < packages; p++) {
        const uint8_t *b = package_at;
        must(b[0] == PACKAGE_SIZE >> 8 && b[1] == (PACKAGE_SIZE & 0xff) && b[2] == 'U' && b[3] == 1, "a package");
        b += 4;
        sum += f64(b) + vector6d(b + 8) + vector6d(b + 56) + vector6d(b + 104) + vector6d(b + 152);
        sum += (double)(int32_t)be32(b + 200) + (double)(int32_t)be32(b + 204) + (double)be32(b + 208);
        sum += (double)be64(b + 212) + f64(b + 220) + (double)(int32_t)be32(b + 228) + vector6d(b + 232);
    }
    return sum;
}

static double by_urcl(long packages)
{
    return urcl_read(package_at, PACKAGE_SIZE, packages, names, VALUES);
}

typedef struct contestant {
    const char *name;
    double (*run)(long packages);
    double best;
} contestant;

int main(int argc, char **argv)
{
    long packages = argc > 1 ? atol(argv[1]) : 200000;
    int turns = argc > 2 ? atoi(argv[2]) : 5, t;
    contestant all[] = {{"index", by_index, 1e30}, {"name", by_name, 1e30}, {"value", by_value, 1e30},
                        {"list", by_list, 1e30}, {"find", by_find, 1e30}, {"hand", by_hand, 1e30},
                        {"urcl", by_urcl, 1e30}};
    size_t n = CONTESTANTS, i;
    double expected = 0;
    set_up();
    expected = by_hand(1);
    for (t = 0; t < turns; t++)
        for (i = 0; i < n; i++) {
            double start = cpu_now(), sum = all[i].run(packages), took = cpu_now() - start;
            if (sum != expected * (double)packages) {
                fprintf(stderr, "bench_rtde_hot: %s read %.17g, the hand-written reader %.17g\n", all[i].name,
                        sum, expected * (double)packages);
                return 1;
            }
            if (took < all[i].best)
                all[i].best = took;
        }
    for (i = 0; i < n; i++) {
        printf("%-6s %7.1f ns/package  %6.2fx the hand-written reader's time", all[i].name,
               all[i].best / (double)packages * 1e9, all[i].best / all[HAND].best);
        if (n == URCL + 1)
            printf("  URCL takes %.2fx as long", all[URCL].best / all[i].best);
        printf("\n");
    }
    for (i = 0; i < 2; i++) {              /* index and name */
        bool hand = all[i].best <= GOAL * all[HAND].best, urcl = n > URCL && all[URCL].best >= GOAL * all[i].best;
        printf("goal   %s: at most %.0fx the hand-written reader's time: %s; URCL at least %.0fx as long: %s\n",
               all[i].name, GOAL, hand ? "met" : "missed", GOAL, n > URCL ? (urcl ? "met" : "missed") : "not compared");
    }
    if (n == URCL)
        printf("urcl   not compared: this bench was built without URCL (make bench-rtde says why)\n");
    return 0;
}

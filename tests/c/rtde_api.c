/* The RTDE client API a firmware would use, checked from C: builds the messages of a session
 * (printed as hex, one per line, for the test to compare with the golden vectors), then decodes a
 * setup reply and a data package and prints the values it reads by variable name, then the indexes
 * those names resolve to and the values read by them, one by one, as a list and by the inline
 * readers of their types. */
#include <stdio.h>
#include <string.h>

#include "rtde.h"

static rtde_conversation conversation;

static void hex(const uint8_t *p, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++)
        printf("%02x", p[i]);
    printf("\n");
}

static void feed(const uint8_t *p, size_t n, bool from_robot, rtde_message *m)
{
    size_t at;
    rtde_error e = rtde_decode(&conversation, p, n, from_robot, m, &at);
    if (e != RTDE_OK)
        printf("error %s at %lu\n", rtde_error_text(e), (unsigned long)at);
}

int main(void)
{
    static const char *const outputs[] = {"timestamp", "actual_q", "robot_mode"};
    static const char *const inputs[] = {"input_double_register_0"};
    static const uint8_t reply[] = {0, 25, 'O', 2, 'D', 'O', 'U', 'B', 'L', 'E', ',', 'V', 'E', 'C', 'T', 'O', 'R',
                                    '6', 'D', ',', 'I', 'N', 'T', '3', '2'};
    static const uint8_t inputs_reply[] = {0, 10, 'I', 1, 'D', 'O', 'U', 'B', 'L', 'E'};
    uint8_t out[256], data[64];
    rtde_message m;
    rtde_value q, mode;
    const rtde_recipe *recipe;
    size_t n;
    rtde_conversation_init(&conversation);
    hex(out, rtde_build_request_protocol_version(out, sizeof out, 2));
    hex(out, rtde_build_get_controller_version(out, sizeof out));
    n = rtde_build_setup_outputs(out, sizeof out, 2, 125.0, outputs, 3);
    hex(out, n);
    feed(out, n, false, &m);
    feed(reply, sizeof reply, true, &m);
    n = rtde_build_setup_inputs(out, sizeof out, inputs, 1);
    hex(out, n);
    feed(out, n, false, &m);
    feed(inputs_reply, sizeof inputs_reply, true, &m);
    hex(out, rtde_build_start(out, sizeof out));
    hex(out, rtde_build_pause(out, sizeof out));
    recipe = rtde_recipe_of(&conversation, false, 1);
    if (recipe) {
        rtde_value v;
        memset(&v, 0, sizeof v);
        v.item[0].f64 = 0.5;
        hex(out, rtde_build_input_data(out, sizeof out, recipe, &v));
    }
    printf("too small: %lu\n", (unsigned long)rtde_build_setup_outputs(out, 8, 2, 125.0, outputs, 3));
    /* A data package of recipe 2: timestamp 12.5, actual_q 0 -1.5 1.5 -0.5 0.25 3, robot_mode 7. */
    memcpy(data, "\x00\x40U\x02\x40\x29\0\0\0\0\0\0", 12);
    memset(data + 12, 0, 52);
    memcpy(data + 20, "\xbf\xf8", 2);
    memcpy(data + 28, "\x3f\xf8", 2);
    memcpy(data + 36, "\xbf\xe0", 2);
    memcpy(data + 44, "\x3f\xd0", 2);
    memcpy(data + 52, "\x40\x08", 2);
    data[63] = 7;
    feed(data, 64, true, &m);
    if (m.layout == RTDE_LAYOUT_DATA_PACKAGE && rtde_data_find(&m.u.data_package.values, "actual_q", &q)
        && rtde_data_find(&m.u.data_package.values, "robot_mode", &mode))
        printf("actual_q %g %g %g %g %g %g robot_mode %lld recipe %u\n", q.item[0].f64, q.item[1].f64,
               q.item[2].f64, q.item[3].f64, q.item[4].f64, q.item[5].f64, (long long)mode.item[0].i64,
               (unsigned)m.u.data_package.recipe_id);
    if (m.layout == RTDE_LAYOUT_DATA_PACKAGE) {
        const rtde_data *d = &m.u.data_package.values;
        size_t iq = rtde_recipe_index(d->recipe, "actual_q"), imode = rtde_recipe_index(d->recipe, "robot_mode");
        bool absent = rtde_recipe_index(d->recipe, "actual_qd") == RTDE_NO_INDEX
                      && rtde_recipe_index(NULL, "actual_q") == RTDE_NO_INDEX && !rtde_data_value(d, 3, &q);
        if (rtde_data_value(d, iq, &q) && rtde_data_value(d, imode, &mode))
            printf("index actual_q %lu robot_mode %lu: %g %g %lld, absent names %s\n", (unsigned long)iq,
                   (unsigned long)imode, q.item[1].f64, q.item[5].f64, (long long)mode.item[0].i64,
                   absent ? "none" : "found");
        {
            size_t list[3] = {2, 0, 1};
            rtde_value three[3];
            bool ok = rtde_data_values(d, list, 3, three);
            list[1] = 3;
            printf("values 2 0 1: %lld %g %g, past the recipe %s\n", (long long)three[0].item[0].i64,
                   three[1].item[0].f64, three[2].item[5].f64, ok && !rtde_data_values(d, list, 3, three) ? "refused"
                                                                                                     : "read");
        }
        {
            double timestamp = 0, six[6] = {0};
            int32_t robot_mode = 0;
            bool ok = rtde_data_double(d, 0, &timestamp) && rtde_data_vector6d(d, iq, six)
                      && rtde_data_int32(d, imode, &robot_mode);
            printf("typed: %g %g %g %ld, as another type %s\n", timestamp, six[1], six[5], (long)robot_mode,
                   ok && !rtde_data_double(d, iq, &timestamp) && !rtde_data_vector6d(d, 3, six) ? "refused" : "read");
        }
    }
    return 0;
}

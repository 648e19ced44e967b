/* Unit checks of the real-time C API that urwire-decode does not reach: the same-size rule
 * (a version chooses among forms of one size, else the newest), enum names by form, presence,
 * and framing errors. Prints "all real-time checks passed". */
#include <stdio.h>
#include <string.h>

#include "ur_realtime.h"

static int failures = 0;

static void check(int ok, const char *what)
{
    if (!ok) {
        printf("FAILED: %s\n", what);
        failures++;
    }
}

static void put_f64(uint8_t *p, double v)
{
    uint64_t bits;
    int i;
    memcpy(&bits, &v, sizeof bits);
    for (i = 7; i >= 0; i--) {
        p[i] = (uint8_t)(bits & 0xffu);
        bits >>= 8;
    }
}

int main(void)
{
    static uint8_t packet[1108];
    ur_realtime_packet p;
    int32_t size = 0;
    int i;
    memset(packet, 0, sizeof packet);
    packet[2] = 0x04;
    packet[3] = 0x54;                               /* message_size = 1108 */
    for (i = 0; i < 6; i++)
        put_f64(packet + 4 + 8 * (95 + i), 248.0);  /* joint_modes */
    put_f64(packet + 4 + 8 * 94, 7.0);              /* robot_mode */

    check(ur_realtime_decode(packet, sizeof packet, ur_realtime_version(3, 6, 0), &p) == UR_REALTIME_OK, "decode");
    check(p.layout == UR_REALTIME_RT_3_5 && strcmp(ur_realtime_layout_name(p.layout), "rt_3_5") == 0, "layout");
    check(p.joint_modes[5] == 248.0 && p.robot_mode == 7.0, "values");
    check(ur_realtime_enum_name(&p, UR_REALTIME_F_JOINT_MODES, 248.0) != NULL &&
          strcmp(ur_realtime_enum_name(&p, UR_REALTIME_F_JOINT_MODES, 248.0), "PART_D_CALIBRATION_ERROR") == 0,
          "3.6 reads CB3 joint modes");
    check(strcmp(ur_realtime_enum_name(&p, UR_REALTIME_F_ROBOT_MODE, 7.0), "RUNNING") == 0, "robot mode name");
    check(ur_realtime_enum_name(&p, UR_REALTIME_F_TIME, 0.0) == NULL, "no enum, no name");
    check(ur_realtime_has(&p, UR_REALTIME_F_ELBOW_POSITION) && !ur_realtime_has(&p, UR_REALTIME_F_SAFETY_STATUS),
          "presence by layout");

    check(ur_realtime_decode(packet, sizeof packet, 0u, &p) == UR_REALTIME_OK, "decode without a version");
    check(ur_realtime_enum_name(&p, UR_REALTIME_F_JOINT_MODES, 248.0) == NULL, "the newest form: e-Series codes");
    check(ur_realtime_decode(packet, sizeof packet, ur_realtime_version(1, 8, 0), &p) == UR_REALTIME_OK &&
          ur_realtime_enum_name(&p, UR_REALTIME_F_JOINT_MODES, 248.0) == NULL, "no form holds 1.8: the newest");

    check(ur_realtime_decode(packet, 1000, 0u, &p) == UR_REALTIME_E_SHORT, "short");
    check(ur_realtime_frame(packet, 3, &size) == UR_REALTIME_E_SHORT, "short size field");
    packet[2] = 0;
    packet[3] = 8;
    check(ur_realtime_decode(packet, sizeof packet, 0u, &p) == UR_REALTIME_E_SIZE_BELOW && p.message_size == 8,
          "size below");
    packet[3] = 28;
    check(ur_realtime_decode(packet, sizeof packet, 0u, &p) == UR_REALTIME_E_UNKNOWN_SIZE &&
          p.layout == UR_REALTIME_UNKNOWN && p.raw == packet + 4 && p.raw_length == 24, "unknown size kept");
    packet[0] = 0x7f;
    check(ur_realtime_decode(packet, sizeof packet, 0u, &p) == UR_REALTIME_E_SIZE_ABOVE, "size above");
    check(strcmp(ur_realtime_error_name(UR_REALTIME_E_UNKNOWN_SIZE), "size matches no layout") == 0, "error name");
    if (failures == 0)
        printf("all real-time checks passed\n");
    return failures != 0;
}

/* Firmware (1) and (2) of `make bench-embedded`: frame a robot's primary/secondary stream and
 * read every robot-state sub-package, in every software version (generated/c/urwire.c) or in the
 * one of a pinned build (`make pinned-c PIN=5.11`, the same source against build/pinned/c).
 * main(), its loop and its memory
 * are primary_stream.c's. */
#include "board.h"
#include "primary_stream.h"

void primary_read(const urwire_message *message, const urwire_robot_state *s)
{
    /* Every sub-package the robot sent is decoded into s; the bits say which, and a few of
     * their values stand for what a firmware would use. */
    if (message->kind == URWIRE_KIND_VERSION && !message->failed) {
        board_report_int("major_version", message->as.version.major_version);
        board_report_int("minor_version", message->as.version.minor_version);
    }
    if (message->kind != URWIRE_KIND_ROBOT_STATE)
        return;
    board_report_int("present", s->present);
    board_report_int("malformed", s->malformed);
    if (s->present & URWIRE_BIT(URWIRE_PACKAGE_TYPE_ROBOT_MODE_DATA))
        board_report_int("robot_mode", s->robot_mode_data.robot_mode);
    if (s->present & URWIRE_BIT(URWIRE_PACKAGE_TYPE_JOINT_DATA))
        board_report_double("q_actual0", s->joint_data.joints[0].q_actual);
    if (s->present & URWIRE_BIT(URWIRE_PACKAGE_TYPE_CARTESIAN_INFO))
        board_report_double("tcp_x", s->cartesian_info.x);
    if (s->present & URWIRE_BIT(URWIRE_PACKAGE_TYPE_TOOL_DATA))
        board_report_float("tool_voltage", s->tool_data.tool_voltage_48v);
}

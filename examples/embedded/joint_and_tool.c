/* Firmware (4) of `make bench-embedded`: joint data and tool data alone, from a parser generated
 * with only those two sub-packages (a subset build: `python -m codegen --select`); every other
 * message and sub-package is still framed and skipped by its length. main(), its loop and
 * its memory are primary_stream.c's. */
#include "board.h"
#include "primary_stream.h"

void primary_read(const urwire_message *message, const urwire_robot_state *state)
{
    if (message->kind != URWIRE_KIND_ROBOT_STATE)
        return;
    if (state->present & URWIRE_BIT(URWIRE_PACKAGE_TYPE_JOINT_DATA))
        board_report_double("q_actual0", state->joint_data.joints[0].q_actual);
    if (state->present & URWIRE_BIT(URWIRE_PACKAGE_TYPE_TOOL_DATA))
        board_report_float("tool_voltage", state->tool_data.tool_voltage_48v);
}

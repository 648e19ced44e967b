/* The main() that firmwares (1), (2) and (4) share (primary_stream.c): frame a robot's
 * primary/secondary stream as the board receives it, decode each message, robot states into
 * their sub-packages, and hand it to the firmware's primary_read. */
#ifndef PRIMARY_STREAM_H
#define PRIMARY_STREAM_H

#include "urwire.h"

/* What a firmware does with each message the robot sent: state is the robot state's
 * sub-packages when message->kind is URWIRE_KIND_ROBOT_STATE. Each firmware defines it; the
 * faults the framer finds are reported by main ("fault", its status). */
void primary_read(const urwire_message *message, const urwire_robot_state *state);

#endif

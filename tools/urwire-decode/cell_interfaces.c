/* The interfaces urwire-decode reads, in one table (cell_interface.h). */
#include "cell_interface.h"

#include <string.h>

#include "capture_json.h"
#include "cell_streams.h"
#include "rtde_json.h"
#include "ur_realtime_json.h"

/* As python/urwire/interfaces.py lists them: an interface adds its row here. */
const cell_interface *const cell_interfaces[] = {
    &cell_primary, &cell_ur_realtime, &cell_rtde, &cell_ur_dashboard, &cell_ur_interpreter, &cell_robotiq_gripper,
    &cell_ur_reverse, &cell_ur_script_sender, &cell_ur_trajectory, &cell_ur_script_command,
};
const size_t cell_interface_count = sizeof cell_interfaces / sizeof cell_interfaces[0];

const cell_interface *cell_interface_named(const char *name)
{
    size_t i;
    for (i = 0; i < cell_interface_count; i++)
        if (strcmp(cell_interfaces[i]->name, name) == 0)
            return cell_interfaces[i];
    return NULL;
}

/* A raw stream's one conversation, of whichever interface but the primary (whose raw stream main.c
 * frames with a loop of its own): static, so that only the pages its interface uses are ever
 * touched (RTDE's recipes take the most), in 8-byte words, every state's alignment. */
#define LARGER(a, b) ((a) > (b) ? (a) : (b))
#define RAW_STATE LARGER(LARGER(sizeof(rtde_json_stream), sizeof(ur_realtime_conversation)), \
                         LARGER(sizeof(cell_lines_state), sizeof(cell_records_state)))
static uint64_t raw_state[(RAW_STATE + 7) / 8];

/* The commands a raw file's client sends all await their replies at once. */
static int16_t raw_queue[UR_DASHBOARD_PENDING_RAW];

void *cell_raw_state(void)
{
    return raw_state;
}

int16_t *cell_raw_queue(size_t *n)
{
    *n = sizeof raw_queue / sizeof raw_queue[0];
    return raw_queue;
}

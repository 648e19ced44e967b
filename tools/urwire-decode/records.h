/* The records a framer has ready, printed as canonical JSON Lines: the loop of urwire-decode,
 * in a file of its own so that its tests and fuzzer run the same code. Part of the CLI. */
#ifndef URWIRE_RECORDS_H
#define URWIRE_RECORDS_H

#include <stdbool.h>

#include "json.h"
#include "urwire.h"

/* Print every record the framer has ready, one line each, through v (a json_visitor of w);
 * returns true when one of them held an error. */
bool print_ready_records(urwire_framer *fr, const urwire_visitor *v, json_writer *w);

#endif

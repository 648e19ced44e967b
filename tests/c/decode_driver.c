/* urwire-decode run many times in one process: the peer of the differential fuzzer
 * (tests/fuzz/fuzz_diff.py), so that it need not start a process per input.
 *
 * The command's own main (tools/urwire-decode/main.c) is linked in under the name
 * urwire_decode_main (-Dmain=urwire_decode_main), so each run is the command, options and all.
 *
 * stdin: requests, each a big-endian uint32 count of arguments, then each argument as a
 * big-endian uint32 length and its bytes (the command line after the command's name).
 * stdout: for each request, what urwire-decode prints, then "=CODE\n" (its exit status), flushed.
 * End of stdin ends the driver. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#define MAX_ARGS 16
#define MAX_ARG 4096

int urwire_decode_main(int argc, char **argv);

static int read_u32(uint32_t *value)
{
    unsigned char b[4];
    if (fread(b, 1, 4, stdin) != 4)
        return 0;
    *value = (uint32_t)b[0] << 24 | (uint32_t)b[1] << 16 | (uint32_t)b[2] << 8 | (uint32_t)b[3];
    return 1;
}

int main(void)
{
    static char args[MAX_ARGS][MAX_ARG + 1];
    char *argv[MAX_ARGS + 2];
    uint32_t argc, i, len;
    while (read_u32(&argc)) {
        if (argc > MAX_ARGS)
            return 2;
        argv[0] = (char *)"urwire-decode";
        for (i = 0; i < argc; i++) {
            if (!read_u32(&len) || len > MAX_ARG || fread(args[i], 1, len, stdin) != len)
                return 2;
            args[i][len] = '\0';
            argv[i + 1] = args[i];
        }
        argv[argc + 1] = NULL;
        i = (uint32_t)urwire_decode_main((int)argc + 1, argv);
        printf("=%u\n", (unsigned)i);
        fflush(stdout);
    }
    return 0;
}

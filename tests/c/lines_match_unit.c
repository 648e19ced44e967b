/* The lines matcher (runtime/c/lines/match.c, which the C library and the dissector join) alone:
 * its pure functions over a small table of its own, without Wireshark. Built and run by
 * tests/c/test_c_kind_runtimes.py; prints "ok" or the failed check. */
#include <stdio.h>
#include <stdlib.h>

#include "match.c"

#define CHECK(x) do { if (!(x)) { printf("failed: %s (line %d)\n", #x, __LINE__); return 1; } } while (0)
#define TEXT(s) (const uint8_t *)(s), strlen(s)

static const lines_reply_t common[] = {{"no", (const char *const[]){"could not understand: '", "'"}, 2, true}};
static const lines_command_t commands[] = {
    {"load", "load", true, 1004000u, 5000000u, 10000000u,
     (const lines_reply_t[]){{"loading", (const char *const[]){"Loading program: ", ""}, 2, false}}, 1},
    {"load_installation", "load installation", true, 3002000u, 5027000u, 0,
     (const lines_reply_t[]){{"three", (const char *const[]){"a", "b", "c"}, 3, false}}, 1},
};
static const int lookup[] = {1, 0};
static const lines_spec_t spec = {
    .column = "T", .max_line = 16, .common = common, .common_count = 1, .commands = commands,
    .command_count = 2, .lookup = lookup, .version_command = 0, .version_prefix = "URSoftware ",
    .e_series_from = 5000000u, .polyscope_x_from = 10000000u,
};

/* Interpreter mode's shape: a command with no text is any other line, tried last. */
static const lines_command_t statements[] = {
    {"statement", "", true, 0, 5010000u, 0,
     (const lines_reply_t[]){{"ack", (const char *const[]){"ack: ", ""}, 2, false}}, 1},
    {"abort", "abort", false, 0, 5010000u, 0,
     (const lines_reply_t[]){{"ack", (const char *const[]){"ack"}, 1, false}}, 1},
};
static const int statement_lookup[] = {1, 0};
static const lines_spec_t any_line = {
    .column = "I", .max_line = 16, .commands = statements, .command_count = 2, .lookup = statement_lookup,
    .version_command = LINES_NONE, .version_prefix = "", .e_series_from = 5000000u,
};

int main(void)
{
    long argument;
    uint64_t v = 7;
    CHECK(lines_find_command(&spec, TEXT("load installation x"), &argument) == 1 && argument == 18);
    CHECK(lines_find_command(&spec, TEXT("load a b"), &argument) == 0 && argument == 5);
    CHECK(lines_find_command(&spec, TEXT("load "), &argument) == 0 && argument == 5);   /* an empty argument */
    CHECK(lines_find_command(&spec, TEXT("load"), &argument) == 0 && argument == -1);
    CHECK(lines_find_command(&spec, TEXT("loadx"), &argument) == LINES_NONE && argument == -1);
    CHECK(lines_find_command(&any_line, TEXT("abort"), &argument) == 1 && argument == -1);
    CHECK(lines_find_command(&any_line, TEXT("abort()"), &argument) == 0 && argument == 0);   /* the whole line */
    CHECK(lines_find_command(&any_line, TEXT(""), &argument) == 0 && argument == 0);
    CHECK(lines_classify(&spec, 0, TEXT("Loading program: p")) == &commands[0].replies[0]);
    CHECK(lines_classify(&spec, LINES_NONE, TEXT("could not understand: 'x'")) == &common[0]);
    CHECK(lines_classify(&spec, LINES_NONE, TEXT("Loading program: p")) == NULL);
    CHECK(lines_classify(&spec, 1, TEXT("a-b-c")) != NULL && lines_classify(&spec, 1, TEXT("abc")) != NULL);
    CHECK(lines_classify(&spec, 1, TEXT("ab")) == NULL && lines_classify(&spec, 1, TEXT("a-c-b")) == NULL);
    CHECK(lines_available(&spec, 1, 3002000u) && !lines_available(&spec, 1, 5011000u));
    /* Each series reads its own column: 5.27 has it, no PolyScope X does. */
    CHECK(lines_available(&spec, 1, 5027000u) && !lines_available(&spec, 1, 10013000u));
    CHECK(lines_available(&spec, 0, 10000000u) && lines_available(&spec, 0, 10013000u));
    CHECK(!lines_available(&spec, 0, 1003000u) && lines_available(&spec, 0, 5000000u));
    CHECK(lines_version_in(&spec, TEXT("URSoftware 5.11.1.108318 (Nov 26 2021)"), &v) && v == 5011001u);
    CHECK(lines_version_in(&spec, TEXT("URSoftware 5.11"), &v) && v == 5011000u);
    CHECK(lines_version_in(&spec, TEXT("URSoftware 0.0"), &v) && v == 0);
    v = 7;
    CHECK(!lines_version_in(&spec, TEXT("URSoftware 5.11."), &v));
    CHECK(!lines_version_in(&spec, TEXT("URSoftware 5.1x"), &v));
    CHECK(!lines_version_in(&spec, TEXT("URSoftware 1234.1"), &v));
    CHECK(!lines_version_in(&spec, TEXT("URSoftware 5"), &v));
    CHECK(!lines_version_in(&spec, TEXT("URSoftware "), &v) && !lines_version_in(&spec, TEXT("URSoft"), &v) && v == 7);
    printf("ok\n");
    return 0;
}

/* The envelope of a record of a capture or read with --to-robot. See envelope.h. */
#include "envelope.h"

#include <string.h>

#include "json.h"

static void put_text(FILE *out, const char *text)
{
    json_write_text(out, (const unsigned char *)text, strlen(text));
}

void envelope_open(FILE *out, const envelope *e)
{
    fputc('{', out);
    if (!e)
        return;
    fputs("\"interface\": ", out);
    put_text(out, e->interface);
    fputs(", \"direction\": ", out);
    put_text(out, e->direction);
    fputs(", \"conversation\": ", out);
    put_text(out, e->conversation);
    fputs(", ", out);
}

void envelope_line(FILE *out, const envelope *e, const char *record)
{
    envelope_open(out, e);
    fputs(record + 1, out);     /* the record's keys, after its own "{" */
    fputc('\n', out);
}

void envelope_error(FILE *out, const envelope *e, int64_t offset, const char *error)
{
    envelope_open(out, e);
    fprintf(out, "\"type\": \"error\", \"offset\": %lld, \"error\": ", (long long)offset);
    put_text(out, error);
    fputs("}\n", out);
}

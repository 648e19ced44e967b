/* The variable table as C reads it: one line per row (rtde_variable_at), its columns separated by
 * tabs (a unit of "-" when it has none), then what a read past the end gives. */
#include <stdio.h>

#include "rtde.h"

int main(void)
{
    rtde_variable v;
    size_t i;
    for (i = 0; rtde_variable_at(i, &v); i++)
        printf("%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n", v.name, rtde_value_type_name(v.type), v.output ? "output" : "input",
               v.label, v.unit ? v.unit : "-", v.since_cb3, v.since_eseries, v.since_polyscope_x);
    printf("rows: %lu of %d\n", (unsigned long)i, RTDE_VARIABLE_COUNT);
    return 0;
}

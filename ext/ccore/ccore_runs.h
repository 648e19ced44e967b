/* Sub-package forms read by one fixed run, built as the generated record objects in C (runs.c),
 * from the generated RUN_RECIPES and ITEM_RUNS of urwire.generated.messages. */
#ifndef URWIRE_CCORE_RUNS_H
#define URWIRE_CCORE_RUNS_H
#include <Python.h>

typedef struct run_recipes run_recipes;
typedef struct run_recipe run_recipe;

/* The recipes of RUN_RECIPES ({decoder: (struct, members, absent names)}) and ITEM_RUNS ({item
 * class: members}), compiled on first use; NULL with an exception set. */
run_recipes *run_recipes_new(PyObject *recipes, PyObject *item_runs);
void run_recipes_free(run_recipes *recipes);

/* The compiled recipe of a decoder (a Forms.fast entry): *recipe NULL when it has none or its
 * class is not one the recipe can fill; -1 with an exception set. */
int run_recipe_of(run_recipes *recipes, PyObject *decode, const run_recipe **recipe);

/* The record the recipe's decoder makes of buf[body:stop] (buf: bytes) read as `version`, when
 * the run is exactly that long; NULL with no exception set when it is not, or when the record
 * cannot be made here; NULL with one set on failure. */
PyObject *run_read(const run_recipe *recipe, PyObject *buf, Py_ssize_t body, Py_ssize_t stop, PyObject *version);

#endif

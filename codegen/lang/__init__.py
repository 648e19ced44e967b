"""What every kind's renderers write alike in one target language: literals, identifiers, class
names and comments, one module a language (c, lua, python). A kind's renderer imports these and
never another kind's or target's helpers, so that one spelling rule lives in one place."""

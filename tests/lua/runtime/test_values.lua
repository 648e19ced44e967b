-- runtime/lua/packages/values.lua: typed values of global variables, nested, with the table of the
-- stream's software version.
local S = dofile("stubs.lua")

local NEW = {   -- as from 5.9 (shape only: codes and names are the test's own)
    [0] = { name = "NONE", layout = "empty", item = nil, n = 0, count = 1, len = 0 },
    [1] = { name = "INT", layout = "scalar", item = "int32", n = 4, count = 1, len = 0 },
    [2] = { name = "STRING", layout = "string", item = nil, n = 0, count = 1, len = 2 },
    [3] = { name = "LIST", layout = "list", item = nil, n = 0, count = 1, len = 2 },
    [4] = { name = "MATRIX", layout = "matrix", item = nil, n = 0, count = 1, len = 2 },
    [5] = { name = "POSE", layout = "array", item = "float32", n = 4, count = 2, len = 0 },
}
local OLD = { [3] = { name = "LIST", layout = "list", item = nil, n = 0, count = 1, len = 2 },
              [5] = { name = "BOOL", layout = "scalar", item = "bool", n = 1, count = 1, len = 0 } }
local rt = S.walker_rt({ max_value_depth = 2, value_tables = { { high = 5008999, kinds = OLD, min_size = 2 },
                                                               { low = 5009000, kinds = NEW, min_size = 1 } } })

local vf = { item = "ur.v.item", type = "ur.v.type", code = "ur.v.code", count = "ur.v.length", rows = "ur.v.rows",
             cols = "ur.v.cols", row = "ur.v.row", int32 = "ur.v.int32", float32 = "ur.v.float32", bool = "ur.v.bool",
             string = "ur.v.string" }
local L = { { k = "values", term = 10, path = "variables", label = "Variable", vf = vf } }

local function run(raw, version)
    local tree = S.tree()
    local o, err = rt.walk(S.tvb(raw), tree, 0, #raw, S.st(raw, version), L, nil)
    return tree, o, err
end

local raw = S.bytes(1, 0, 0, 0, 7, 10) ..
            S.bytes(2, 0, 2) .. "hi" .. S.bytes(10) ..
            S.bytes(3, 0, 2, 1, 0, 0, 0, 1, 0, 10) ..
            S.bytes(4, 0, 1, 0, 2, 0, 0, 10)
local tree, o, err = run(raw, 5009000)
S.eq(err, nil, "no error")
S.eq(o, #raw, "to the end")
S.eq(S.dump(tree), S.lines(
    "ur.v.item @0+5 (Variable 0: INT)",
    "  ur.v.type @0+1 = INT",
    "  ur.v.code @0+1",
    "  ur.v.int32 @1+4",
    "ur.v.item @6+5 (Variable 1: STRING)",
    "  ur.v.type @6+1 = STRING",
    "  ur.v.code @6+1",
    "  ur.v.length @7+2",
    "  ur.v.string @9+2 = hi",
    "ur.v.item @12+9 (Variable 2: LIST)",
    "  ur.v.type @12+1 = LIST",
    "  ur.v.code @12+1",
    "  ur.v.length @13+2",
    "  ur.v.item @15+5 (Item 0: INT)",
    "    ur.v.type @15+1 = INT",
    "    ur.v.code @15+1",
    "    ur.v.int32 @16+4",
    "  ur.v.item @20+1 (Item 1: NONE)",
    "    ur.v.type @20+1 = NONE",
    "    ur.v.code @20+1",
    "ur.v.item @22+7 (Variable 3: MATRIX)",
    "  ur.v.type @22+1 = MATRIX",
    "  ur.v.code @22+1",
    "  ur.v.rows @23+2",
    "  ur.v.cols @25+2",
    "  ur.v.row @27+2 (Row 0)",
    "    ur.v.item @27+1 (Column 0: NONE)",
    "      ur.v.type @27+1 = NONE",
    "      ur.v.code @27+1",
    "    ur.v.item @28+1 (Column 1: NONE)",
    "      ur.v.type @28+1 = NONE",
    "      ur.v.code @28+1"), "tree")

-- The same byte is a POSE from 5.9 and a BOOL before.
raw = S.bytes(5, 1, 10)
_, o, err = run(raw, 5009000)
S.eq(err, "variables[0] at offset 1: needs 8 bytes, 2 left", "POSE in 5.9")
tree, o, err = run(raw, 5000000)
S.eq(err, nil, "BOOL in 5.0")
S.eq(S.dump(tree):match("ur.v.bool @1%+1") ~= nil, true, "the bool")

_, o, err = run(S.bytes(9, 10), 5009000)
S.eq(err, "variables[0].type at offset 0: unknown value type 9", "unknown type")
_, o, err = run(S.bytes(0, 11), 5009000)
S.eq(err, "variables[0] at offset 1: expected terminator 0x0a, found 0x0b", "terminator")
_, o, err = run(S.bytes(0), 5009000)
S.eq(err, "variables[0] at offset 1: needs 1 bytes, 0 left", "missing terminator")
_, o, err = run(S.bytes(3, 0, 1, 3, 0, 1, 0, 10), 5009000)
S.eq(err, "variables[0][0][0] at offset 6: nesting deeper than 2", "depth")
_, o, err = run(S.bytes(2, 0xff, 0xff, 10), 5009000)
S.eq(err, "variables[0] at offset 1: negative length -1", "negative string length")
_, o, err = run(S.bytes(4, 0, 1, 0xff, 0xff, 10), 5009000)
S.eq(err, "variables[0] at offset 3: negative length -1", "negative column count, at its own offset")

-- Counts are weighed against the bytes left, at the table's fewest bytes per value.
_, o, err = run(S.bytes(3, 0, 4, 0, 0, 10), 5009000)
S.eq(err, "variables[0] at offset 1: 4 items need more than the 3 bytes left", "LIST: 4 items, 3 bytes left")
_, o, err = run(S.bytes(3, 0, 2, 0, 0, 10), 5009000)
S.eq(err, nil, "LIST: 2 items in the 3 bytes left")
_, o, err = run(S.bytes(4, 0x7f, 0xff, 0, 0, 10), 5009000)
S.eq(err, "variables[0] at offset 1: 32767 rows of 0 columns", "MATRIX: rows that take no bytes")
tree, o, err = run(S.bytes(4, 0, 0, 0x7f, 0xff, 10), 5009000)
S.eq(err, nil, "MATRIX: columns of no rows take no bytes either, and claim nothing")
_, o, err = run(S.bytes(4, 0, 2, 0, 3, 0, 0, 0, 10), 5009000)
S.eq(err, "variables[0] at offset 1: 6 items need more than the 4 bytes left", "MATRIX: rows times columns")
-- Before 5.9 the test's table takes 2 bytes a value at the least (it has no NONE).
_, o, err = run(S.bytes(3, 0, 3, 5, 1, 5, 0, 10), 5000000)
S.eq(err, "variables[0] at offset 1: 3 items need more than the 5 bytes left", "the table's own fewest bytes")
_, o, err = run(S.bytes(3, 0, 2, 5, 1, 5, 0, 10), 5000000)
S.eq(err, nil, "two BOOLs in the 5 bytes left")
print("ok")

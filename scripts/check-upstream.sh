#!/usr/bin/env bash
# check-upstream.sh WIRESHARK_SOURCE FILE...: Wireshark's own source checks, from a Wireshark
# source tree's tools/, on the generated dissectors (Debian ships none of them). Each check that
# the tree has runs on every file; a check that reports a problem makes the exit status 1.
#   checkAPIs.pl               prohibited and deprecated APIs, bad value_string and hf arrays
#   checkhf.pl                 hf_ handles declared but not registered, or never used
#   check_typed_item_calls.py  each proto_tree_add_* call against its field's type, masks, labels
#   check_tfs.py               true_false_strings that tfs.h already has
#   check_val_to_str.py        val_to_str formats (asked to read generated files: --generated)
#   check_spelling.py          words of strings against a dictionary and tools/wireshark_words.txt,
#                              on the .c files only (as the script picks files itself); needs the
#                              pip package pyspellchecker (module spellchecker); skipped, and
#                              said, where it is missing
#   check_static.py            globals that could be static: it reads the objects of a Wireshark
#                              build, so it runs only with WIRESHARK_BUILD set to the build folder
#                              of a tree the patch is applied to (make upstream-build makes one),
#                              and is given the tree's copy of each .c (epan/dissectors/...);
#                              tests/native/test_plugin.py checks the same on the plugin's objects
set -u
source=${1:?usage: check-upstream.sh WIRESHARK_SOURCE FILE...}
shift
if [ ! -d "$source/tools" ]; then
    echo "check-upstream: $source has no tools/ folder: give WIRESHARK_SOURCE a Wireshark checkout" >&2
    exit 2
fi
files=()
for f in "$@"; do files+=("$(realpath "$f")"); done
[ ${#files[@]} -gt 0 ] || { echo "check-upstream: no files to check" >&2; exit 2; }
status=0
ran=0

# A folder with the tree's check_spelling.py and its word list plus the protocols' words, made once.
words_tree=""
make_spelling_tree() {
    if [ -z "$words_tree" ]; then
        words_tree=$(mktemp -d)
        trap 'rm -rf "$words_tree"' EXIT
        mkdir -p "$words_tree/tools"
        cp "$source/tools/check_spelling.py" "$words_tree/tools/"
        python3 -c 'import importlib.util, sys
spec = importlib.util.spec_from_file_location("up", sys.argv[1]); up = importlib.util.module_from_spec(spec)
spec.loader.exec_module(up); sys.stdout.write(up.with_our_words(open(sys.argv[2], encoding="utf-8").read()))' \
            "$(dirname "$0")/upstream-patch.py" "$source/tools/wireshark_words.txt" > "$words_tree/tools/wireshark_words.txt"
    fi
}

finding() {
    echo "check-upstream: $1 reports problems"
    status=1
}

if [ -f "$source/tools/checkAPIs.pl" ]; then
    echo "== checkAPIs.pl"; ran=$((ran + 1))
    # As Wireshark's git pre-commit hook runs it: one file at a time, with -p where the script
    # knows it (then a packet-*.c is also checked for abort() and terminal output). Releases that
    # name those groups dissectors-prohibited and dissectors-restricted still have -p ask for
    # their old names, so they are asked for by name too.
    precommit=()
    grep -q "'pre-commit'" "$source/tools/checkAPIs.pl" && precommit=(-p)
    for group in dissectors-prohibited dissectors-restricted; do
        grep -q "'$group'" "$source/tools/checkAPIs.pl" && precommit+=(-g "$group")
    done
    for f in "${files[@]}"; do
        (cd "$source" && perl tools/checkAPIs.pl "${precommit[@]}" "$f") || finding "checkAPIs.pl on $(basename "$f")"
    done
fi
if [ -f "$source/tools/checkhf.pl" ]; then
    echo "== checkhf.pl"; ran=$((ran + 1))
    out=$(cd "$source" && perl tools/checkhf.pl "${files[@]}" 2>&1); rc=$?
    [ -n "$out" ] && echo "$out"
    { [ $rc -ne 0 ] || echo "$out" | grep -qE "Unused entry|NO ARRAY"; } && finding checkhf.pl
fi
# One file a run: some releases of these scripts keep only the last --file.
for check in check_typed_item_calls.py check_tfs.py check_val_to_str.py check_spelling.py check_static.py; do
    [ -f "$source/tools/$check" ] || continue
    extra=()
    case $check in
        check_typed_item_calls.py) extra=(--mask --label --consecutive) ;;
        check_val_to_str.py)
            # it passes over a file that says it was generated, as ours do, unless asked not to
            grep -q -- "--generated" "$source/tools/$check" && extra=(--generated) ;;
        check_spelling.py)
            if ! python3 -c "import spellchecker" 2>/dev/null; then
                echo "== $check: skipped, it needs the pip package pyspellchecker"; continue
            fi
            # the dictionary only: no download of Wikipedia's list of common misspellings
            grep -q -- "--no-wikipedia" "$source/tools/$check" && extra=(--no-wikipedia) ;;
        check_static.py)
            if [ -z "${WIRESHARK_BUILD:-}" ]; then
                echo "== $check: skipped, it needs WIRESHARK_BUILD (a build folder of the patched tree)"; continue
            fi
            extra=(--build-folder "$(realpath "$WIRESHARK_BUILD")") ;;
    esac
    echo "== $check"; ran=$((ran + 1))
    for f in "${files[@]}"; do
        # check_spelling.py reads a file it is given but a .c as prose, every word of the code
        # too; of ours it would itself pick (isAppropriateFile) only the .c files
        [ "$check" = check_spelling.py ] && [ "${f%.c}" = "$f" ] && continue
        target=$f
        if [ "$check" = check_static.py ]; then
            # it finds a file's object only by the file's path in the tree (epan/dissectors/...),
            # and says nothing of any other path: the tree's own copy, where the patch put it
            [ "${f%.c}" = "$f" ] && continue
            target=epan/dissectors/$(basename "$f")
            if [ ! -f "$source/$target" ]; then
                echo "check_static.py: $source has no $target: apply the patch there (make upstream-apply)"
                finding "$check on $(basename "$f")"; continue
            fi
        fi
        # check_spelling.py reads ./tools/wireshark_words.txt: the tree's, with the words the
        # patch adds to it (dissector/native/wireshark_words.txt) where they are not there yet
        where=$source
        [ "$check" = check_spelling.py ] && make_spelling_tree && where=$words_tree
        out=$(cd "$where" && python3 "tools/$check" --file "$target" "${extra[@]}" 2>&1); rc=$?
        # check_spelling.py prints its count in bold: the terminal's escapes would hide it
        out=$(printf '%s\n' "$out" | sed 's/\x1b\[[0-9;]*m//g')
        echo "$out"
        # "3 warnings found", or "3 warnings" in releases of check_typed_item_calls.py
        problems="^[1-9][0-9]* (issues|warnings)( found)?$|^Error|Traceback"
        { [ $rc -ne 0 ] || echo "$out" | grep -qE "$problems"; } && finding "$check on $(basename "$f")"
    done
done
if [ $ran -eq 0 ]; then
    echo "check-upstream: none of Wireshark's checks is under $source/tools" >&2
    exit 2
fi
verdict=$([ $status -eq 0 ] && echo "no problem" || echo "problems above")
echo "check-upstream: $ran checks on ${#files[@]} files, $verdict"
exit $status

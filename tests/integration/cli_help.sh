# The command line explains itself: romkit --help lists every command, romkit CMD --help says
# what CMD does, lists the options its parser accepts and ends with an example; unknown commands
# are refused; long stages show progress on a terminal only (DESIGN.md, Rules: Progress).
. tests/lib.sh
COMMANDS="mesh fom motions adaptive basis cubature build plan run rom compare track dmd neural-dmd control inspect export"
case "$ROMKIT" in */*) case "$ROMKIT" in /*) ;; *) ROMKIT=$PWD/$ROMKIT ;; esac ;; esac

# romkit --help: every command, one line each, and a pipeline example.
if "$ROMKIT" --help >"$TMP/out" 2>"$TMP/err"; then ok top_help_exits_0; else fail top_help_exits_0 "status $?"; fi
missing=""
for c in $COMMANDS; do grep -q "^  $c  " "$TMP/out" || missing="$missing $c"; done
[ -z "$missing" ] && ok top_help_lists_every_command || fail top_help_lists_every_command "missing:$missing"
grep -q "^  romkit fom " "$TMP/out" && grep -q "^  romkit build " "$TMP/out" && grep -q "^  romkit run " "$TMP/out" \
    && grep -q "^  romkit dmd " "$TMP/out" && ok top_help_shows_pipeline || fail top_help_shows_pipeline "$(cat "$TMP/out")"

# No command: usage on stderr, status 2. An unknown command: a message naming it, status 2.
"$ROMKIT" >"$TMP/out" 2>"$TMP/err"; rc=$?
[ $rc -eq 2 ] && grep -q "usage:" "$TMP/err" && ok no_command_exits_2 || fail no_command_exits_2 "status $rc"
"$ROMKIT" frobnicate x >"$TMP/out" 2>"$TMP/err"; rc=$?
[ $rc -eq 2 ] && grep -q "unknown command 'frobnicate'" "$TMP/err" && ok unknown_command_exits_2 \
    || fail unknown_command_exits_2 "status $rc: $(head -c 200 "$TMP/err")"

# The options a command's help names: those of its synopsis (not the hyphen inside a name such as
# neural-dmd) and the first words of its
# option lines ("  --rank, --energy  ...").
help_options() {
    awk '/^usage:/ { syn = 1 } syn && !/^usage:/ && !/^ +\[/ { syn = 0 }
         syn { gsub(/romkit [-a-z]+/, ""); print; next }
         /^ {2,4}-/ { sub(/^ +/, ""); n = split($0, w, /  +/); print w[1] }' "$1" |
        grep -o -- '-[-a-z][-a-z]*' | grep -v '^-[A-Z]$' | sort -u
}

for c in $COMMANDS; do
    if "$ROMKIT" "$c" --help >"$TMP/help" 2>"$TMP/err"; then ok "${c}_help_exits_0"; else fail "${c}_help_exits_0" "status $?"; fi
    grep -q "^usage: romkit $c" "$TMP/help" && ok "${c}_help_has_usage" || fail "${c}_help_has_usage" "$(head -3 "$TMP/help")"
    grep -qi "^example" "$TMP/help" && grep -q "^  romkit " "$TMP/help" && ok "${c}_help_has_example" \
        || fail "${c}_help_has_example" "no 'example' line followed by a romkit command"
    "$ROMKIT" "$c" -h >"$TMP/h" 2>&1 && cmp -s "$TMP/h" "$TMP/help" && ok "${c}_dash_h_is_help" \
        || fail "${c}_dash_h_is_help" "romkit $c -h differs from --help"
    # Every option the help names is one the parser knows ...
    unknown=""
    for o in $(help_options "$TMP/help"); do
        (cd "$TMP" && "$ROMKIT" "$c" "$o" 1 >"$TMP/out" 2>"$TMP/err" </dev/null)
        grep -Eq -- "unknown option '?$o('| |\$)|^romkit $c: $o needs a value \(or is unknown\)" "$TMP/err" \
            && unknown="$unknown $o"
    done
    [ -z "$unknown" ] && ok "${c}_help_options_are_accepted" || fail "${c}_help_options_are_accepted" "refused:$unknown"
    # ... and every option the parser looks for is in the help.
    src=tools/cmd_$(echo "$c" | tr - _).c
    if [ -f "$src" ]; then
        absent=""
        for o in $(grep -o '"--*[a-z][-a-z]*"' "$src" | tr -d '"' | sort -u); do
            case "$o" in --help | -h) continue ;; esac
            grep -q -- "$o\\([^-a-z]\\|\$\\)" "$TMP/help" || absent="$absent $o"
        done
        [ -z "$absent" ] && ok "${c}_help_names_every_option" || fail "${c}_help_names_every_option" "not in help:$absent"
    fi
done

# Progress: a full-order run of a tiny scene. On a terminal (a pseudo-terminal from script)
# it draws "fom: k/N (p%)"; with stderr to a file, or with --quiet, it draws nothing.
cat >"$TMP/tiny.json" <<'EOF'
{"objects": [{"mesh": {"box": {"size": [1, 0.1, 0.1], "cells": [4, 1, 1]}},
  "material": {"model": "neohookean", "young": 2e5, "poisson": 0.4, "density": 1000},
  "fixed": [{"box": [[-1, -1, -1], [0.01, 2, 2]]}]}],
 "gravity": [0, -9.81, 0], "time": {"step": 0.01, "duration": 0.05}}
EOF
progress='full-order run: [0-9][0-9]*/[0-9][0-9]* *( *[0-9]*%)'
if command -v script >/dev/null 2>&1 && script -qec true /dev/null </dev/null >/dev/null 2>&1; then
    script -qec "\"$ROMKIT\" fom \"$TMP/tiny.json\"" /dev/null </dev/null >"$TMP/tty" 2>&1; rc=$?
    [ $rc -eq 0 ] && grep -q "$progress" "$TMP/tty" && grep -q "full-order run: done" "$TMP/tty" && ok progress_on_terminal \
        || fail progress_on_terminal "status $rc: $(head -c 300 "$TMP/tty")"
    script -qec "\"$ROMKIT\" fom \"$TMP/tiny.json\" --quiet" /dev/null </dev/null >"$TMP/tty" 2>&1
    grep -q "$progress\|full-order run: done" "$TMP/tty" && fail quiet_on_terminal "$(head -c 300 "$TMP/tty")" \
        || ok quiet_on_terminal
else
    ok "progress_on_terminal # skipped: no script command"
    ok "quiet_on_terminal # skipped: no script command"
fi
"$ROMKIT" fom "$TMP/tiny.json" >"$TMP/out" 2>"$TMP/err"; rc=$?
[ $rc -eq 0 ] && ! grep -q "$progress\|full-order run: done" "$TMP/err" && ! grep -q "$(printf '\r')" "$TMP/err" \
    && ok no_progress_when_not_a_terminal || fail no_progress_when_not_a_terminal "status $rc: $(head -c 300 "$TMP/err")"

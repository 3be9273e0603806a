# The README's embedding example (examples/embed/readme_example.c, built by make all): the README's
# code block is that file's text, it steps a baked asset with every status checked, and each
# refusal it handles (no file, a damaged asset, no "tip" group) ends it with a message.
. tests/lib.sh
B=${ROMKIT_BUILD:-build}
EX=$B/readme_example
SCENE=examples/scenes/cantilever_small.json

# The README's ```c block that follows the line naming the file, against the file itself.
awk '/examples\/embed\/readme_example\.c/ { named = 1 } named && /^```c$/ { inside = 1; next }
     inside && /^```$/ { exit } inside { print }' README.md >"$TMP/block.c"
if [ -s "$TMP/block.c" ] && cmp -s "$TMP/block.c" examples/embed/readme_example.c; then ok readme_block_is_the_example
else fail readme_block_is_the_example "README.md's code block differs from examples/embed/readme_example.c: $(diff "$TMP/block.c" examples/embed/readme_example.c | head -5)"; fi

"$ROMKIT" build "$SCENE" -o "$TMP/a.rombin" --quiet >/dev/null 2>"$TMP/err" || fail readme_example_asset "$(cat "$TMP/err")"
if "$EX" "$TMP/a.rombin" >"$TMP/out" 2>"$TMP/err"; then
    # 100 steps of h = 0.01 s; the last shown vertex, then the same vertex in romkit run without the push.
    read -r _ _ t _ _ _ _ x y z <"$TMP/out"
    "$ROMKIT" run "$TMP/a.rombin" --steps 100 --positions "$TMP/p.npy" --quiet >/dev/null 2>&1
    if python3 - "$TMP/p.npy" "$t" "$x" "$y" "$z" <<'PY'
import ast, struct, sys, math
data = open(sys.argv[1], "rb").read()
hlen = struct.unpack("<H", data[8:10])[0]
head = ast.literal_eval(data[10:10 + hlen].decode())
assert head["descr"] in ("<f4", "<f8"), head
n, _ = head["shape"]                      # romkit run --positions: the final shown positions, n x 3
size = 4 if head["descr"] == "<f4" else 8
last = struct.unpack("<3" + ("f" if size == 4 else "d"), data[10 + hlen + (n - 1) * 3 * size:][:3 * size])
t, x, y, z = (float(v) for v in sys.argv[2:6])
assert t == 1.0, f"t = {t}, not 100 steps of 0.01 s"
assert all(math.isfinite(v) for v in (x, y, z)), (x, y, z)
# The push is 0.05 N along +z on the tip: that vertex ends further along z than unpushed, by more
# than float rounding, and no further than the cantilever's length.
assert 1e-4 < z - last[2] < 1.0, f"pushed z {z} against unpushed {last[2]}"
assert abs(x - last[0]) < 0.1 and abs(y - last[1]) < 0.1, (x, y, last)
PY
    then ok readme_example_steps_and_pushes; else fail readme_example_steps_and_pushes "$(cat "$TMP/out")"; fi
else
    fail readme_example_steps_and_pushes "$(cat "$TMP/err")"
fi

"$EX" >/dev/null 2>"$TMP/err"; [ $? -eq 2 ] && grep -q usage "$TMP/err" && ok readme_example_usage || fail readme_example_usage "$(cat "$TMP/err")"
size=$(wc -c <"$TMP/a.rombin")
head -c $((size / 2)) "$TMP/a.rombin" >"$TMP/cut.rombin"
expect_fail readme_example_refuses_a_damaged_asset "open: truncated" "$EX" "$TMP/cut.rombin"
sed 's/"name": "tip"/"name": "end"/' "$SCENE" >"$TMP/no_tip.json"
"$ROMKIT" build "$TMP/no_tip.json" -o "$TMP/b.rombin" --quiet >/dev/null 2>&1
expect_fail readme_example_refuses_a_missing_group "push: " "$EX" "$TMP/b.rombin"

# romkit motions (issue 33's training-data generator, the Grassmann paper's Sec. 6): a cube dropped
# through pachinko pegs and tumbled in a turning drum, each scene run at full order with no crossing
# and with contact made; the same seed writes the same files; a pod basis trains on the runs; bad
# templates and options are refused by name with nothing written.
. tests/lib.sh
cat >"$TMP/cube.json" <<'JSON'
{
  "objects": [{
    "mesh": {"box": {"size": [0.2, 0.2, 0.2], "cells": [2, 2, 2]}},
    "material": {"model": "neohookean", "young": 1e5, "poisson": 0.45, "density": 1000}
  }],
  "gravity": [0, -9.81, 0],
  "time": {"step": 0.01, "duration": 0.5, "integrator": "backward_euler"},
  "obstacles": [{"plane": {"point": [0, -1, 0], "normal": [0, 1, 0]}}],
  "rom": {"basis": "modes", "size": 6}
}
JSON

"$ROMKIT" motions "$TMP/cube.json" --kind pachinko --count 2 --seed 7 -o "$TMP/p" >"$TMP/p.out" 2>&1 \
    && [ -f "$TMP/p/pachinko_0.json" ] && [ -f "$TMP/p/pachinko_1.json" ] && grep -q "17 pegs and 5 planes" "$TMP/p.out" \
    && grep -q "the template's 1 obstacles are not in them" "$TMP/p.out" \
    && ok pachinko_writes_two_boards || fail pachinko_writes_two_boards "$(cat "$TMP/p.out")"
"$ROMKIT" motions "$TMP/cube.json" --kind dryer --count 1 --seed 3 --duration 0.3 -o "$TMP/d" >"$TMP/d.out" 2>&1 \
    && [ -f "$TMP/d/drum.obj" ] && [ -f "$TMP/d/dryer_0.json" ] \
    && ok dryer_writes_a_drum || fail dryer_writes_a_drum "$(cat "$TMP/d.out")"
json_checks pachinko_scene_has_the_board "$TMP/p/pachinko_0.json" "obstacles[21].plane" "obstacles[0].capsule.radius=0.02" \
    "contact.friction=0.3" "objects[0].velocity"
json_checks dryer_scene_turns_its_drum "$TMP/d/dryer_0.json" 'obstacles[0].mesh.file="drum.obj"' \
    "obstacles[0].twist.degrees_per_second" "time.duration=0.3"
"$JSONQ" has "$TMP/p/pachinko_0.json" rom 2>/dev/null && fail pachinko_scene_has_no_rom "rom kept" || ok pachinko_scene_has_no_rom

# Each scene at full order: contact made (the closest approach within dhat, 1 mm by default),
# nothing crossed (the exact test every frame).
for s in p/pachinko_0 p/pachinko_1 d/dryer_0; do
    n=$(echo "$s" | tr / _)
    if "$ROMKIT" fom "$TMP/$s.json" --snapshots "$TMP/$s.npy" --report "$TMP/$s.rep.json" --quiet >"$TMP/fom.out" 2>&1; then
        d=$(json_num "$TMP/$s.rep.json" contact.min_distance)
        json_is "$TMP/$s.rep.json" contact.intersections 0 && below "$d" 1e-3 && ok "${n}_runs_in_contact_without_crossing" \
            || fail "${n}_runs_in_contact_without_crossing" "closest $d, crossings $("$JSONQ" get "$TMP/$s.rep.json" contact.intersections)"
    else fail "${n}_runs_in_contact_without_crossing" "$(tail -3 "$TMP/fom.out")"; fi
done

# Gravity along -z: the board stands in the frame gravity sets.
sed 's/"gravity": \[0, -9.81, 0\]/"gravity": [0, 0, -9.81]/' "$TMP/cube.json" >"$TMP/zup.json"
if "$ROMKIT" motions "$TMP/zup.json" --kind pachinko --count 1 --duration 0.3 -o "$TMP/z" --quiet \
    && "$ROMKIT" fom "$TMP/z/pachinko_0.json" --report "$TMP/z.rep.json" --quiet >"$TMP/z.out" 2>&1; then
    d=$(json_num "$TMP/z.rep.json" contact.min_distance)
    json_is "$TMP/z.rep.json" contact.intersections 0 && below "$d" 1e-3 && ok board_follows_gravity_along_z \
        || fail board_follows_gravity_along_z "closest $d"
else fail board_follows_gravity_along_z "$(tail -3 "$TMP/z.out")"; fi

# The same seed writes the same files, another seed other draws.
"$ROMKIT" motions "$TMP/cube.json" --kind pachinko --count 2 --seed 7 -o "$TMP/p2" --quiet \
    && cmp -s "$TMP/p/pachinko_1.json" "$TMP/p2/pachinko_1.json" && ok same_seed_same_scenes \
    || fail same_seed_same_scenes "differ"
"$ROMKIT" motions "$TMP/cube.json" --kind pachinko --count 2 --seed 8 -o "$TMP/p3" --quiet \
    && ! cmp -s "$TMP/p/pachinko_1.json" "$TMP/p3/pachinko_1.json" && ok other_seed_other_scenes \
    || fail other_seed_other_scenes "same"

# A pod basis trains on the runs (rom.training), the template's own drop measured against it.
sed "s|\"rom\": {\"basis\": \"modes\", \"size\": 6}|\"rom\": {\"basis\": \"pod\", \"size\": 6, \"training\": [{\"snapshots\": \"p/pachinko_0.npy\"}, {\"snapshots\": \"p/pachinko_1.npy\"}, {\"snapshots\": \"d/dryer_0.npy\"}]}|" \
    "$TMP/cube.json" >"$TMP/pod.json"
"$ROMKIT" compare "$TMP/pod.json" --report "$TMP/pod.rep.json" >"$TMP/pod.out" 2>&1 && grep -q "^pod-6 " "$TMP/pod.out" \
    && ok pod_trains_on_the_motions || fail pod_trains_on_the_motions "$(tail -4 "$TMP/pod.out")"

# Refused by name, nothing written.
sed 's/"material"/"fixed": [{"box": [[-1, -1, -1], [0.01, 1, 1]]}], "material"/' "$TMP/cube.json" >"$TMP/fixed.json"
expect_fail refuses_a_fixed_object "objects\[0\] has fixed or moving vertices" "$ROMKIT" motions "$TMP/fixed.json" --kind dryer -o "$TMP/no1"
[ ! -e "$TMP/no1" ] && ok refused_writes_nothing || fail refused_writes_nothing "$(ls "$TMP/no1")"
sed 's/"gravity": \[0, -9.81, 0\]/"gravity": [0, 0, 0]/' "$TMP/cube.json" >"$TMP/nog.json"
expect_fail refuses_no_gravity "gravity is zero" "$ROMKIT" motions "$TMP/nog.json" --kind pachinko -o "$TMP/no2"
expect_fail refuses_count_0 "count must be" "$ROMKIT" motions "$TMP/cube.json" --kind pachinko --count 0 -o "$TMP/no3"
expect_fail refuses_an_unknown_kind "kind must be pachinko or dryer" "$ROMKIT" motions "$TMP/cube.json" --kind spin -o "$TMP/no4"
[ ! -e "$TMP/no2" ] && [ ! -e "$TMP/no3" ] && [ ! -e "$TMP/no4" ] && ok bad_options_write_nothing || fail bad_options_write_nothing "written"

# Fuzzing and damaged-asset tools, included by the main Makefile (which defines BUILD, RT_SRC
# and $(BUILD)/romkit; include it after RT_SRC is defined, prerequisites expand at once). Targets:
#   $(BUILD)/fuzz/replay-san      clang + ASan/UBSan: replays inputs, --expect-error / --expect-ok
#                                 (clang: its UBSan also checks pointer arithmetic overflow)
#   $(BUILD)/fuzz/damage          damaged variants of a valid asset (a corpus and test inputs)
#   $(BUILD)/fuzz/fuzz-open-step  the libFuzzer binary (clang)
#   fuzz                          seeds + damage corpus, then FUZZ_SECONDS of fuzzing; crashes
#                                 land in $(BUILD)/fuzz/crashes/ (replay them with replay-san)

# Keep the including Makefile's default goal: this fragment's first target must not become it.
fuzz_saved_goal := $(.DEFAULT_GOAL)

FUZZ_CC      ?= clang
FUZZ_SECONDS ?= 60
FUZZ_DIR     := $(BUILD)/fuzz
FUZZ_SRC     := tests/fuzz/fuzz_target.c
FUZZ_HDR     := $(wildcard runtime/*.h) formats/rombin.h formats/rombin_read.h
FUZZ_SAN     := -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
# Extra flags for the libFuzzer build, e.g. -DROMRT_DOUBLE, or -fno-sanitize=pointer-overflow to
# fuzz past a known finding (make does not notice a change: remove the binary first).
FUZZ_FLAGS   ?=

.PHONY: fuzz

$(FUZZ_DIR)/replay-san: tests/fuzz/replay.c $(FUZZ_SRC) $(RT_SRC) $(FUZZ_HDR)
	@mkdir -p $(dir $@)
	$(FUZZ_CC) -std=c99 -O1 -g $(FUZZ_SAN) -I. -o $@ tests/fuzz/replay.c $(FUZZ_SRC) $(RT_SRC) -lm

# Toolchain side, but only the container reader: CRCs come from rombin_crc32, no zlib.
$(FUZZ_DIR)/damage: tests/fuzz/damage.c formats/rombin_read.c formats/rombin_read.h formats/rombin.h runtime/romrt.h
	@mkdir -p $(dir $@)
	$(CC) -std=c99 -O2 -g -Wall -Wextra -I. -o $@ tests/fuzz/damage.c formats/rombin_read.c

$(FUZZ_DIR)/fuzz-open-step: $(FUZZ_SRC) $(RT_SRC) $(FUZZ_HDR)
	@mkdir -p $(dir $@)
	$(FUZZ_CC) -std=c99 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all $(FUZZ_FLAGS) -I. -o $@ \
	    $(FUZZ_SRC) $(RT_SRC) -lm

# Seeds in both precisions, their damaged variants, then the fuzzer. -max_len: twice the larger
# seed, so inputs may grow; -timeout: a step that loops is a finding too.
fuzz: $(FUZZ_DIR)/fuzz-open-step $(FUZZ_DIR)/damage $(BUILD)/romkit
	@mkdir -p $(FUZZ_DIR)/corpus $(FUZZ_DIR)/crashes
	$(BUILD)/romkit build tests/fuzz/seed_scene.json -o $(FUZZ_DIR)/seed.rombin --quiet
	$(BUILD)/romkit build tests/fuzz/seed_scene.json -o $(FUZZ_DIR)/seed64.rombin --quiet --precision float64
	$(BUILD)/romkit build tests/fuzz/seed_koopman.json -o $(FUZZ_DIR)/seedk.rombin --quiet
	$(BUILD)/romkit build tests/fuzz/seed_both.json -o $(FUZZ_DIR)/seedb.rombin --quiet
	$(BUILD)/romkit build tests/fuzz/seed_skinning.json -o $(FUZZ_DIR)/seeds.rombin --quiet
	$(BUILD)/romkit build tests/fuzz/seed_points.json -o $(FUZZ_DIR)/seedp.rombin --quiet
	$(BUILD)/romkit build tests/fuzz/seed_adaptive.json -o $(FUZZ_DIR)/seeda.rombin --quiet
	$(BUILD)/romkit build tests/fuzz/seed_crom.json -o $(FUZZ_DIR)/seedc.rombin --quiet
	$(BUILD)/romkit build tests/fuzz/seed_objects.json -o $(FUZZ_DIR)/seedo.rombin --quiet
	$(BUILD)/romkit build tests/fuzz/seed_obstacles.json -o $(FUZZ_DIR)/seedx.rombin --quiet
	rm -rf $(FUZZ_DIR)/damaged $(FUZZ_DIR)/damaged64 $(FUZZ_DIR)/damagedk $(FUZZ_DIR)/damagedb $(FUZZ_DIR)/damageds \
	    $(FUZZ_DIR)/damagedp $(FUZZ_DIR)/damageda $(FUZZ_DIR)/damagedc $(FUZZ_DIR)/damagedx
	$(FUZZ_DIR)/damage $(FUZZ_DIR)/seed.rombin $(FUZZ_DIR)/damaged >/dev/null
	$(FUZZ_DIR)/damage $(FUZZ_DIR)/seed64.rombin $(FUZZ_DIR)/damaged64 >/dev/null
	$(FUZZ_DIR)/damage $(FUZZ_DIR)/seedk.rombin $(FUZZ_DIR)/damagedk >/dev/null
	$(FUZZ_DIR)/damage $(FUZZ_DIR)/seedb.rombin $(FUZZ_DIR)/damagedb >/dev/null
	$(FUZZ_DIR)/damage $(FUZZ_DIR)/seeds.rombin $(FUZZ_DIR)/damageds >/dev/null
	$(FUZZ_DIR)/damage $(FUZZ_DIR)/seedp.rombin $(FUZZ_DIR)/damagedp >/dev/null
	$(FUZZ_DIR)/damage $(FUZZ_DIR)/seeda.rombin $(FUZZ_DIR)/damageda >/dev/null
	$(FUZZ_DIR)/damage $(FUZZ_DIR)/seedc.rombin $(FUZZ_DIR)/damagedc >/dev/null
	$(FUZZ_DIR)/damage $(FUZZ_DIR)/seedx.rombin $(FUZZ_DIR)/damagedx >/dev/null
	cp $(FUZZ_DIR)/seed.rombin $(FUZZ_DIR)/seed64.rombin $(FUZZ_DIR)/seedk.rombin $(FUZZ_DIR)/seedb.rombin \
	    $(FUZZ_DIR)/seeds.rombin $(FUZZ_DIR)/seedp.rombin $(FUZZ_DIR)/seeda.rombin $(FUZZ_DIR)/seedc.rombin $(FUZZ_DIR)/seedx.rombin \
	    $(FUZZ_DIR)/corpus/
	for d in damaged damaged64 damagedk damagedb damageds damagedp damageda damagedc damagedx; do for k in bad good; do for f in $(FUZZ_DIR)/$$d/$$k/*; do \
	    cp "$$f" "$(FUZZ_DIR)/corpus/$$d-$$k-$$(basename "$$f")"; done; done; done
	max=$$(wc -c <$(FUZZ_DIR)/seed64.rombin); a=$$(wc -c <$(FUZZ_DIR)/seed.rombin); \
	[ "$$a" -gt "$$max" ] && max=$$a; \
	$(FUZZ_DIR)/fuzz-open-step -max_total_time=$(FUZZ_SECONDS) -rss_limit_mb=2048 -max_len=$$((2 * max)) \
	    -timeout=20 -print_final_stats=1 -artifact_prefix=$(FUZZ_DIR)/crashes/ $(FUZZ_DIR)/corpus

.DEFAULT_GOAL := $(fuzz_saved_goal)

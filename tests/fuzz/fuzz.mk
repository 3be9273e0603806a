# Fuzzing and damaged-asset tools, included by the main Makefile (which defines BUILD, RT_SRC
# and $(BUILD)/romkit; include it after RT_SRC is defined, prerequisites expand at once). Targets:
#   $(BUILD)/fuzz/replay-san      clang + ASan/UBSan: replays inputs, --expect-error / --expect-ok
#                                 (clang: its UBSan also checks pointer arithmetic overflow)
#   $(BUILD)/fuzz/damage          damaged variants of a valid asset (a corpus and test inputs)
#   $(BUILD)/fuzz/fuzz-open-step  the libFuzzer binary (clang)
#   $(BUILD)/fuzz/fuzz-read-NAME  libFuzzer binaries of the precompute's readers of outside files
#                                 (tests/fuzz/fuzz_read.c; NAME in FUZZ_READERS), over a clang +
#                                 ASan/UBSan build of the stages they link ($(BUILD)/fuzz/lib)
#   fuzz-targets                  every libFuzzer binary, nothing run
#   fuzz-run-open-step            seeds + damage corpus, then FUZZ_SECONDS of fuzzing the runtime
#   fuzz-run-NAME                 FUZZ_SECONDS of fuzzing reader NAME from tests/fuzz/seeds/NAME
#   fuzz                          every fuzz-run-*, FUZZ_SECONDS each; crashes land in
#                                 $(BUILD)/fuzz/crashes/ (the runtime's: replay them with
#                                 replay-san; a reader's: run its binary on the file). A fixed
#                                 finding's input goes to tests/fuzz/regressions/<target>/, which
#                                 tests/integration/fuzz_short.sh and damaged_assets.sh replay.

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

.PHONY: fuzz fuzz-targets fuzz-run-open-step

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
fuzz-run-open-step: $(FUZZ_DIR)/fuzz-open-step $(FUZZ_DIR)/damage $(BUILD)/romkit
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
	$(BUILD)/romkit build tests/fuzz/seed_lifted.json -o $(FUZZ_DIR)/seedl.rombin --quiet
	rm -rf $(FUZZ_DIR)/damaged $(FUZZ_DIR)/damaged64 $(FUZZ_DIR)/damagedk $(FUZZ_DIR)/damagedb $(FUZZ_DIR)/damageds \
	    $(FUZZ_DIR)/damagedp $(FUZZ_DIR)/damageda $(FUZZ_DIR)/damagedc $(FUZZ_DIR)/damagedx $(FUZZ_DIR)/damagedl
	$(FUZZ_DIR)/damage $(FUZZ_DIR)/seed.rombin $(FUZZ_DIR)/damaged >/dev/null
	$(FUZZ_DIR)/damage $(FUZZ_DIR)/seed64.rombin $(FUZZ_DIR)/damaged64 >/dev/null
	$(FUZZ_DIR)/damage $(FUZZ_DIR)/seedk.rombin $(FUZZ_DIR)/damagedk >/dev/null
	$(FUZZ_DIR)/damage $(FUZZ_DIR)/seedb.rombin $(FUZZ_DIR)/damagedb >/dev/null
	$(FUZZ_DIR)/damage $(FUZZ_DIR)/seeds.rombin $(FUZZ_DIR)/damageds >/dev/null
	$(FUZZ_DIR)/damage $(FUZZ_DIR)/seedp.rombin $(FUZZ_DIR)/damagedp >/dev/null
	$(FUZZ_DIR)/damage $(FUZZ_DIR)/seeda.rombin $(FUZZ_DIR)/damageda >/dev/null
	$(FUZZ_DIR)/damage $(FUZZ_DIR)/seedc.rombin $(FUZZ_DIR)/damagedc >/dev/null
	$(FUZZ_DIR)/damage $(FUZZ_DIR)/seedx.rombin $(FUZZ_DIR)/damagedx >/dev/null
	$(FUZZ_DIR)/damage $(FUZZ_DIR)/seedl.rombin $(FUZZ_DIR)/damagedl >/dev/null
	cp $(FUZZ_DIR)/seed.rombin $(FUZZ_DIR)/seed64.rombin $(FUZZ_DIR)/seedk.rombin $(FUZZ_DIR)/seedb.rombin \
	    $(FUZZ_DIR)/seeds.rombin $(FUZZ_DIR)/seedp.rombin $(FUZZ_DIR)/seeda.rombin $(FUZZ_DIR)/seedc.rombin $(FUZZ_DIR)/seedx.rombin \
	    $(FUZZ_DIR)/seedl.rombin $(FUZZ_DIR)/corpus/
	for d in damaged damaged64 damagedk damagedb damageds damagedp damageda damagedc damagedx damagedl; do for k in bad good; do for f in $(FUZZ_DIR)/$$d/$$k/*; do \
	    cp "$$f" "$(FUZZ_DIR)/corpus/$$d-$$k-$$(basename "$$f")"; done; done; done
	max=$$(wc -c <$(FUZZ_DIR)/seed64.rombin); a=$$(wc -c <$(FUZZ_DIR)/seed.rombin); \
	[ "$$a" -gt "$$max" ] && max=$$a; \
	$(FUZZ_DIR)/fuzz-open-step -max_total_time=$(FUZZ_SECONDS) -rss_limit_mb=2048 -max_len=$$((2 * max)) \
	    -timeout=20 -print_final_stats=1 -artifact_prefix=$(FUZZ_DIR)/crashes/ $(FUZZ_DIR)/corpus \
	    tests/fuzz/regressions/open-step

# The readers of outside files. Each links only the stages its reader needs; the scene parser
# is the pipeline's, so it links the pipeline and all below it.
FUZZ_READERS := gmsh medit tetgen vtk obj off stl ply gltf splats points scene
FUZZ_PC_FLAGS := -std=c11 -D_DEFAULT_SOURCE -O1 -g -pthread -I. -Iprecompute -I/usr/include/suitesparse \
                 -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
fuzz_read_deps = $(if $(filter scene,$(1)),$(DEPS_pipeline),mesh util)
fuzz_lib_of = $(FUZZ_DIR)/lib/librk_$(1).a
$(FUZZ_DIR)/obj/%.o: %.c
	@mkdir -p $(dir $@)
	$(FUZZ_CC) $(FUZZ_PC_FLAGS) $(FUZZ_FLAGS) -MMD -MP -c $< -o $@
define fuzz_stage_lib
$(call fuzz_lib_of,$(1)): $(patsubst %.c,$(FUZZ_DIR)/obj/%.o,$(call src_of,$(1)))
	@mkdir -p $$(dir $$@)
	rm -f $$@ && ar rcs $$@ $$^
endef
$(foreach s,$(STAGES),$(eval $(call fuzz_stage_lib,$(s))))
define fuzz_reader
$(FUZZ_DIR)/fuzz-read-$(1): tests/fuzz/fuzz_read.c $(foreach s,$(call fuzz_read_deps,$(1)),$(call fuzz_lib_of,$(s)))
	$(FUZZ_CC) $(FUZZ_PC_FLAGS) -fsanitize=fuzzer $(FUZZ_FLAGS) -DFUZZ_READ_$(shell echo $(1) | tr a-z A-Z) -o $$@ $$< \
	    $(foreach s,$(call fuzz_read_deps,$(1)),$(call fuzz_lib_of,$(s))) $(LDLIBS)
.PHONY: fuzz-run-$(1)
fuzz-run-$(1): $(FUZZ_DIR)/fuzz-read-$(1)
	@mkdir -p $(FUZZ_DIR)/corpus-$(1) $(FUZZ_DIR)/crashes
	$(FUZZ_DIR)/fuzz-read-$(1) -max_total_time=$(FUZZ_SECONDS) -rss_limit_mb=2048 -max_len=65536 -timeout=20 \
	    -print_final_stats=1 -artifact_prefix=$(FUZZ_DIR)/crashes/$(1)- $(FUZZ_DIR)/corpus-$(1) tests/fuzz/seeds/$(1) \
	    $(wildcard tests/fuzz/regressions/$(1))
endef
$(foreach r,$(FUZZ_READERS),$(eval $(call fuzz_reader,$(r))))

fuzz-targets: $(FUZZ_DIR)/fuzz-open-step $(FUZZ_DIR)/replay-san $(foreach r,$(FUZZ_READERS),$(FUZZ_DIR)/fuzz-read-$(r))
fuzz: fuzz-run-open-step $(foreach r,$(FUZZ_READERS),fuzz-run-$(r))
-include $(shell find $(FUZZ_DIR)/obj -name '*.d' 2>/dev/null)

.DEFAULT_GOAL := $(fuzz_saved_goal)

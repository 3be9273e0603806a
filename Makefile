# romkit build. Each precompute stage is its own static library so a test links only
# the stages it needs (tests/unit/test_<stage>_*.c links util..<stage>).
CC       ?= cc
BUILD    ?= build
OPT      ?= -O2
SANFLAGS ?=
# Warnings are errors in CI and make test (WERROR=1, set by the test targets and .ci/run), not in a
# user's plain make: another compiler's new warning must not stop a build of working code.
WERROR   ?=
WERR     := $(if $(filter 1,$(WERROR)),-Werror,)
WARN     := -Wall -Wextra $(WERR) -Wshadow -Wno-unused-parameter -Wno-format-truncation
CFLAGS_PC := -std=c11 -D_DEFAULT_SOURCE $(OPT) -g $(WARN) $(SANFLAGS) -pthread \
             -I. -Iprecompute -I/usr/include/suitesparse
# -lgomp: precompute/util/threads.c, the one place that sets thread counts, keeps CHOLMOD's OpenMP
# regions on one thread; romkit's own loops run on plain threads (-pthread).
# -lmeshoptimizer: precompute/cage simplifies surfaces into simulation cages (meshopt_simplify).
# -lpng: precompute/video reads the frames of filmed dot markers (and writes the test renderer's).
LDLIBS    := -lcholmod -larpack -llapacke -lopenblas -lmetis -lgomp -lz -lcjson -lmeshoptimizer -lpng -lm
LDFLAGS   := $(SANFLAGS) -pthread

# The runtime's version, read from romrt.h (ROMRT_VERSION_MAJOR/MINOR/PATCH): the shared library's
# file name and soname, the pkg-config files.
rt_version_part = $(shell sed -n 's/^\#define ROMRT_VERSION_$(1) \([0-9][0-9]*\)$$/\1/p' runtime/romrt.h)
ROMRT_SOMAJOR := $(call rt_version_part,MAJOR)
ROMRT_VERSION := $(ROMRT_SOMAJOR).$(call rt_version_part,MINOR).$(call rt_version_part,PATCH)

# Stages and what each links against (itself first, then what it uses); data flows one way.
STAGES := util video mesh physics fem contact cage solver fom adaptive grassmann basis cubature neural rom koopman formats asset pipeline motions compare plan export
DEPS_util    := util
# Dot markers in frames: images, dots, pyramidal Lucas-Kanade, cameras, the lift onto a surface.
DEPS_video   := video util
DEPS_mesh    := mesh util
DEPS_physics := physics
DEPS_fem     := fem physics mesh util
DEPS_contact := contact fem physics mesh util
# Simulation cages around detailed surfaces, and points embedded in them (exact predicates of contact).
DEPS_cage    := cage contact fem physics mesh util
DEPS_solver  := solver physics util
DEPS_fom     := fom solver contact fem physics mesh util
DEPS_adaptive := adaptive fom solver contact fem physics mesh util
DEPS_grassmann := grassmann neural fom solver contact fem physics mesh util
DEPS_basis   := basis fem physics mesh util
DEPS_cubature := cubature fem physics mesh util
# Dense MLPs (the CROM encoder and decoder of the adaptive linear ROM): BLAS and util only.
DEPS_neural  := neural util
DEPS_rom     := rom cubature fom solver contact fem physics mesh util
DEPS_koopman := koopman formats neural cubature fem physics mesh util
DEPS_formats := formats util
DEPS_asset   := asset koopman formats rom grassmann neural cubature fom solver contact fem physics mesh util
# The scene parsed once and the whole-scene orchestration: every stage below it.
DEPS_pipeline := pipeline asset koopman formats rom cubature basis adaptive grassmann fom solver cage contact fem physics mesh neural video util
DEPS_compare := compare $(DEPS_pipeline)
# A scene entry's bake as a job graph (romkit plan): Makefile, Slurm scripts.
DEPS_plan    := plan $(DEPS_pipeline)
# Training scenes around a scene's object (romkit motions): the scene parsed and built.
DEPS_motions := motions $(DEPS_pipeline)
# An asset's shown vertices as glTF (romkit export): the container's rows, the skinning rows of basis.
DEPS_export  := export basis formats fem physics mesh util
DEPS_runtime := $(DEPS_pipeline)
# The command line and the benches link every stage.
DEPS_tools   := export plan motions $(DEPS_compare)
src_of  = $(if $(filter physics formats,$(1)),$(wildcard $(1)/*.c),$(wildcard precompute/$(1)/*.c))
lib_of  = $(BUILD)/lib/librk_$(1).a
libs_of = $(foreach s,$(DEPS_$(1)),$(call lib_of,$(s)))

ALL_LIBS := $(foreach s,$(STAGES),$(call lib_of,$(s)))
TOOL_SRC := $(wildcard tools/*.c)
# The most downstream stage: the command line links it and all it uses.
TOOL_STAGE := tools
TEST_SRC := $(wildcard tests/unit/test_*.c)
# The runtime tests that also run against the double runtime, as <name>_double.
TEST_DOUBLE := test_runtime_engine test_runtime_lifted test_runtime_obstacles test_runtime_mesh_collider test_runtime_objects test_runtime_object_contact test_runtime_parity test_runtime_alrom test_runtime_alrom_growth test_runtime_alrom_cadence test_runtime_koopman test_runtime_colliders test_runtime_newton_modes test_runtime_skinning test_runtime_point_gradients test_runtime_incline test_runtime_cloud_mesh test_runtime_shape_colliders
TEST_BIN := $(patsubst tests/unit/%.c,$(BUILD)/tests/%,$(TEST_SRC)) $(patsubst %,$(BUILD)/tests/%_double,$(TEST_DOUBLE))

.PHONY: all test test-unit test-sanitize bench bench-reference paper-table demo clean deps deps-build deps-test deps-web deps-bench
all: $(BUILD)/romkit $(BUILD)/romkit-double $(TEST_BIN) $(BUILD)/embed $(BUILD)/embed_cpp $(BUILD)/readme_example $(BUILD)/jsonq $(BUILD)/render_dots \
     $(BUILD)/lib/libromrt.so.$(ROMRT_VERSION) $(BUILD)/lib/libromrt_double.so.$(ROMRT_VERSION) $(BUILD)/rt_push

$(BUILD)/obj/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_PC) -MMD -MP -c $< -o $@
# The element kernels (physics/ in double) at -O3, as the runtime builds them: the full-order
# element Hessians on the 15k-tet beam 1.7 -> 1.45 us each (one thread, bench in the commit). The
# same bits: no FMA at the baseline x86-64 ISA and no reassociation without -ffast-math. A
# sanitizer build (OPT=-O1) keeps its own level.
$(BUILD)/obj/physics/%.o: CFLAGS_PC += $(if $(filter -O2,$(OPT)),-O3,)

define stage_lib
$(call lib_of,$(1)): $(patsubst %.c,$(BUILD)/obj/%.o,$(call src_of,$(1)))
	@mkdir -p $$(dir $$@)
	rm -f $$@ && ar rcs $$@ $$^
endef
$(foreach s,$(STAGES),$(eval $(call stage_lib,$(s))))

# The runtime: C99 with only libm, built for float (RT_LIB, what romkit run uses) and for
# double (RT_LIB_DOUBLE); formats/rombin_read.c and the physics are compiled into it.
RT_SRC     := $(wildcard runtime/*.c) formats/rombin_read.c
# The desktop runtime libraries step assets up to r = RT_MAX_R (an RKPM skinning basis of m = 16
# weights has 204 coordinates); an app compiling the sources itself picks its own ROMRT_MAX_R.
RT_MAX_R   ?= $(shell sed -n 's/^\#define ROMRT_MAX_R \([0-9][0-9]*\)$$/\1/p' runtime/romrt_impl.h)
# -O3: at -O2 gcc 12 leaves the r x r loops of the Newton Hessian scalar (2.6x slower at r = 204).
# A sanitizer build (OPT=-O1) keeps its own level.
RT_OPT     := $(if $(filter -O2,$(OPT)),-O3,$(OPT))
# The desktop libraries are portable by default: baseline x86-64 (SSE2), so an installed libromrt
# runs on any x86-64 CPU. NATIVE=1 opts in to the vector units of the machine that builds them where
# it has AVX2 and FMA: the element kernels then run 8 float lanes with fused multiply-adds instead
# of SSE2's 4 (bench/bench_speed.sh measures both).
# Such a library dies with an illegal instruction on a CPU without them: keep it on that machine.
# tests/integration/portable_runtime.sh checks the default build has no AVX or FMA instruction.
# The Cortex-M, WebAssembly and fuzz builds take their own flags.
NATIVE     ?=
RT_ARCH    ?= $(if $(filter 1,$(NATIVE)),$(shell grep -qw avx2 /proc/cpuinfo 2>/dev/null && grep -qw fma /proc/cpuinfo && echo -mavx2 -mfma -ffp-contract=fast),)
RT_CFLAGS  := -std=c99 -pedantic -Wall -Wextra $(WERR) -Wshadow $(RT_OPT) $(RT_ARCH) -g $(SANFLAGS) -I. -DROMRT_MAX_R=$(RT_MAX_R)
RT_LIB        := $(BUILD)/lib/libromrt.a
RT_LIB_DOUBLE := $(BUILD)/lib/libromrt_double.a
# The runtime's objects depend on the flags they were built with: this file changes (and they are
# rebuilt) only when RT_CFLAGS does, but for -Werror, which changes no object. So a tree built with
# NATIVE=1 and then without it ships no stale AVX object.
RT_FLAGS_STAMP := $(BUILD)/rt/cflags
RT_STAMPED     := $(filter-out -Werror,$(RT_CFLAGS))
$(RT_FLAGS_STAMP): FORCE
	@mkdir -p $(dir $@)
	@echo '$(RT_STAMPED)' | cmp -s - $@ || echo '$(RT_STAMPED)' >$@
.PHONY: FORCE
FORCE:
$(BUILD)/rt/float/%.o: %.c $(RT_FLAGS_STAMP)
	@mkdir -p $(dir $@)
	$(CC) $(RT_CFLAGS) -MMD -MP -c $< -o $@
$(BUILD)/rt/double/%.o: %.c $(RT_FLAGS_STAMP)
	@mkdir -p $(dir $@)
	$(CC) $(RT_CFLAGS) -DROMRT_DOUBLE -MMD -MP -c $< -o $@
# The link names of the functions romrt.h declares, one a line, for a precision (romrt_f32_* for
# float, romrt_f64_* for double: the header maps romrt_X to them): what the libraries export.
$(BUILD)/rt/float/romrt.syms: runtime/romrt.h
	@mkdir -p $(dir $@)
	$(CC) -E -P -x c runtime/romrt.h | grep -o 'romrt_f32_[a-z0-9_]*' | sort -u >$@.tmp && mv $@.tmp $@
$(BUILD)/rt/double/romrt.syms: runtime/romrt.h
	@mkdir -p $(dir $@)
	$(CC) -E -P -x c -DROMRT_DOUBLE runtime/romrt.h | grep -o 'romrt_f64_[a-z0-9_]*' | sort -u >$@.tmp && mv $@.tmp $@
# The static libraries export romrt.h's functions and nothing else: the objects are linked into one
# (ld -r) whose other globals (rt_*, rombin_*, romrt_phys_*) objcopy makes local, so an app's own
# rt_dot or rombin_open never meets the runtime's. $(call rt_archive,PRECISION) $@ from $^.
rt_archive = rm -f $@ $(BUILD)/rt/$(1)/romrt_all.o && $(LD) -r -o $(BUILD)/rt/$(1)/romrt_all.o $(filter %.o,$^) && \
             $(OBJCOPY) --keep-global-symbols=$(BUILD)/rt/$(1)/romrt.syms $(BUILD)/rt/$(1)/romrt_all.o && \
             ar rcs $@ $(BUILD)/rt/$(1)/romrt_all.o
OBJCOPY ?= objcopy
$(RT_LIB): $(patsubst %.c,$(BUILD)/rt/float/%.o,$(RT_SRC)) $(BUILD)/rt/float/romrt.syms
	@mkdir -p $(dir $@)
	$(call rt_archive,float)
$(RT_LIB_DOUBLE): $(patsubst %.c,$(BUILD)/rt/double/%.o,$(RT_SRC)) $(BUILD)/rt/double/romrt.syms
	@mkdir -p $(dir $@)
	$(call rt_archive,double)

$(BUILD)/romkit: $(patsubst %.c,$(BUILD)/obj/%.o,$(TOOL_SRC)) $(ALL_LIBS) $(RT_LIB)
	$(CC) $(LDFLAGS) -o $@ $(patsubst %.c,$(BUILD)/obj/%.o,$(TOOL_SRC)) $(call libs_of,$(TOOL_STAGE)) $(RT_LIB) $(LDLIBS)

# The same command line over the double runtime (romkit-double run steps an asset as an app built
# with ROMRT_DOUBLE would): models whose float32 rounding matters, compared in the same units.
$(BUILD)/obj-double/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_PC) -DROMRT_DOUBLE -MMD -MP -c $< -o $@
$(BUILD)/romkit-double: $(patsubst %.c,$(BUILD)/obj-double/%.o,$(TOOL_SRC)) $(ALL_LIBS) $(RT_LIB_DOUBLE)
	$(CC) $(LDFLAGS) -o $@ $(patsubst %.c,$(BUILD)/obj-double/%.o,$(TOOL_SRC)) $(call libs_of,$(TOOL_STAGE)) $(RT_LIB_DOUBLE) $(LDLIBS)


# examples/embed: an app that uses only romrt.h (#include "romrt.h", so it also builds against make install's copy), in C and in C++.
CXX ?= c++
$(BUILD)/embed: examples/embed/embed.c runtime/romrt.h $(RT_LIB)
	$(CC) -std=c99 -pedantic -Wall -Wextra $(WERR) $(OPT) $(SANFLAGS) -Iruntime -o $@ $< $(RT_LIB) -lm
$(BUILD)/embed_cpp: examples/embed/embed_cpp.cpp runtime/romrt.h $(RT_LIB)
	$(CXX) -std=c++11 -pedantic -Wall -Wextra $(WERR) $(OPT) $(SANFLAGS) -Iruntime -o $@ $< $(RT_LIB) -lm
# The README's embedding example, the same text as its code block (tests/integration/readme_example.sh).
$(BUILD)/readme_example: examples/embed/readme_example.c runtime/romrt.h $(RT_LIB)
	$(CC) -std=c99 -pedantic -Wall -Wextra $(WERR) $(OPT) $(SANFLAGS) -Iruntime -o $@ $< $(RT_LIB) -lm

# rt_push: the float runtime stepped with pushes, positions as raw float32 (the Python binding's
# test compares against it; tests/tools/rt_push.c).
$(BUILD)/rt_push: tests/tools/rt_push.c runtime/romrt.h $(RT_LIB)
	$(CC) -std=c99 -pedantic -Wall -Wextra $(WERR) $(OPT) $(SANFLAGS) -Iruntime -o $@ $< $(RT_LIB) -lm

# render_dots: cli_track.sh's synthetic video of dot markers on a full-order run (tests/tools/render_dots.c).
$(BUILD)/render_dots: tests/tools/render_dots.c $(call libs_of,video) $(call lib_of,mesh)
	$(CC) $(CFLAGS_PC) -o $@ $< $(call lib_of,mesh) $(call libs_of,video) $(LDLIBS)

# jsonq: the integration tests read JSON reports through it (tests/tools/jsonq.c).
$(BUILD)/jsonq: tests/tools/jsonq.c
	$(CC) $(CFLAGS_PC) -o $@ $< -lcjson -lm

# tests/unit/test_<stage>_<name>.c links the libraries of <stage>.
test_stage = $(word 2,$(subst _, ,$(notdir $(1))))
.SECONDEXPANSION:
# The runtime tests link the float runtime; <name>_double is the same source in double.
$(BUILD)/tests/%_double: tests/unit/%.c tests/testlib.h $(call libs_of,runtime) $(RT_LIB_DOUBLE)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_PC) -DROMRT_DOUBLE -Itests -MMD -MP -MF $@.d -o $@ $< $(call libs_of,runtime) $(RT_LIB_DOUBLE) $(LDLIBS)
# A test that checks its stage against a stage above it (an independent reference) names that one:
# TEST_ALSO_<test> stages are linked before its own.
TEST_ALSO_test_basis_derivatives := fom solver contact
TEST_ALSO_test_basis_pod := fom solver contact
TEST_ALSO_test_adaptive_subspace := basis
# the embedded contact surface's vertices located in the bodies by the cage's embedding
TEST_ALSO_test_fom_contact_embedded := cage
TEST_ALSO_test_grassmann_alrom := basis
# The chain's default fit is baked and jumped in the runtime.
TEST_ALSO_test_koopman_dmd := asset formats
# the neural DMD tests build their beams with the pipeline (scenes from JSON, full-order runs)
TEST_ALSO_test_koopman_neural := $(DEPS_pipeline)
TEST_ALSO_test_koopman_shape := $(DEPS_pipeline)
TEST_ALSO_test_koopman_neural_io := $(DEPS_pipeline)
TEST_ALSO_test_koopman_neural_sample := $(DEPS_pipeline)
TEST_ALSO_test_koopman_xres := $(DEPS_pipeline)
test_libs = $(foreach s,$(TEST_ALSO_$(1)),$(call lib_of,$(s))) $(call libs_of,$(call test_stage,$(1)))
$(BUILD)/tests/%: tests/unit/%.c tests/testlib.h $$(call test_libs,$$*) $(RT_LIB)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_PC) -Itests -MMD -MP -MF $@.d -o $@ $< $(call test_libs,$*) $(RT_LIB) $(LDLIBS)

$(BUILD)/bench_%: bench/bench_%.c bench/bench_cases.h $(call libs_of,$(TOOL_STAGE))
	$(CC) $(CFLAGS_PC) -o $@ $< $(call libs_of,$(TOOL_STAGE)) $(LDLIBS)
$(BUILD)/bench_rom: bench/bench_rom_model.h
# The runtime bench also links the float runtime (as the runtime tests do).
$(BUILD)/bench_runtime: bench/bench_runtime.c bench/bench_cases.h bench/bench_rom_model.h $(call libs_of,$(TOOL_STAGE)) $(RT_LIB)
	$(CC) $(CFLAGS_PC) -o $@ $< $(call libs_of,$(TOOL_STAGE)) $(RT_LIB) $(LDLIBS)

# The Koopman bench: DMD fit and bake seconds, and the runtime's step/jump, on a Koopman asset.
$(BUILD)/bench_koopman: bench/bench_koopman.c bench/bench_cases.h $(call libs_of,$(TOOL_STAGE)) $(RT_LIB)
	$(CC) $(CFLAGS_PC) -o $@ $< $(call libs_of,$(TOOL_STAGE)) $(RT_LIB) $(LDLIBS)

# Experiments whose product is a table (issue 31's tiers): bench/ablation_*.c, run by make bench.
$(BUILD)/ablation_%: bench/ablation_%.c $(call libs_of,$(TOOL_STAGE))
	$(CC) $(CFLAGS_PC) -o $@ $< $(call libs_of,$(TOOL_STAGE)) $(LDLIBS)

# The converged Newton mode with a fresh or a kept Newton matrix, and the default (issue 31), in
# float and in double (for float64 assets).
$(BUILD)/bench_newton_modes: bench/bench_newton_modes.c bench/bench_read.h $(call libs_of,$(TOOL_STAGE)) $(RT_LIB)
	$(CC) $(CFLAGS_PC) -o $@ $< $(call libs_of,$(TOOL_STAGE)) $(RT_LIB) $(LDLIBS)
$(BUILD)/bench_newton_modes_double: bench/bench_newton_modes.c bench/bench_read.h $(call libs_of,$(TOOL_STAGE)) $(RT_LIB_DOUBLE)
	$(CC) $(CFLAGS_PC) -DROMRT_DOUBLE -o $@ $< $(call libs_of,$(TOOL_STAGE)) $(RT_LIB_DOUBLE) $(LDLIBS)

# The pour's step split into broad phase, narrow phase and Newton (bench/pour.sh): the runtime's
# sources again with -DROMRT_PROFILE, whose hooks the bench times; the shipped libraries have none.
$(BUILD)/rt/prof-float/%.o: %.c $(RT_FLAGS_STAMP)
	@mkdir -p $(dir $@)
	$(CC) $(RT_CFLAGS) -DROMRT_PROFILE -MMD -MP -c $< -o $@
$(BUILD)/rt/prof-double/%.o: %.c $(RT_FLAGS_STAMP)
	@mkdir -p $(dir $@)
	$(CC) $(RT_CFLAGS) -DROMRT_DOUBLE -DROMRT_PROFILE -MMD -MP -c $< -o $@
$(BUILD)/bench_pour: bench/bench_pour.c bench/prof_phases.h bench/bench_read.h $(patsubst %.c,$(BUILD)/rt/prof-float/%.o,$(RT_SRC))
	$(CC) $(CFLAGS_PC) -o $@ $< $(filter %.o,$^) -lm
$(BUILD)/bench_pour_double: bench/bench_pour.c bench/prof_phases.h bench/bench_read.h $(patsubst %.c,$(BUILD)/rt/prof-double/%.o,$(RT_SRC))
	$(CC) $(CFLAGS_PC) -DROMRT_DOUBLE -o $@ $< $(filter %.o,$^) -lm

# An adaptive linear ROM's step split into encoder, basis, rows, terms and Newton
# (bench_alrom_runtime.sh), on the profiled runtime objects as bench_pour.
$(BUILD)/bench_alrom_split: bench/bench_alrom_split.c bench/prof_phases.h bench/bench_read.h $(patsubst %.c,$(BUILD)/rt/prof-float/%.o,$(RT_SRC))
	$(CC) $(CFLAGS_PC) -o $@ $< $(filter %.o,$^) -lm

# Several baked assets' runtime step cost, interleaved in one process (bench_alrom_runtime.sh).
$(BUILD)/bench_assets: bench/bench_assets.c bench/bench_read.h $(call libs_of,$(TOOL_STAGE)) $(RT_LIB)
	$(CC) $(CFLAGS_PC) -o $@ $< $(call libs_of,$(TOOL_STAGE)) $(RT_LIB) $(LDLIBS)

bench: deps-bench all $(BUILD)/bench_assets $(BUILD)/bench_newton_modes $(BUILD)/bench_newton_modes_double $(BUILD)/ablation_koopman_momentum $(BUILD)/bench_physics $(BUILD)/bench_fom $(BUILD)/bench_contact $(BUILD)/bench_basis $(BUILD)/bench_rom $(BUILD)/bench_runtime $(BUILD)/bench_koopman $(BUILD)/bench_scale $(BUILD)/bench_adaptive \
       $(BUILD)/bench_pour $(BUILD)/bench_pour_double $(BUILD)/bench_alrom_split
	@mkdir -p bench/results
	$(BUILD)/bench_physics tests/data/meshes bench/results
	$(BUILD)/bench_fom tests/data/meshes bench/results
	$(BUILD)/bench_contact tests/data/meshes bench/results
	$(BUILD)/bench_basis tests/data/meshes bench/results
	$(BUILD)/bench_rom tests/data/meshes bench/results
	$(BUILD)/bench_runtime tests/data/meshes bench/results
	$(BUILD)/bench_koopman tests/data/meshes bench/results
	BUILD=$(BUILD) sh bench/bench_speed.sh tests/data/meshes bench/results
	BUILD=$(BUILD) sh bench/newton_modes.sh tests/data/meshes bench/results
	$(BUILD)/ablation_koopman_momentum bench/results
	$(BUILD)/bench_scale tests/data/meshes bench/results
	$(BUILD)/bench_adaptive tests/data/meshes bench/results
	BUILD=$(BUILD) sh bench/bench_alrom.sh tests/data/meshes bench/results
	BUILD=$(BUILD) sh bench/alrom_table3.sh tests/data/meshes bench/results
	BUILD=$(BUILD) sh bench/bench_alrom_runtime.sh tests/data/meshes bench/results
	BUILD=$(BUILD) sh bench/bench_alrom_cadence.sh tests/data/meshes bench/results
	BUILD=$(BUILD) sh bench/volume_step.sh bench/results
	BUILD=$(BUILD) sh bench/pour.sh
	BUILD=$(BUILD) sh bench/moving_obstacles.sh
	BUILD=$(BUILD) sh bench/adaptive_moving.sh
	BUILD=$(BUILD) sh bench/adaptive_threads.sh
	BUILD=$(BUILD) sh bench/adaptive_defaults.sh
	BUILD=$(BUILD) sh bench/adaptive_picture.sh
	BUILD=$(BUILD) sh bench/cage.sh
	BUILD=$(BUILD) sh bench/shape_family.sh
	@$(MAKE) --no-print-directory bench-plots
	@$(MAKE) --no-print-directory results-tables

# docs/results/*.md: markdown tables written from bench/results by bench/tables.py (python3, standard
# library only). make bench, paper-table and bench-reference end with it; runs no benchmark.
.PHONY: results-tables
results-tables:
	python3 bench/tables.py bench/results docs/results

# The charts of bench/results/*.csv (bench/plots/*.gp, gnuplot): pareto.png (error against s/step),
# step_time_vs_tets.png, koopman_jump.png, adaptive.png, alrom.png. Draws from the CSVs already there; runs no benchmark.
.PHONY: bench-plots
bench-plots:
	@if command -v gnuplot >/dev/null 2>&1; then \
	    for p in pareto step_time_vs_tets koopman_jump adaptive alrom; do \
	        gnuplot bench/plots/$$p.gp || exit 1; echo "bench/results/$$p.png"; \
	    done; \
	else echo "bench-plots: gnuplot not found; no charts drawn (the CSVs are in bench/results)"; fi

# The freeform paper's Table 1 beam tests, every method beside the paper's numbers: the bend against
# quadratic tets on 15,360 tets (converged to about 4e-7: docs/methods.md), the twists against quadratic
# tets on their own 1,920 tets (the 720-degree one took 705 s on one thread at load 6-13, where its
# 122,880-tet P1 reference took 1,600-2,660 s; the whole target was about 1.5 hours on 2 cores before).
paper-table: deps-build $(BUILD)/romkit
	@mkdir -p bench/results
	$(BUILD)/romkit compare examples/scenes/beam_bend_table.json --quiet --report bench/results/paper_table_bend.json | tee bench/results/paper_table_bend.txt
	$(BUILD)/romkit compare examples/scenes/beam_twist_table.json --quiet --report bench/results/paper_table_twist.json | tee bench/results/paper_table_twist.txt
	$(BUILD)/romkit compare examples/scenes/beam_twist360_table_lifted.json --quiet --report bench/results/paper_table_twist360_lifted.json | tee bench/results/paper_table_twist360_lifted.txt
	$(BUILD)/romkit compare examples/scenes/beam_twist360_table.json --quiet --report bench/results/paper_table_twist360.json | tee bench/results/paper_table_twist360.txt
	for s in bend twist360; do $(BUILD)/romkit compare examples/scenes/beam_$${s}_table_pin1e3.json --quiet \
	    --report bench/results/paper_table_$${s}_pin1e3.json | tee bench/results/paper_table_$${s}_pin1e3.txt; done
	for s in armadillo_fix_side armadillo_hang armadillo_pull layered_sphere; do \
	    $(BUILD)/romkit compare examples/scenes/$$s.json --quiet --report bench/results/$$s.json | tee bench/results/$$s.txt; done
	@$(MAKE) --no-print-directory results-tables

# How fine the beam's full-order reference must be for Table 1 (bench/beam_reference.sh): full-order
# runs of the table scenes on 1,920 to 983,040 tets, the normalized MSE between levels; and the
# beam's converged static sag by quadratic tets (bench/bench_p2_beam.c: 4 to 13 minutes and 7 GB);
# how converged the bend's dynamic quadratic-tet reference is (bench/p2_reference.sh, 40 minutes).
# The neural DMD trained and evaluated at 2.4k, 10k and 106k vertices (bench/neural_resolution.sh,
# issue 35: its 106k full-order run alone is about 8 minutes of CPU and 3.4 GB).
# The beam's static sag by volume treatment and pressure space, m = 6 to 32, mesh-free and mesh
# skinning (bench/bench_volume_sag.c, issue 37: about 15 minutes on a loaded 2-core machine).
# Not part of make bench or make test: about an hour on 2 cores, more with the 983k-tet levels.
bench-reference: deps-bench all $(BUILD)/bench_reference $(BUILD)/bench_p2_beam $(BUILD)/bench_volume_sag
	$(BUILD)/bench_p2_beam 2
	$(BUILD)/bench_volume_sag
	BUILD=$(BUILD) sh bench/p2_reference.sh
	BUILD=$(BUILD) sh bench/beam_reference.sh
	NEURAL_RES_100K=1 BUILD=$(BUILD) sh bench/neural_resolution.sh
	@$(MAKE) --no-print-directory results-tables

demo: deps-build all
	@sh tools/demo.sh $(BUILD)

# What each goal needs (tools/install-deps.sh, by group): as root it installs what is missing; as
# another user a missing library is an error and a missing test tool is reported (its tests skip).
deps:
	@sh tools/install-deps.sh all
deps-build deps-test deps-web deps-bench:
	@sh tools/install-deps.sh $(patsubst deps-%,%,$@)

# make test: the unit and validation tiers of tests/unit (tests/tiers) and tests/integration;
# make test-unit: the quick tier alone, tests/unit's unit tests (seconds each, deterministic).
# TEST_JOBS tests at once (tests/run.sh's JOBS: each gets the CPUs / TEST_JOBS threads).
TEST_JOBS ?= $(shell nproc 2>/dev/null || echo 1)
test: deps-test
	$(MAKE) WERROR=1 all
	@BUILD=$(BUILD) WERROR=1 TIERS="unit validation" JOBS=$(TEST_JOBS) sh tests/run.sh

test-unit: deps-test
	$(MAKE) WERROR=1 all
	@BUILD=$(BUILD) WERROR=1 TIERS=unit SUITES=unit JOBS=$(TEST_JOBS) sh tests/run.sh

# The test scripts' own make calls (make mcu, the fuzz tools) see the same flags through the
# environment, so they never relink sanitized objects without the sanitizer.
SAN := -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all
test-sanitize: deps-test
	$(MAKE) BUILD=build-san OPT=-O1 SANFLAGS="$(SAN)" WERROR=1 all
	@BUILD=build-san WERROR=1 OPT=-O1 SANFLAGS="$(SAN)" ROMKIT_SANITIZE=1 JOBS=$(TEST_JOBS) sh tests/run.sh

clean:
	rm -rf build build-san

# make install: the romkit command, the float runtime as a static and a shared library
# (libromrt.so.$(ROMRT_VERSION), soname libromrt.so.$(ROMRT_SOMAJOR), exporting only romrt.h's
# functions), the double runtime as a static library, romrt.h, and pkg-config files romrt.pc
# (float) and romrt-double.pc (-DROMRT_DOUBLE, static). PREFIX and DESTDIR are honoured:
# make install DESTDIR=/tmp/stage PREFIX=/opt/romkit. make uninstall removes the same files.
PREFIX       ?= /usr/local
DESTDIR      ?=
BINDIR       ?= $(PREFIX)/bin
LIBDIR       ?= $(PREFIX)/lib
INCLUDEDIR   ?= $(PREFIX)/include
PKGCONFIGDIR ?= $(LIBDIR)/pkgconfig
INSTALL      ?= install
RT_SO  := $(BUILD)/lib/libromrt.so.$(ROMRT_VERSION)
RT_MAP := $(BUILD)/rt/pic/romrt.map
$(BUILD)/rt/pic/%.o: %.c $(RT_FLAGS_STAMP)
	@mkdir -p $(dir $@)
	$(CC) $(RT_CFLAGS) -fPIC -MMD -MP -c $< -o $@
# The shared library exports what romrt.h declares and nothing else (no rt_*, rombin_*, romrt_phys_*).
$(BUILD)/rt/%/romrt.map: $(BUILD)/rt/%/romrt.syms
	{ echo 'ROMRT_$(ROMRT_SOMAJOR) {'; echo '  global:'; sed 's/.*/    &;/' $<; echo '  local: *;'; echo '};'; } >$@.tmp && mv $@.tmp $@
$(BUILD)/rt/pic/romrt.syms: $(BUILD)/rt/float/romrt.syms
	@mkdir -p $(dir $@)
	cp $< $@
$(RT_SO): $(patsubst %.c,$(BUILD)/rt/pic/%.o,$(RT_SRC)) $(RT_MAP)
	@mkdir -p $(dir $@)
	$(CC) -shared $(LDFLAGS) -Wl,-soname,libromrt.so.$(ROMRT_SOMAJOR) -Wl,--version-script=$(RT_MAP) -o $@ $(filter %.o,$^) -lm
# The double runtime as a shared library too, for bindings/python (romrt.Model(..., double=True));
# not installed (make install's double runtime is the static library).
$(BUILD)/rt/pic-double/%.o: %.c $(RT_FLAGS_STAMP)
	@mkdir -p $(dir $@)
	$(CC) $(RT_CFLAGS) -DROMRT_DOUBLE -fPIC -MMD -MP -c $< -o $@
$(BUILD)/rt/pic-double/romrt.syms: $(BUILD)/rt/double/romrt.syms
	@mkdir -p $(dir $@)
	cp $< $@
$(BUILD)/lib/libromrt_double.so.$(ROMRT_VERSION): $(patsubst %.c,$(BUILD)/rt/pic-double/%.o,$(RT_SRC)) $(BUILD)/rt/pic-double/romrt.map
	@mkdir -p $(dir $@)
	$(CC) -shared $(LDFLAGS) -Wl,-soname,libromrt_double.so.$(ROMRT_SOMAJOR) -Wl,--version-script=$(filter %.map,$^) -o $@ $(filter %.o,$^) -lm
# romrt.pc from runtime/romrt.pc.in: $(call romrt_pc,NAME,LIB,EXTRA_CFLAGS,DESCRIPTION) > file
pc_rel = $(patsubst $(PREFIX)/%,$${prefix}/%,$(1))
romrt_pc = sed -e 's|@PREFIX@|$(PREFIX)|' -e 's|@LIBDIR@|$(call pc_rel,$(LIBDIR))|' -e 's|@INCLUDEDIR@|$(call pc_rel,$(INCLUDEDIR))|' \
               -e 's|@VERSION@|$(ROMRT_VERSION)|' -e 's|@NAME@|$(1)|' -e 's|@LIB@|$(2)|' -e 's|@CFLAGS@|$(3)|' -e 's|@DESCRIPTION@|$(4)|' runtime/romrt.pc.in
.PHONY: install uninstall
install: $(BUILD)/romkit $(RT_LIB) $(RT_LIB_DOUBLE) $(RT_SO) runtime/romrt.h runtime/romrt.pc.in
	$(INSTALL) -d "$(DESTDIR)$(BINDIR)" "$(DESTDIR)$(LIBDIR)" "$(DESTDIR)$(INCLUDEDIR)" "$(DESTDIR)$(PKGCONFIGDIR)"
	$(INSTALL) -m 755 $(BUILD)/romkit "$(DESTDIR)$(BINDIR)/romkit"
	$(INSTALL) -m 644 $(RT_LIB) $(RT_LIB_DOUBLE) "$(DESTDIR)$(LIBDIR)/"
	$(INSTALL) -m 755 $(RT_SO) "$(DESTDIR)$(LIBDIR)/"
	ln -sf libromrt.so.$(ROMRT_VERSION) "$(DESTDIR)$(LIBDIR)/libromrt.so.$(ROMRT_SOMAJOR)"
	ln -sf libromrt.so.$(ROMRT_SOMAJOR) "$(DESTDIR)$(LIBDIR)/libromrt.so"
	$(INSTALL) -m 644 runtime/romrt.h "$(DESTDIR)$(INCLUDEDIR)/romrt.h"
	$(call romrt_pc,romrt,romrt,,Float build (romrt_real is float); the double build is romrt-double.) >"$(DESTDIR)$(PKGCONFIGDIR)/romrt.pc"
	$(call romrt_pc,romrt-double,romrt_double, -DROMRT_DOUBLE,Double build (-DROMRT_DOUBLE: romrt_real is double); static library only.) >"$(DESTDIR)$(PKGCONFIGDIR)/romrt-double.pc"
	chmod 644 "$(DESTDIR)$(PKGCONFIGDIR)/romrt.pc" "$(DESTDIR)$(PKGCONFIGDIR)/romrt-double.pc"
uninstall:
	rm -f "$(DESTDIR)$(BINDIR)/romkit" "$(DESTDIR)$(INCLUDEDIR)/romrt.h" \
	      "$(DESTDIR)$(PKGCONFIGDIR)/romrt.pc" "$(DESTDIR)$(PKGCONFIGDIR)/romrt-double.pc" \
	      "$(DESTDIR)$(LIBDIR)/libromrt.a" "$(DESTDIR)$(LIBDIR)/libromrt_double.a" "$(DESTDIR)$(LIBDIR)/libromrt.so" \
	      "$(DESTDIR)$(LIBDIR)/libromrt.so.$(ROMRT_SOMAJOR)" "$(DESTDIR)$(LIBDIR)/libromrt.so.$(ROMRT_VERSION)"

-include $(shell find $(BUILD)/obj $(BUILD)/obj-double $(BUILD)/rt $(BUILD)/tests -name '*.d' 2>/dev/null)

# make mcu (Cortex-M4F under qemu), make fuzz, make web and make test-web: their own fragments.
include tests/mcu/mcu.mk
include tests/fuzz/fuzz.mk
include web/web.mk

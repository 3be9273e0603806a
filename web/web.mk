# make web: the runtime in WebAssembly (Debian's emscripten) and the page of web/ in $(BUILD)/web,
# with the demo's assets; make test-web drives that page in Debian's chromium (tests/web/). Neither
# is part of make test (a browser and the demo's bake are too slow for its budget).
WEB      := $(BUILD)/web
EMCC     ?= emcc
# Debian's emcc runs its JS optimizer under node with Debian's node-acorn (/usr/share/nodejs), where
# a node from elsewhere (NodeSource's) does not look. Debian's emscripten brings its own prebuilt,
# frozen library cache, which has every library this build links: EM_CACHE is left alone.
WEB_EMCC := NODE_PATH=/usr/share/nodejs $(EMCC)
# The float runtime with the desktop libraries' ROMRT_MAX_R (the demo's RKPM asset has r = 204).
# -msimd128: wasm's 4-lane SIMD, which clang auto-vectorizes the r x r loops into (every browser
# with WebAssembly SIMD, Chrome 91, Firefox 89, Safari 16.4).
WEB_CFLAGS := -std=c99 -pedantic -Wall -Wextra -Werror -Wshadow -O3 -msimd128 -I. -DROMRT_MAX_R=$(RT_MAX_R)
# The page's sources, copied as they are; three.js comes from web/node_modules (npm ci).
WEB_PAGE  := index.html main.js model.js view.js drag.js splats.js
WEB_THREE := three.module.js three.core.js
# The demo's assets (tools/demo.sh bakes them into $(BUILD)/demo) the page lists; the first opens.
WEB_DEMO  := rkpm koopman koopman_half_g

# Every function romrt.h declares is exported, by its link name (romrt_f32_*; romrt.syms).
$(WEB)/romrt.js: $(RT_SRC) $(wildcard runtime/*.h physics/*.h formats/*.h) $(BUILD)/rt/float/romrt.syms web/web.mk
	@mkdir -p $(dir $@)
	$(WEB_EMCC) $(WEB_CFLAGS) $(RT_SRC) -o $@ -sMODULARIZE=1 -sEXPORT_ES6=1 -sALLOW_MEMORY_GROWTH=1 \
	    -sEXPORTED_FUNCTIONS=$$(sed 's/^/_/' $(BUILD)/rt/float/romrt.syms | tr '\n' ,)_malloc,_free \
	    -sEXPORTED_RUNTIME_METHODS=HEAPU8,HEAP32,HEAPU32,HEAPF32,UTF8ToString

# npm ci from the lockfile; node_modules/.package-lock.json is what npm ci writes last.
web/node_modules/.package-lock.json: web/package.json web/package-lock.json
	npm ci --prefix web --no-audit --no-fund
$(WEB)/three/%.js: web/node_modules/.package-lock.json
	@mkdir -p $(dir $@)
	cp web/node_modules/three/build/$*.js $@
# OrbitControls, and GLTFLoader with the two addons it imports.
WEB_ADDONS := controls/OrbitControls.js loaders/GLTFLoader.js utils/BufferGeometryUtils.js utils/SkeletonUtils.js
$(WEB)/three/addons/%.js: web/node_modules/.package-lock.json
	@mkdir -p $(dir $@)
	cp web/node_modules/three/examples/jsm/$*.js $@

# @mkkellogg/gaussian-splats-3d (npm, pinned), which web/splats.js draws a point cloud's splats with.
$(WEB)/gaussian-splats-3d.module.js: web/node_modules/.package-lock.json
	@mkdir -p $(dir $@)
	cp web/node_modules/@mkkellogg/gaussian-splats-3d/build/gaussian-splats-3d.module.js $@
$(WEB)/%: web/%
	@mkdir -p $(dir $@)
	cp $< $@

# The demo's assets come from one make demo run (about 3 minutes, once); a rebuilt romkit does
# not bake them again (make demo does).
$(WEB_DEMO:%=$(BUILD)/demo/%.rombin) &: | $(BUILD)/romkit
	sh tools/demo.sh $(BUILD)
$(WEB)/%.rombin: $(BUILD)/demo/%.rombin
	@mkdir -p $(dir $@)
	cp $< $@
# A point cloud for the page's Gaussian splats: the example donut (45,624 splats of a 3DGS capture,
# RKPM skinning, mesh-free; about 15 s to bake, once: a rebuilt romkit does not bake it again).
$(WEB)/donut.rombin: examples/scenes/donut_splats.json tests/data/meshes/donut_3dgs.ply | $(BUILD)/romkit
	@mkdir -p $(dir $@)
	$(BUILD)/romkit build $< -o $@ --quiet
# One glTF export of the RKPM asset (romkit export: the shown surface, its r basis columns as morph
# targets, WEB_GLTF_STEPS runtime steps as the weights' animation), which the page opens with
# three.js's GLTFLoader (index.html?gltf=demo.glb, or the file picker). tests/web/page.sh expects
# these steps and this asset.
WEB_GLTF_STEPS := 20
$(WEB)/demo.glb: $(WEB)/rkpm.rombin $(BUILD)/romkit
	$(BUILD)/romkit export $(WEB)/rkpm.rombin --gltf $@ --steps $(WEB_GLTF_STEPS) --quiet
$(WEB)/assets.json: web/web.mk
	@mkdir -p $(dir $@)
	echo '[$(patsubst %,"%.rombin",$(WEB_DEMO)) "donut.rombin" "demo.glb"]' | sed 's/" "/", "/g' >$@

# deps first, on its own: it may install emscripten, chromium and the libraries romkit links.
.PHONY: web web-files web-test-files test-web
web: deps-web
	@$(MAKE) --no-print-directory web-files
	@echo "make web: the page is in $(WEB); serve it with"
	@echo "    python3 -m http.server -d $(WEB) 8000"
	@echo "and open http://localhost:8000/ (a browser will not run WebAssembly from file://)"
web-files: $(WEB)/romrt.js $(WEB_PAGE:%=$(WEB)/%) $(WEB_THREE:%=$(WEB)/three/%) \
           $(WEB_ADDONS:%=$(WEB)/three/addons/%) $(WEB_DEMO:%=$(WEB)/%.rombin) $(WEB)/assets.json \
           $(WEB)/demo.glb $(WEB)/gaussian-splats-3d.module.js $(WEB)/donut.rombin

# The page in headless chromium (tests/web/page.sh): ok/FAIL lines, the browser's and the native
# ms per step, and "N passed, N failed".
test-web: deps-web
	@$(MAKE) --no-print-directory web-test-files
	@BUILD=$(BUILD) SUITES=web sh tests/run.sh
web-test-files: web-files $(BUILD)/romkit $(BUILD)/jsonq
	@:

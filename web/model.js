// model.js: one .rombin asset stepped by the runtime compiled to WebAssembly (romrt.js, made by
// `make web` from runtime/ with emscripten). Direct calls to the exported C functions: the float
// build's link names, romrt_f32_* (romrt.h maps every romrt_NAME to them).
//
// The asset, the arena and the buffers live in the wasm heap and belong to this object; free()
// gives them back. Nothing in the runtime allocates, so the heap does not grow while a model
// steps and the views taken after each call stay valid until the next one.

export const KIND_REDUCED = 0;
export const KIND_KOOPMAN = 1;

// romrt_error in wasm32: status (a 4-byte enum), chunk[5], message[160]: 172 bytes.
const ERROR_BYTES = 176;
const ERROR_MESSAGE = 9;

// The bytes of chunk `id` (four ASCII letters) of a .rombin, stored uncompressed; null if absent
// (formats/rombin.h: a 64-byte header, the chunk count at 40, 40-byte entries from 64: the id, the
// flags at 4, the offset at 8 and the stored size at 16, both u64). Read before the runtime
// validates the file: out-of-range entries give null.
export function rombinChunk(bytes, id) {
  if (bytes.length < 64) return null;
  const d = new DataView(bytes.buffer, bytes.byteOffset, bytes.length);
  const count = d.getUint32(40, true);
  for (let i = 0; i < count && 64 + 40 * (i + 1) <= bytes.length; i++) {
    const e = 64 + 40 * i;
    if (String.fromCharCode(...bytes.subarray(e, e + 4)) !== id) continue;
    const compressed = (d.getUint32(e + 4, true) >> 16) & 0xf;
    const offset = d.getUint32(e + 8, true) + 2 ** 32 * d.getUint32(e + 12, true);
    const stored = d.getUint32(e + 16, true) + 2 ** 32 * d.getUint32(e + 20, true);
    if (compressed || offset + stored > bytes.length) return null;
    return bytes.subarray(offset, offset + stored);
  }
  return null;
}

export class Model {
  // M: the emscripten module (await createRomrt()); bytes: the asset's bytes (Uint8Array).
  constructor(M, bytes) {
    this.M = M;
    this.blocks = [];
    this.c = (name, ...args) => M['_romrt_f32_' + name](...args);
    try {
      this.open(bytes);
    } catch (e) {
      this.free();
      throw e;
    }
  }

  open(bytes) {
    const M = this.M, c = this.c;
    this.err = this.alloc(ERROR_BYTES);
    const out = this.alloc(8); // a size_t or a pointer (4 bytes each in wasm32)
    // The runtime reads the asset in place and wants it aligned to 8 bytes (16 recommended).
    this.asset = this.alloc(bytes.length);
    M.HEAPU8.set(bytes, this.asset);
    this.check(c('arena_size', this.asset, bytes.length, out, this.err));
    const arenaBytes = M.HEAPU32[out >> 2];
    this.arena = this.alloc(arenaBytes);
    this.check(c('open', this.asset, bytes.length, this.arena, arenaBytes, out, this.err));
    this.model = M.HEAPU32[out >> 2];
    this.kind = c('model_kind', this.model);
    this.shown = c('shown_count', this.model);
    this.triangleCount = c('triangle_count', this.model);
    this.r = c('reduced_size', this.model);
    this.arenaBytes = arenaBytes;
    this.xyz = this.alloc(12 * this.shown);
    this.force = this.alloc(12);
  }

  // A heap block aligned to 16 bytes (malloc promises 8 here), freed with the model.
  alloc(bytes) {
    const p = this.M._malloc(bytes + 15);
    if (!p) throw new Error(`out of memory (${bytes} bytes)`);
    this.blocks.push(p);
    return (p + 15) & ~15;
  }

  // Throws for a failed status, with the call, the status's name and the runtime's message (every
  // fallible call fills this.err: romrt.h 3.0).
  check(status, call) {
    if (status === 0) return;
    const M = this.M;
    const name = M.UTF8ToString(this.c('status_string', status));
    const message = M.UTF8ToString(this.err + ERROR_MESSAGE);
    throw new Error(call ? `romrt_${call}: ${name}: ${message}` : `${name}: ${message}`);
  }

  // The shown vertices now, xyz[3 i + k]: a view into the heap, valid until the next call.
  positions() {
    this.check(this.c('positions', this.model, this.xyz, 3 * this.shown, 3, this.err), 'positions');
    return this.M.HEAPF32.subarray(this.xyz >> 2, (this.xyz >> 2) + 3 * this.shown);
  }

  // The deformation gradient at each shown vertex, F[9 i + 3 a + b] = dx_a/dX_b: a view into the
  // heap, valid until the next call; null for an asset without the weights' gradients (GRAD).
  deformationGradients() {
    if (this.F === undefined) this.F = this.alloc(36 * this.shown);
    if (this.c('deformation_gradients', this.model, this.F, 9 * this.shown, this.err) !== 0) return null;
    return this.M.HEAPF32.subarray(this.F >> 2, (this.F >> 2) + 9 * this.shown);
  }

  restPositions() {
    this.check(this.c('rest_positions', this.model, this.xyz, 3 * this.shown, 3, this.err), 'rest_positions');
    return this.M.HEAPF32.slice(this.xyz >> 2, (this.xyz >> 2) + 3 * this.shown);
  }

  // The surface triangles over the shown vertices (empty for a point cloud).
  triangles() {
    const n = this.triangleCount;
    if (n === 0) return new Uint32Array(0);
    const p = this.M._malloc(12 * n);
    try {
      this.check(this.c('triangles', this.model, p, 3 * n, this.err), 'triangles');
      return new Uint32Array(this.M.HEAP32.slice(p >> 2, (p >> 2) + 3 * n));
    } finally {
      this.M._free(p);
    }
  }

  // The whole dynamic state (romrt_get_state), or null where the asset cannot save it (an
  // adaptive linear ROM); setState puts one back.
  getState() {
    const n = this.c('state_size', this.model);
    if (n === 0) return null;
    const p = this.M._malloc(4 * n);
    try {
      this.check(this.c('get_state', this.model, p, n, this.err), 'get_state');
      return this.M.HEAPF32.slice(p >> 2, (p >> 2) + n);
    } finally {
      this.M._free(p);
    }
  }
  setState(state) {
    const p = this.M._malloc(4 * state.length);
    try {
      this.M.HEAPF32.set(state, p >> 2);
      this.check(this.c('set_state', this.model, p, state.length, this.err), 'set_state');
    } finally {
      this.M._free(p);
    }
  }

  step() { this.check(this.c('step', this.model, this.err)); }
  // Koopman assets: `steps` steps at once (cost grows like log(steps)).
  jump(steps) { this.check(this.c('jump', this.model, steps, this.err)); }
  reset() { this.check(this.c('reset', this.model, this.err), 'reset'); }
  time() { return this.c('time', this.model); }
  timeStep() { return this.c('time_step', this.model); }

  // Adds f (N) on one shown vertex; it acts on every following step until clearForces().
  addVertexForce(vertex, f) {
    this.M.HEAPF32.set(f, this.force >> 2);
    this.check(this.c('add_vertex_force', this.model, vertex, this.force, this.err), 'add_vertex_force');
  }
  clearForces() { this.check(this.c('clear_forces', this.model, this.err), 'clear_forces'); }

  free() {
    for (const p of this.blocks) this.M._free(p);
    this.blocks = [];
  }
}

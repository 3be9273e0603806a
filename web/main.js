// main.js: the page. Loads the runtime (romrt.js) once, then an asset from the demo list
// (assets.json, written by make web) or the file picker; every animation frame it sets the drag's
// force, advances the model one step (a Koopman asset: a jump of the slider's steps), times that
// call and draws the positions. A .glb (romkit export's glTF: ?gltf=NAME, the list or the picker)
// is opened by three.js's GLTFLoader instead and its morph-weight animation played by an
// AnimationMixer, the runtime not involved. window.romkitState is what tests/web/page.mjs reads.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import createRomrt from './romrt.js';
import { Model, KIND_KOOPMAN, rombinChunk } from './model.js';
import { Splats } from './splats.js';
import { View } from './view.js';
import { Drag } from './drag.js';

const $ = (id) => document.getElementById(id);
const view = new View($('view'));
const drag = new Drag(view, () => Number($('pull').value));
const jumpSteps = () => 10 ** Number($('jump').value);
let M = null, model = null, rest = null, running = false;
let opened = null; // the last asset opened: { name, bytes }, opened again when the splats box changes
// the open glTF: its animation's mixer, the morphed object; the last frame's time (ms)
let mixer = null, action = null, morphed = null, lastFrame = performance.now();

const state = window.romkitState = {
  ready: false, asset: null, kind: null, drawn: null, shown: 0, triangles: 0, r: 0, h: 0,
  steps: 0, frames: 0, time: 0, error: null,
  // the drag: the grabbed shown vertex, the force on it (N), the pointer's target, k (N/m)
  picked: -1, force: null, target: null, stiffness: null,
  // ms per step of every step since the asset was opened (a jump's time over its steps)
  stepMs: [],
  positions: () => Array.from(view.object.geometry.attributes.position.array),
  rest: () => Array.from(rest),
  // shown vertex i's position on the canvas, CSS pixels
  project: (i) => view.projectVertex(i),
  // an open glTF: what GLTFLoader made of it (null otherwise)
  gltf: null,
  // the glTF's morphed positions (rest plus the weighted targets, as three.js draws them) with its
  // animation set to time t: xyz of every vertex, in the file's vertex order
  gltfPositions: (t) => {
    mixer.setTime(t);
    const p = morphed.geometry.attributes.position, v = new THREE.Vector3(), out = new Array(3 * p.count);
    for (let i = 0; i < p.count; i++) {
      morphed.getVertexPosition(i, v);
      out[3 * i] = v.x; out[3 * i + 1] = v.y; out[3 * i + 2] = v.z;
    }
    return out;
  },
  gltfTimes: () => Array.from(action.getClip().tracks[0].times),
  // a point cloud drawn as Gaussian splats: their count, whether their covariances follow F, and
  // how many frames moved them (null otherwise)
  splats: null,
  // the splats' centres as the library holds them now
  splatCenters: () => view.splats.centers(),
};

function showError(e) {
  state.error = String(e && e.message ? e.message : e);
  $('error').textContent = state.error;
}
window.addEventListener('error', (e) => showError(e.error || e.message));
window.addEventListener('unhandledrejection', (e) => showError(e.reason));

// Closes what is open (a model or a glTF) and starts on `name`.
function close(name) {
  if (model) model.free();
  model = null;
  if (mixer) mixer.stopAllAction();
  mixer = action = morphed = null;
  drag.up(); // a vertex of the last model
  running = false;
  Object.assign(state, { ready: false, asset: name, error: null, steps: 0, stepMs: [], gltf: null, splats: null });
  $('error').textContent = '';
}

// A .glb: its scene drawn, its first animation looping; the first mesh (or points) with morph
// targets is the one state.gltfPositions reads.
async function openGltf(name, bytes) {
  close(name);
  let gltf;
  try {
    gltf = await new GLTFLoader().parseAsync(bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.length), '');
  } catch (e) {
    showError(`${name}: ${e.message}`);
    return;
  }
  if (state.asset !== name) return; // another was opened meanwhile
  const objects = [];
  gltf.scene.traverse((o) => { if (o.isMesh || o.isPoints) objects.push(o); });
  morphed = objects.find((o) => o.morphTargetInfluences) || null;
  for (const o of objects) if (o.isMesh) o.material.side = THREE.DoubleSide; // winding not promised
  view.showGltf(gltf.scene);
  mixer = new THREE.AnimationMixer(gltf.scene);
  const clip = gltf.animations[0];
  if (clip) action = mixer.clipAction(clip).play();
  const p = morphed ? morphed.geometry.attributes.position : null;
  Object.assign(state, {
    kind: 'gltf', drawn: 'gltf', shown: p ? p.count : 0, r: 0, h: 0, time: 0, ready: true,
    triangles: morphed && morphed.isMesh && morphed.geometry.index ? morphed.geometry.index.count / 3 : 0,
    gltf: {
      objects: objects.length, morphed: morphed ? (morphed.isMesh ? 'mesh' : 'points') : null,
      morphTargets: morphed ? morphed.morphTargetInfluences.length : 0,
      animations: gltf.animations.length,
      tracks: clip ? clip.tracks.map((t) => ({ name: t.name, keyframes: t.times.length })) : [],
      duration: clip ? clip.duration : 0,
    },
  });
  $('jump-row').hidden = true;
}

// A point cloud's source splats (its SPLY chunk) drawn in place of its points, once loaded; the
// points stay if the library cannot take them (the reason shown).
async function openSplats(name, m, ply, restXyz) {
  try {
    const F = m.deformationGradients(); // its heap block, taken now: no allocation while stepping
    const splats = await Splats.load(ply, m.shown, restXyz);
    if (model !== m) { splats.dispose(); return; } // another asset was opened meanwhile
    view.showSplats(splats);
    state.drawn = view.drawn;
    state.splats = { count: splats.count, covariances: splats.covariances && F !== null, updates: 0 };
  } catch (e) {
    if (model === m) $('error').textContent = `${name}: drawn as points, not splats: ${e.message}`;
  }
}

function open(name, bytes) {
  opened = { name, bytes };
  if (/\.glb$/i.test(name)) return openGltf(name, bytes).catch(showError);
  close(name);
  try {
    model = new Model(M, bytes);
  } catch (e) {
    showError(`${name}: ${e.message}`);
    return;
  }
  rest = model.restPositions();
  view.show(model, rest);
  const ply = model.triangleCount === 0 && $('splats').checked ? rombinChunk(bytes, 'SPLY') : null;
  if (ply) openSplats(name, model, ply.slice(), rest);
  Object.assign(state, {
    kind: model.kind === KIND_KOOPMAN ? 'koopman' : 'reduced', drawn: view.drawn, shown: model.shown,
    triangles: model.triangleCount, r: model.r, h: model.timeStep(), time: 0, ready: true,
  });
  $('jump-row').hidden = model.kind !== KIND_KOOPMAN;
  running = true;
}

async function openUrl(name) {
  const response = await fetch(name);
  if (!response.ok) throw new Error(`${name}: ${response.status} ${response.statusText}`);
  await open(name, new Uint8Array(await response.arrayBuffer()));
}

function median(values) {
  if (values.length === 0) return NaN;
  const s = values.slice().sort((a, b) => a - b);
  return s[s.length >> 1];
}

function hud(callMs, steps) {
  if (mixer && state.gltf) {
    const g = state.gltf;
    $('hud').textContent = `${state.asset}: glTF (three.js GLTFLoader), ${state.shown} vertices, ` +
      `${g.morphTargets} morph targets\nanimation: ${g.tracks.length ? g.tracks[0].keyframes : 0} keyframes, ` +
      `t = ${state.time.toFixed(2)} of ${g.duration.toFixed(2)} s`;
    return;
  }
  if (!model) return;
  const last = median(state.stepMs.slice(-120));
  const what = state.drawn === 'surface' ? `${state.shown} vertices, ${state.triangles} triangles`
    : state.drawn === 'splats' ? `${state.shown} Gaussian splats` : `${state.shown} points`;
  // performance.now() ticks in 0.1 ms on a page that is not cross-origin isolated
  const ms = (t) => (t > 0 ? `${t.toFixed(3)} ms` : 'under 0.1 ms');
  let timing = `${ms(last)} a step (median of the last ${Math.min(120, state.stepMs.length)})`;
  if (steps > 1) timing = `a jump of ${steps} steps: ${ms(callMs)}`;
  $('hud').textContent = `${state.asset}: ${state.kind}, r = ${state.r}, ${what}\n` +
    `${timing}\nt = ${state.time.toFixed(2)} s` + (drag.force ? `, pulling vertex ${drag.vertex}` : '');
}

function frame() {
  requestAnimationFrame(frame);
  let callMs = 0, steps = 0;
  if (model && running) {
    try {
      drag.apply(model, view.object.geometry.attributes.position.array);
      steps = model.kind === KIND_KOOPMAN ? jumpSteps() : 1;
      const t0 = performance.now();
      if (model.kind === KIND_KOOPMAN) model.jump(steps); else model.step();
      callMs = performance.now() - t0;
      state.stepMs.push(callMs / steps);
      if (state.stepMs.length > 20000) state.stepMs.splice(0, 10000);
      state.steps += steps;
      state.time = model.time();
      if (view.splats) {
        const F = model.deformationGradients();
        view.update(model.positions(), F);
        state.splats.updates = view.splats.updates;
      } else {
        view.update(model.positions());
      }
    } catch (e) {
      running = false; // the runtime leaves the state as it was before a failed step
      showError(`${state.asset}: ${e.message} (reset to go on)`);
    }
    state.picked = drag.vertex;
    state.force = drag.force;
    state.target = drag.force ? drag.target.toArray() : null;
    state.stiffness = drag.k; // N/m, measured at the press
  }
  const now = performance.now(), dt = (now - lastFrame) / 1000;
  lastFrame = now;
  if (mixer) {
    mixer.update(dt);
    state.time = action ? action.time : 0;
  }
  view.render();
  state.frames++;
  hud(callMs, steps);
}

function sliderLabels() {
  $('pull-value').textContent = Number($('pull').value).toFixed(2);
  $('jump-value').textContent = String(jumpSteps());
}

async function main() {
  M = await createRomrt();
  $('pull').addEventListener('input', sliderLabels);
  $('jump').addEventListener('input', sliderLabels);
  sliderLabels();
  $('splats').addEventListener('change', () => { if (opened) open(opened.name, opened.bytes); });
  $('reset').addEventListener('click', () => {
    if (!model) return;
    model.reset();
    Object.assign(state, { steps: 0, stepMs: [], error: null, time: 0 });
    $('error').textContent = '';
    running = true;
  });
  $('file').addEventListener('change', async (e) => {
    const file = e.target.files[0];
    if (!file) return;
    $('demo').selectedIndex = -1;
    open(file.name, new Uint8Array(await file.arrayBuffer()));
  });
  const demos = await (await fetch('assets.json')).json();
  for (const name of demos) $('demo').add(new Option(name, name));
  $('demo').addEventListener('change', (e) => openUrl(e.target.value).catch(showError));
  const query = new URLSearchParams(location.search);
  const first = query.get('gltf') || query.get('asset') || demos[0];
  if (first) {
    $('demo').value = first;
    await openUrl(first);
  }
  requestAnimationFrame(frame);
}

main().catch(showError);

// main.js: the page. Loads the runtime (romrt.js) once, then an asset from the demo list
// (assets.json, written by make web) or the file picker; every animation frame it sets the drag's
// force, advances the model one step (a Koopman asset: a jump of the slider's steps), times that
// call and draws the positions. window.romkitState is what tests/web/page.mjs reads.
import createRomrt from './romrt.js';
import { Model, KIND_KOOPMAN } from './model.js';
import { View } from './view.js';
import { Drag } from './drag.js';

const $ = (id) => document.getElementById(id);
const view = new View($('view'));
const drag = new Drag(view, () => Number($('pull').value));
const jumpSteps = () => 10 ** Number($('jump').value);
let M = null, model = null, rest = null, running = false;

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
};

function showError(e) {
  state.error = String(e && e.message ? e.message : e);
  $('error').textContent = state.error;
}
window.addEventListener('error', (e) => showError(e.error || e.message));
window.addEventListener('unhandledrejection', (e) => showError(e.reason));

function open(name, bytes) {
  if (model) model.free();
  model = null;
  drag.up(); // a vertex of the last model
  running = false;
  Object.assign(state, { ready: false, asset: name, error: null, steps: 0, stepMs: [] });
  $('error').textContent = '';
  try {
    model = new Model(M, bytes);
  } catch (e) {
    showError(`${name}: ${e.message}`);
    return;
  }
  rest = model.restPositions();
  view.show(model, rest);
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
  open(name, new Uint8Array(await response.arrayBuffer()));
}

function median(values) {
  if (values.length === 0) return NaN;
  const s = values.slice().sort((a, b) => a - b);
  return s[s.length >> 1];
}

function hud(callMs, steps) {
  if (!model) return;
  const last = median(state.stepMs.slice(-120));
  const what = state.drawn === 'surface' ? `${state.shown} vertices, ${state.triangles} triangles`
                                         : `${state.shown} points`;
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
      view.update(model.positions());
    } catch (e) {
      running = false; // the runtime leaves the state as it was before a failed step
      showError(`${state.asset}: ${e.message} (reset to go on)`);
    }
    state.picked = drag.vertex;
    state.force = drag.force;
    state.target = drag.force ? drag.target.toArray() : null;
    state.stiffness = drag.k; // N/m, measured at the press
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
  const asked = new URLSearchParams(location.search).get('asset');
  const first = asked || demos[0];
  if (first) {
    $('demo').value = first;
    await openUrl(first);
  }
  requestAnimationFrame(frame);
}

main().catch(showError);

// drag.js: pushing a model by dragging one of its shown vertices. A press on the drawn object
// grabs the nearest shown vertex; the target then follows the pointer on the plane through the
// grabbed point that faces the camera. Before every step the vertex is pulled towards the target
// by a spring, f = k (target - x), through romrt_add_vertex_force: the forces are cleared and set
// again each step, so the force follows the drag, and releasing leaves none.
//
// k is not a constant in N/m: assets weigh from grams to tonnes. At the press the page measures
// how far one step moves the grabbed vertex per newton (its compliance C, from the current state,
// which is then restored), and k = strength / C: strength 0.5 moves the vertex about half way to
// the pointer in a step, whatever the object's mass and stiffness (an explicit spring, stable up
// to a strength of about 1).
import * as THREE from 'three';

// Newtons per metre that one step moves `vertex` along `dir` (a unit vector) from the current
// state; the state is restored. null where it cannot be measured: an asset whose state cannot
// be saved (an adaptive linear ROM), or a vertex no force moves (pinned).
function stiffnessAt(model, vertex, dir, size) {
  const saved = model.getState();
  if (!saved) return null;
  const moved = (f) => {
    model.setState(saved);
    model.clearForces();
    if (f > 0) model.addVertexForce(vertex, [dir.x * f, dir.y * f, dir.z * f]);
    model.step();
    const x = model.positions();
    return new THREE.Vector3(x[3 * vertex], x[3 * vertex + 1], x[3 * vertex + 2]);
  };
  try {
    const base = moved(0);
    // The force grows until the move is well above float32 rounding of the positions.
    for (let f = 1; f <= 1e12; f *= 100) {
      const d = moved(f).sub(base).dot(dir);
      if (d > 1e-3 * size) return f / d;
    }
    return null;
  } catch (e) {
    return null; // the step failed at that force: no measure
  } finally {
    model.setState(saved);
  }
}

export class Drag {
  // view: the View; strength(): the pull's strength (0 to 1), read at every step (the page's slider).
  constructor(view, strength) {
    this.view = view;
    this.strength = strength;
    this.k = null;
    this.vertex = -1;
    this.force = null;
    this.plane = new THREE.Plane();
    this.target = new THREE.Vector3();
    this.line = new THREE.Line(new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(), new THREE.Vector3()]),
                               new THREE.LineBasicMaterial({ color: 0xd04020 }));
    this.line.visible = false;
    view.scene.add(this.line);
    // The canvas's parent listens in the capture phase, before OrbitControls on the canvas: a
    // press on the object is a drag and never reaches the orbit controls; elsewhere it orbits.
    const el = view.renderer.domElement.parentElement;
    el.addEventListener('pointerdown', (e) => this.down(e, el), { capture: true });
    el.addEventListener('pointermove', (e) => this.move(e));
    el.addEventListener('pointerup', () => this.up());
    el.addEventListener('pointercancel', () => this.up());
  }

  local(e) {
    const rect = this.view.renderer.domElement.getBoundingClientRect();
    return [e.clientX - rect.left, e.clientY - rect.top];
  }

  down(e, el) {
    if (!this.view.object || e.button !== 0) return;
    const hit = this.view.pick(...this.local(e));
    if (!hit) return;
    e.stopPropagation();
    el.setPointerCapture(e.pointerId);
    this.vertex = hit.vertex;
    this.k = null; // measured at the next step, on the model
    this.target.copy(hit.point);
    const facing = this.view.camera.getWorldDirection(new THREE.Vector3());
    this.plane.setFromNormalAndCoplanarPoint(facing, hit.point);
  }

  move(e) {
    if (this.vertex < 0) return;
    const rect = this.view.renderer.domElement.getBoundingClientRect();
    const [x, y] = this.local(e);
    const ray = new THREE.Raycaster();
    ray.setFromCamera(new THREE.Vector2((x / rect.width) * 2 - 1, -(y / rect.height) * 2 + 1), this.view.camera);
    ray.ray.intersectPlane(this.plane, this.target);
  }

  up() { this.vertex = -1; }

  // Sets the model's applied force for the next step from the drawn positions xyz.
  apply(model, xyz) {
    model.clearForces();
    this.force = null;
    this.line.visible = this.vertex >= 0;
    if (this.vertex < 0) return;
    if (this.k === null) {
      const up = new THREE.Vector3(0, 1, 0).applyQuaternion(this.view.camera.quaternion);
      this.k = stiffnessAt(model, this.vertex, up, this.view.size);
      if (this.k === null) this.k = 0; // nothing to pull with; the line still shows the drag
    }
    const i = 3 * this.vertex, k = this.strength() * this.k;
    const x = new THREE.Vector3(xyz[i], xyz[i + 1], xyz[i + 2]);
    const f = this.target.clone().sub(x).multiplyScalar(k);
    this.force = [f.x, f.y, f.z];
    model.addVertexForce(this.vertex, this.force);
    this.line.geometry.setFromPoints([x, this.target]);
  }
}

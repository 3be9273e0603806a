// view.js: the three.js scene that draws a model's shown vertices: its surface triangles as a
// mesh, or, for a point cloud (no triangles), the points. The geometry's position buffer is
// refilled from romrt_positions every frame. Or a glTF file's scene (romkit export's morph targets).
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

export class View {
  constructor(container) {
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio);
    container.appendChild(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0xf2f2ef);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x8a8a80, 2.0));
    const sun = new THREE.DirectionalLight(0xffffff, 1.5);
    sun.position.set(1, 2, 3);
    this.scene.add(sun);
    this.camera = new THREE.PerspectiveCamera(40, 1, 0.01, 1000);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.object = null;
    this.gltf = null;
    this.splats = null;
    this.helpers = [];
    this.resize = () => {
      const w = container.clientWidth, h = container.clientHeight;
      this.renderer.setSize(w, h);
      this.camera.aspect = w / h;
      this.camera.updateProjectionMatrix();
    };
    window.addEventListener('resize', this.resize);
    this.resize();
  }

  // Takes away what is drawn: the model's object, or a glTF scene.
  clear() {
    this.hideSplats();
    if (this.object) {
      this.scene.remove(this.object);
      this.object.geometry.dispose();
      this.object.material.dispose();
      this.object = null;
    }
    if (this.gltf) {
      this.scene.remove(this.gltf);
      this.gltf.traverse((o) => { if (o.geometry) o.geometry.dispose(); if (o.material) o.material.dispose(); });
      this.gltf = null;
    }
    for (const h of this.helpers) this.scene.remove(h);
    this.helpers = [];
  }

  // Replaces what is drawn by a glTF file's scene (GLTFLoader's gltf.scene), as it is: its
  // morph targets and animation are the page's (main.js) to play. Nothing in it can be dragged.
  showGltf(root) {
    this.clear();
    this.gltf = root;
    this.scene.add(root);
    this.frame(new THREE.Box3().setFromObject(root));
    this.drawn = 'gltf';
  }

  // Replaces what is drawn by the model's shown vertices (rest: their rest positions).
  show(model, rest) {
    this.clear();
    const geometry = new THREE.BufferGeometry();
    const position = new THREE.BufferAttribute(new Float32Array(rest), 3);
    position.setUsage(THREE.DynamicDrawUsage);
    geometry.setAttribute('position', position);
    geometry.computeBoundingBox();
    const box = geometry.boundingBox;
    const size = box.getSize(new THREE.Vector3()).length();
    const tris = model.triangles();
    if (tris.length > 0) {
      geometry.setIndex(new THREE.BufferAttribute(tris, 1));
      geometry.computeVertexNormals();
      // The stored surface's winding is not promised to face outwards: light both sides.
      const material = new THREE.MeshStandardMaterial({ color: 0x6b8fb5, roughness: 0.7, side: THREE.DoubleSide });
      this.object = new THREE.Mesh(geometry, material);
    } else {
      // about a fifth of the points' mean spacing, were they spread through the bounding box
      const material = new THREE.PointsMaterial({ color: 0x2f5f8f, size: 0.2 * size / Math.cbrt(model.shown) });
      this.object = new THREE.Points(geometry, material);
    }
    this.drawn = tris.length > 0 ? 'surface' : 'points';
    this.scene.add(this.object);
    this.frame(box);
  }

  // Draws a point cloud's Gaussian splats (a Splats, moved by update) in place of its points; the
  // points stay, hidden, for picking.
  showSplats(splats) {
    this.hideSplats();
    this.splats = splats;
    this.scene.add(splats.viewer);
    this.object.visible = false;
    this.drawn = 'splats';
  }

  hideSplats() {
    if (!this.splats) return;
    this.scene.remove(this.splats.viewer);
    this.splats.dispose();
    this.splats = null;
    if (this.object) this.object.visible = true;
    if (this.drawn === 'splats') this.drawn = 'points';
  }

  // A floor grid under the box, and the camera in front of it (+z), a little above.
  frame(box) {
    const size = box.getSize(new THREE.Vector3()).length();
    const center = box.getCenter(new THREE.Vector3());
    const grid = new THREE.GridHelper(2 * size, 20, 0xb0b0a8, 0xd0d0c8);
    grid.position.set(center.x, box.min.y - 0.25 * size, center.z);
    this.scene.add(grid);
    this.helpers = [grid];
    this.camera.near = size / 100;
    this.camera.far = size * 100;
    this.camera.position.set(center.x, center.y + 0.35 * size, center.z + 1.5 * size);
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(center);
    this.controls.update();
    this.size = size;
  }

  // Draws the model's positions (romrt_positions' xyz) this frame; with splats, F (9 per point,
  // romrt_deformation_gradients, or null) turns their covariances.
  update(xyz, F) {
    if (this.splats) this.splats.update(xyz, F);
    const geometry = this.object.geometry;
    geometry.attributes.position.array.set(xyz);
    geometry.attributes.position.needsUpdate = true;
    if (this.drawn === 'surface') geometry.computeVertexNormals();
    // The raycaster culls by the bounding sphere and box: keep them around the moved vertices.
    geometry.computeBoundingBox();
    geometry.computeBoundingSphere();
  }

  render() {
    this.controls.update();
    this.renderer.render(this.scene, this.camera);
  }

  // The shown vertex under a pointer position (CSS pixels in the canvas), and the point hit:
  // the nearest corner of the triangle hit, or the point hit. null when nothing is there.
  pick(x, y) {
    const rect = this.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2((x / rect.width) * 2 - 1, -(y / rect.height) * 2 + 1);
    const ray = new THREE.Raycaster();
    ray.params.Points.threshold = this.size / 100;
    ray.setFromCamera(ndc, this.camera);
    const hit = ray.intersectObject(this.object)[0];
    if (!hit) return null;
    if (this.object.isPoints) return { vertex: hit.index, point: hit.point };
    const p = this.object.geometry.attributes.position;
    let best = -1, bestD = Infinity;
    for (const v of [hit.face.a, hit.face.b, hit.face.c]) {
      const d = new THREE.Vector3().fromBufferAttribute(p, v).distanceToSquared(hit.point);
      if (d < bestD) { bestD = d; best = v; }
    }
    return { vertex: best, point: hit.point };
  }

  // Where shown vertex i is drawn on the canvas (CSS pixels).
  projectVertex(i) {
    const rect = this.renderer.domElement.getBoundingClientRect();
    const p = new THREE.Vector3().fromBufferAttribute(this.object.geometry.attributes.position, i).project(this.camera);
    return { x: (p.x + 1) / 2 * rect.width, y: (1 - p.y) / 2 * rect.height };
  }
}

// splats.js: a point-cloud asset's source Gaussian splats (its SPLY chunk, the 3DGS PLY it was
// built from, its points in file order) drawn by @mkkellogg/gaussian-splats-3d (a DropInViewer in
// the page's three.js scene), moved every frame by the runtime: each splat's centre is its shown
// vertex's position, and its covariance F Σ Fᵀ from its rest covariance Σ and the deformation
// gradient F there (romrt_deformation_gradients), as `romkit run --splats` writes them.
//
// The library has no API to move single splats (only whole scenes), so this writes into its
// internals, as of 0.4.7 (pinned in web/package-lock.json): the splat mesh's base data (centres,
// covariances: xx, xy, xz, yy, yz, zz), pushed to its data textures by
// updateDataTexturesFromBaseData, and the centres its sort worker computes depths from (posted as
// the library posts them at load; dynamicScene sorts again every frame). Not updated: the splat tree the
// library culls by, built from the rest centres (a node wholly off screen at rest may be skipped),
// and the spherical harmonics (loaded at degree 0: the view-dependent colour is not rotated).
import * as GS from './gaussian-splats-3d.module.js';

export class Splats {
  // Loads the PLY (bytes) into a DropInViewer; resolves once its splats are ready. count: the
  // asset's shown vertices; the PLY must give as many splats, in the same order (checked against
  // rest, the rest positions, to 1e-5 of their extent), or this rejects.
  static async load(ply, count, rest) {
    const viewer = new GS.DropInViewer({
      // the GPU's depths (gpuAcceleratedSort) draw nothing in headless chromium's SwiftShader
      gpuAcceleratedSort: false, dynamicScene: true, sharedMemoryForWorkers: false,
      sphericalHarmonicsDegree: 0, optimizeSplatData: false, halfPrecisionCovariancesOnGPU: false,
      logLevel: GS.LogLevel.None,
    });
    const url = URL.createObjectURL(new Blob([ply]));
    try {
      await viewer.addSplatScene(url, { format: GS.SceneFormat.Ply, progressiveLoad: false, showLoadingUI: false });
    } finally {
      URL.revokeObjectURL(url);
    }
    const s = new Splats(viewer, count);
    s.check(rest);
    return s;
  }

  constructor(viewer, count) {
    this.viewer = viewer;
    this.count = count;
    this.updates = 0;
    this.covariances = false;
  }

  mesh() { return this.viewer.viewer.splatMesh; }

  // The library's copy of the splats: as many as the asset's shown vertices, at their rest positions.
  check(rest) {
    const mesh = this.mesh();
    const n = mesh.getSplatCount(true);
    if (n !== this.count) throw new Error(`the PLY has ${n} splats, the asset ${this.count} shown points`);
    const base = mesh.splatDataTextures && mesh.splatDataTextures.baseData;
    if (!base || !base.centers) throw new Error('gaussian-splats-3d: no base data (its internals changed?)');
    let lo = Infinity, hi = -Infinity, worst = 0;
    for (let i = 0; i < 3 * n; i++) {
      lo = Math.min(lo, rest[i]); hi = Math.max(hi, rest[i]);
      worst = Math.max(worst, Math.abs(base.centers[i] - rest[i]));
    }
    if (worst > 1e-5 * (hi - lo)) throw new Error(`the PLY's splats are not the asset's points in order (off by ${worst})`);
    // the rest covariances, kept: each frame's are F Σ Fᵀ of these
    const cov = mesh.splatDataTextures.covariances;
    if (base.covariances && cov && cov.compressionLevel === 0) {
      this.rest = Float32Array.from(base.covariances.subarray(0, 6 * n));
      this.covariances = true;
    }
  }

  // This frame's centres (xyz, 3 per splat) and deformation gradients (F, 9 per splat, row-major;
  // null: the covariances stay at rest).
  update(xyz, F) {
    const mesh = this.mesh(), n = this.count, base = mesh.splatDataTextures.baseData;
    base.centers.set(xyz.subarray(0, 3 * n));
    if (F && this.covariances) {
      const c = base.covariances, r = this.rest;
      for (let i = 0; i < n; i++) {
        const s = 6 * i, f = 9 * i;
        const S = [r[s], r[s + 1], r[s + 2], r[s + 1], r[s + 3], r[s + 4], r[s + 2], r[s + 4], r[s + 5]];
        // T = F S, then F S Fᵀ's upper triangle
        const T = new Array(9);
        for (let a = 0; a < 3; a++)
          for (let b = 0; b < 3; b++)
            T[3 * a + b] = F[f + 3 * a] * S[b] + F[f + 3 * a + 1] * S[3 + b] + F[f + 3 * a + 2] * S[6 + b];
        const C = (a, b) => T[3 * a] * F[f + 3 * b] + T[3 * a + 1] * F[f + 3 * b + 1] + T[3 * a + 2] * F[f + 3 * b + 2];
        c[s] = C(0, 0); c[s + 1] = C(0, 1); c[s + 2] = C(0, 2); c[s + 3] = C(1, 1); c[s + 4] = C(1, 2); c[s + 5] = C(2, 2);
      }
    }
    mesh.updateDataTexturesFromBaseData(0, n - 1);
    // the centres the sort worker orders the splats by depth from (4 per splat: integers in mm, or
    // floats), posted before the next sort request, which the worker answers in order
    const v = this.viewer.viewer;
    if (v.sortWorker) {
      const ints = v.integerBasedSort;
      const c4 = ints ? new Int32Array(4 * n) : new Float32Array(4 * n);
      for (let i = 0; i < n; i++) {
        for (let k = 0; k < 3; k++) c4[4 * i + k] = ints ? Math.round(xyz[3 * i + k] * 1000) : xyz[3 * i + k];
        c4[4 * i + 3] = ints ? 1000 : 1;
      }
      v.sortWorker.postMessage({ centers: c4.buffer, sceneIndexes: new Uint32Array(n).buffer,
                                 range: { from: 0, to: n - 1, count: n } }, [c4.buffer]);
    }
    this.updates++;
  }

  // The library's centres now (what it draws), 3 per splat.
  centers() { return Array.from(this.mesh().splatDataTextures.baseData.centers.subarray(0, 3 * this.count)); }

  dispose() { this.viewer.dispose().catch(() => {}); }
}

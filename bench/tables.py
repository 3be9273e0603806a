#!/usr/bin/env python3
"""Turn the bench result files (bench/results/*.csv, *.json, *.txt, *.md) into markdown tables
in docs/results/, so the tables the documentation links to are written from the measurements and
never by hand.

    python3 bench/tables.py [RESULTS_DIR [DOCS_RESULTS_DIR]]     (make results-tables)

Runs no benchmark: it reads what `make bench`, `make paper-table` and `make bench-reference` left
in bench/results. Every file it writes starts with a line saying so; it writes only the files it
names in docs/results/README.md (its index) and removes nothing else. Python's standard library
only.

A CSV becomes one table, its columns in the CSV's order: a column X with X_min and X_max beside it
is shown as "X (X_min..X_max)"; reals keep 4 significant digits (the CSVs carry more), integers
get thousands separators. A CSV with a `section`, `scenario` or `sweep` column (or the columns
GROUPS names for it) becomes one table per value, each without the columns that are empty in it.
"""
import csv
import json
import os
import sys

# What each result file is: its title, the program that writes it and what its rows are.
# A file not listed here is still tabulated, under its own name.
ABOUT = {
    "physics": ("The cost of projecting dP/dF", "make bench: build/bench_physics",
                "One dP/dF on 256 deformation gradients within 30% of the rest shape (a fifth "
                "inverted): raw, projected by the analytic eigensystem, and by a 9 x 9 Jacobi "
                "eigen-solve; microseconds per dP/dF, median of 21 passes."),
    "fom_scaling": ("Full-order step time against mesh size", "make bench: build/bench_fom",
                    "Soft neo-Hookean object, bottom 10% fixed, gravity, backward Euler at h = 0.01 s; "
                    "seconds per step, Newton iterations per step, the median Newton iteration and "
                    "numeric factorization (s) and their ratio, and the shares of step time."),
    "fom_threads": ("Full-order Newton iteration against factorization, 1 and 2 threads",
                    "make bench: build/bench_fom", "The same measures on the demo beam and bunny_19k."),
    "fom_orderings": ("CHOLMOD orderings", "make bench: build/bench_fom",
                      "Analysis and numeric factorization on one thread, median of 5; flops and lnz "
                      "are CHOLMOD's counts; `chosen` is what the ordering resolved to."),
    "contact_scaling": ("Full-order step time with contact", "make bench: build/bench_contact",
                        "Two soft boxes, one dropped on the other; IPC, one thread; shares of step "
                        "time, contact pairs per potential evaluation, the smallest surface distance "
                        "(m) and exact intersections after the timed steps."),
    "basis_scaling": ("Basis build time against mesh size", "make bench: build/bench_basis",
                      "32 linear modes, 16 RKPM skinning eigenmodes (1,000 kernels), 32 POD modes "
                      "from 100 frames; seconds, median of 3; rkpm_vs_paper_gpu is the RKPM time "
                      "over the FreeForm paper's 3.19 s on a GPU."),
    "scale": ("Scale: meshes refined 1:8", "make bench: build/bench_scale",
              "Refinement, 32 linear modes and full-order steps, each in a child process of its own "
              "(peak resident memory in MiB); one thread per library."),
    "rom": ("Reduced step time with cubature against full order", "make bench: build/bench_rom",
            "The first r of 64 linear modes, cubature trained to 1% force error on 40 poses; "
            "seconds per step full order, reduced exact and reduced with cubature."),
    "runtime": ("Runtime step time and asset size", "make bench: build/bench_runtime",
                "The float32 runtime on a float32 asset against the double reduced simulator on the "
                "same model and the full-order step; linear modes, cubature at tolerance 0.01; "
                "bytes of the asset (and deflated), the arena, every chunk."),
    "runtime_speed": ("Runtime speed against error", "make bench: bench/bench_speed.sh",
                      "The runtime (float32 unless the model says double), one thread: microseconds "
                      "per step in each Newton mode, Newton iterations per step, the error of the "
                      "shown vertices over the first 100 steps against full order, the element "
                      "kernels' GFLOP/s, full order's seconds per step and its ratio to the runtime."),
    "newton_modes": ("The runtime's Newton matrix: fresh, kept, and the default",
                     "make bench: bench/newton_modes.sh (build/bench_newton_modes)",
                     "The converged mode on each asset (float32 through the float runtime, float64 "
                     "through the double one) with a fresh Newton matrix every iteration, with one "
                     "kept for up to k steps, and the default romrt_open leaves: CPU microseconds per "
                     "step (median of interleaved rounds), the ratio to fresh, Newton iterations per "
                     "step, the largest distance of a shown vertex from the fresh trajectory (m and "
                     "over the largest displacement), the asset's Newton tolerance (m) and the "
                     "largest RMS distance from the fresh trajectory over it."),
    "koopman_momentum": ("Koopman momentum ablation (Fig. 4)",
                         "make bench: build/ablation_koopman_momentum",
                         "DMD on the displacement alone (u only) against the paper's [u; u - u_prev], "
                         "same rank, unclamped, fitted on the first 1 s or the whole 2 s of a full-order "
                         "cantilever run and rolled out from frame 1 over 2 s: the largest |lambda| and "
                         "the rollout error (max over frames of |u - u_fom| over the largest |u_fom|); "
                         "the stiff beam's ranks 4 to 24 are asserted (momentum better: 1)."),
    "fuzz": ("Fuzz campaign: inputs per target", "bench/fuzz_campaign.sh SECONDS (not part of make bench)",
             "Each libFuzzer target (clang, ASan and UBSan) run alone for about SECONDS on one core "
             "beside other work, from its seeds and the corpus of earlier runs: the inputs it ran, "
             "the seconds, inputs per second, findings (libFuzzer stops at the first; each is fixed "
             "with its input in tests/fuzz/regressions/) and the corpus it left. A target with a "
             "finding has a second row: the run after the fix."),
    "koopman": ("Koopman operator: fit and runtime cost", "make bench: build/bench_koopman",
                "Cantilever boxes released under gravity, h = 10 ms, one full-order run of 800 "
                "frames each; the fit against the frame count, and the float32 runtime per call "
                "(step, positions, jumps of 1, 10^3 and 10^6 steps)."),
    "adaptive_thresholds": ("Adaptive subspaces: thresholds (Fig. 12)", "make bench: build/bench_adaptive",
                            "The clamped slab on the sphere, 10k tets, 4 steps; difference: the final "
                            "state's largest vertex distance from full order over the bounding-box "
                            "diagonal; residual: the full-space Newton step left (m/s)."),
    "adaptive_stiffness": ("Adaptive subspaces: stiffness (Fig. 14/16)", "make bench: build/bench_adaptive",
                           "A free box on the sphere, 10k tets; PCG iterations of ours (Schur "
                           "complement) beside full-space block-Jacobi CG on the same iterate."),
    "adaptive_speed": ("Adaptive subspaces: speed (Tables 1, 3)", "make bench: build/bench_adaptive",
                       "The clamped slab, 4 steps; the probe_* columns solve the contact step's first "
                       "Newton iteration three ways (CHOLMOD, block-Jacobi CG, ours); no_downdate_* "
                       "the same run without downdating."),
    "adaptive_downdate": ("Adaptive subspaces: downdating where the contact stays put",
                          "make bench: build/bench_adaptive", "The slab, 48k tets, 10 steps."),
    "adaptive_downdate_moving": ("Adaptive subspaces: downdating where the contact moves (Fig. 11)",
                                 "make bench: build/bench_adaptive",
                                 "A stiff box sliding across a soft terrain, 14k tets, 20 steps."),
    "adaptive_mesh": ("Adaptive subspaces: mesh independence (Fig. 9)", "make bench: build/bench_adaptive",
                      "The same scene at two resolutions: the enriched share of the vertices."),
    "alrom": ("Adaptive linear ROM against PCA: ablations", "make bench: bench/bench_alrom.sh",
              "The armadillo's Table 3 scenarios; total relative online error with per-step "
              "realignment, against r, the history m and lambda (adaptive: the CROM decoder)."),
    "alrom_table3": ("Adaptive linear ROM against PCA: the Grassmann paper's Table 3", "make bench: bench/alrom_table3.sh",
                     "Three objects (armadillo_4k, bunny_19k, octopus-low scaled 4x), each compressed, bent, "
                     "stretched and twisted (examples/scenes/alrom/<object>_<motion>.json), every data-driven "
                     "method trained on the object's six other runs; total relative online error with per-step "
                     "realignment at r = 16 (m 20, lambda 0.2): PCA (pod), the adaptive linear ROM with the CROM "
                     "decoder, the modal-derivative quadratic manifold and the fitted quadratic (quadratic_pod); "
                     "lower_*: percent below PCA (negative: above it); paper_*: the paper's Table 3 (its PCA and "
                     "its CROM-decoder ROM, errors in percent) where it has the object and motion; crom_train_s "
                     "and compare_s are wall seconds on a shared machine, not timings."),
    "alrom_runtime": ("Adaptive linear ROM in the runtime", "make bench: bench/bench_alrom_runtime.sh",
                      "float32, r = 16, the armadillo (armadillo_4k, 1,180 vertices) and the bunny (bunny_19k, "
                      "4,670 vertices), each compressed and bent; the adaptive ROM's cubature capped at PCA's "
                      "element count on the same object; CPU microseconds per step, median of 7 interleaved "
                      "rounds of the scene's 40 steps; the free run's error against full order; the step split "
                      "into encoder, basis (history, Grassmann), rows (the basis at the used vertices, G_e), "
                      "terms (M_r, f_r, commit) and Newton by bench_alrom_split (CROM_OBJECTS leaves CROM out of "
                      "an object: its row \"–\")."),
    "alrom_cadence": ("Adaptive linear ROM in the runtime: basis cadence, history, encoder (issue 33)",
                      "make bench: bench/bench_alrom_cadence.sh",
                      "float32, the armadillo's scenes, r = 16, the fitted quadratic decoder at PCA's 210 cubature "
                      "elements; cadence K (the basis formed every K steps, held between), history m, the "
                      "encoder's Gauss-Newton cap; CPU microseconds per step, median of 7 interleaved rounds "
                      "of 40 steps, all assets in one process; the free run's error against full order."),
    "alrom_freerun": ("Why the adaptive linear ROM's free run leads or trails PCA's (issue 33)",
                      "a diagnostic run by hand (not make bench): bench/alrom_freerun.sh",
                      "The precompute's double simulators, r = 16, the fitted quadratic decoder, trained on the "
                      "object's six other motions; errors relative to full order over the run: the adaptive ROM, "
                      "PCA's basis in the same (incremental) simulator, the floors (full order's own states through "
                      "PCA's projection and the decoder's manifold), the kinetic energy the turning basis dropped, "
                      "and romkit compare's PCA (the fixed ROM). Variants: free, exact forces, realigned each step, "
                      "free from step 20, the decoder's basis alone (lambda 1), and the test run's frames added to "
                      "the training (oracle)."),
    "contact_pour": ("The pour in the runtime: 8 objects into a mesh box (issue 30)", "make bench: bench/pour.sh",
                     "Contact every frame, CPU us per step split into broad phase, narrow phase and Newton, "
                     "and the ratio against the old code."),
    "adaptive_moving": ("Adaptive subspaces through a moving obstacle (issue 34)", "make bench: bench/adaptive_moving.sh",
                        "A bar lifted by a rising box platform, the adaptive method against full order."),
    "adaptive_defaults": ("Adaptive subspaces at their defaults on untuned scenes (issue 34)",
                          "make bench: bench/adaptive_defaults.sh",
                          "Drops onto a sphere over a plane (up to the bunny refined to 155k tets), a stiff object "
                          "on a soft one, a twisted bar with self-contact: CPU against full order on one thread, "
                          "the error, the solves handed to full order, the time shares."),
    "adaptive_threads": ("Adaptive subspaces on 1 and 2 threads (issue 34)", "make bench: bench/adaptive_threads.sh",
                         "bench_adaptive's clamped slab at the defaults and at the paper's settings, 1 and 2 "
                         "threads alternated, against full order at its best thread count; the split by part."),
    "moving_obstacles": ("Moving obstacles in the runtime (issue 30)", "make bench: bench/moving_obstacles.sh",
                         "A slab thrown onto a terrain rising at 1 m/s: us per step, Newton iterations, closest "
                         "approach and crossings, against an older build with OLD."),
    "shape_family": ("Shape optimisation of a pneumatic finger's lift (issue 35)", "make bench: bench/shape_family.sh",
                     "examples/shape_family: a 3-value code (chamber length, wall thickness, offset), the neural "
                     "DMD's lift optimum checked by full order."),
    "cage": ("The 43k-vertex class through a simulation cage (issue 32)", "make bench: bench/cage.sh",
             "spot.obj split 1:4 (46,126 vertices) on a cage of at most 20,000 tets, skinning eigenmodes and "
             "cubature by romkit build, and romkit run --frames' OBJ counts."),
    "volume_step": ("The projected volume's cost in the runtime (issue 37)", "make bench: bench/volume_step.sh",
                    "The FreeForm beam's bend, mesh-free skinning at m = 16 and 32, float32, pointwise and projected "
                    "volume on the same integration (exact over the 5,000 grid points, or a cubature trained to 0.01); "
                    "microseconds per step, median of 7 interleaved rounds of 40 steps, and the ratio to pointwise."),
    "p2_beam": ("The beam's converged static sag by quadratic tets (issue 37)", "make bench-reference: build/bench_p2_beam",
                "The freeform beam, linear, a tenth of gravity, first 0.5 m fixed: P2 on the Table-1 box mesh and "
                "its 1:8 refinements; Richardson's extrapolation from the last three levels."),
    "volume_sag": ("The beam's static sag by volume treatment and pressure space (issue 37)",
                   "make bench-reference: build/bench_volume_sag",
                   "The freeform beam, linear, a tenth of gravity, first 0.5 m fixed (Dirichlet clamp), mesh-free "
                   "rkpm_skinning (5,000 grid points) and mesh skinning (1,920 P1 tets) at m weights: tip sag per "
                   "volume (pointwise; projected on the pressure space weights, weights_affine or constant), against "
                   "the converged solid at nu = 0.45 (P2 Richardson, 0.1220 m, p2_beam.md) and Timoshenko at nu = 0. "
                   "At nu = 0 every space gives the pointwise model bit for bit (lambda = 0)."),
    "p2_reference": ("How converged the bend's quadratic-tet reference is (issue 37)",
                     "make bench-reference: bench/p2_reference.sh",
                     "The bend on quadratic tets along two chains of 1:8 refinements (the table box 20x4x4, "
                     "and 10x2x2 for the rate); normalized MSE between consecutive levels at each chain's "
                     "level-0 vertices, the ratio of consecutive changes, and the table reference's "
                     "estimated distance to the limit."),
    "neural_resolution": ("Neural DMD at resolution: 2.4k, 10k and 106k vertices (issue 35)",
                          "make bench-reference: bench/neural_resolution.sh",
                          "A linear cantilever's full-order run and the neural DMD trained on a vertex sample and "
                          "evaluated at every vertex: CPU seconds, peak memory, relative error and normalized MSE."),
    "beam_reference": ("How converged the beam's full-order reference is", "make bench-reference: bench/beam_reference.sh",
                       "Full-order runs of the table scenes on box meshes and their 1:8 refinements; "
                       "normalized MSE between consecutive levels."),
}

# Files tabulated together on one page, in this order: (page, title, command, [files]).
PAGES_OF_TEXT = [
    ("paper_table", "The FreeForm paper's Table 1 beam tests", "make paper-table",
     ["paper_table_bend", "paper_table_bend_pin1e3", "paper_table_twist", "paper_table_twist360",
      "paper_table_twist360_pin1e3", "paper_table_twist_L2", "paper_table_twist_levels",
      "paper_table_twist360_pin_sweep", "paper_table_twist360_lifted", "paper_table_twist360_lifted_mesh",
      "paper_table_twist360_lifted_p1", "paper_table_twist720_frames"]),
]
PAGES_OF_COMPARE_JSON = [
    ("armadillo_point_cloud", "A point cloud against the mesh path (armadillo, FreeForm Table 2)",
     "make paper-table: romkit compare examples/scenes/armadillo_*.json",
     ["armadillo_fix_side", "armadillo_hang", "armadillo_pull"]),
    ("layered_sphere", "A sphere of four layers, stiff-soft-stiff-soft, dropped on the ground (FreeForm Fig. 7)",
     "make paper-table: romkit compare examples/scenes/layered_sphere.json", ["layered_sphere"]),
]
# Result files that no make target writes (one-off runs kept in bench/results): said on their page.
NOT_FROM_A_TARGET = {
    "paper_table_twist_levels": "no make target writes this file: it records one-off bench_reference runs of "
                                "the twist scenes on quadratic tets, as its comment lines say",
    "paper_table_twist360_pin_sweep": "no make target writes this file: it records one-off romkit compare runs "
                                      "of the 360-degree twist's rows at other pin_stiffness values, as its "
                                      "comment lines say",
    "paper_table_twist360_lifted_mesh": "no make target writes this file: it records a one-off romkit compare "
                                        "of the 360-degree twist's mesh-path rows lifted, as its comment lines say",
    "paper_table_twist360_lifted_p1": "no make target writes this file: it records one-off romkit compare runs "
                                      "of the lifted rows against the P1 run, as its comment lines say",
    "paper_table_twist720_frames": "no make target writes this file: it records one-off runtime runs of the "
                                   "720-degree twist's rows read frame by frame (bench/twist_buckle.py), as its "
                                   "comment lines say",
    "paper_table_twist_L2": "no make target writes this file: it records one-off runs of "
                            "`romkit-double run --reference`, as its comment lines say",
}
GROUP_COLUMNS = ("section", "scenario", "sweep")
# Files grouped by other columns than GROUP_COLUMNS (an object column is a plain column elsewhere:
# alrom_table3 is one table of every object).
GROUPS = {"alrom_runtime": ("object", "scenario")}
HEADER = "<!-- Written by bench/tables.py (make results-tables) from bench/results/{src}; do not edit. -->\n"


def number(text):
    """The cell as a number, or None when it is not one."""
    try:
        return float(text)
    except ValueError:
        return None


def cell(text):
    """A CSV value as shown: integers with separators, reals to 4 significant digits."""
    text = text.strip()
    x = number(text)
    if x is None or text.lower() in ("nan", "inf", "-inf"):
        return text.replace("|", "\\|") if text else "–"
    if x == int(x) and "." not in text and "e" not in text.lower():
        return f"{int(x):,}"
    return f"{x:.4g}"


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        return [], []
    header, body = rows[0], [r for r in rows[1:] if any(c.strip() for c in r)]
    width = max([len(header)] + [len(r) for r in body])
    header = header + [f"col_{i + 1}" for i in range(len(header), width)]
    body = [r + [""] * (width - len(r)) for r in body]
    return header, body


def markdown_table(header, body):
    """Columns X, X_min, X_max merged into one; empty columns dropped."""
    keep = [i for i, _ in enumerate(header) if any(r[i].strip() for r in body)]
    names = [header[i] for i in keep]
    columns = []  # (title, index, index_min, index_max)
    for i in keep:
        name = header[i]
        if name.endswith("_min") and name[:-4] in names or name.endswith("_max") and name[:-4] in names:
            continue
        lo = header.index(name + "_min") if name + "_min" in names else None
        hi = header.index(name + "_max") if name + "_max" in names else None
        columns.append((name if lo is None else f"{name} (min..max)", i, lo, hi))
    lines = ["| " + " | ".join(c[0] for c in columns) + " |",
             "|" + "|".join("---:" if all(number(r[c[1]]) is not None or not r[c[1]].strip() for r in body)
                            else "---" for c in columns) + "|"]
    for r in body:
        out = []
        for _, i, lo, hi in columns:
            text = cell(r[i])
            if lo is not None and hi is not None and r[lo].strip():
                text += f" ({cell(r[lo])}..{cell(r[hi])})"
            out.append(text)
        lines.append("| " + " | ".join(out) + " |")
    return "\n".join(lines) + "\n"


def csv_page(stem, path):
    title, command, what = ABOUT.get(stem, (stem, "", ""))
    header, body = read_csv(path)
    text = [HEADER.format(src=os.path.basename(path)), f"# {title}\n"]
    source = f"Source: `bench/results/{os.path.basename(path)}`"
    if os.path.exists(path[:-4] + ".json"):
        source += f" (and `{stem}.json`)"
    if command:
        target, _, program = command.partition(": ")
        source += f", written by `{target}`" + (f" (`{program}`)" if program else "")
    text.append(source + ".\n")
    if what:
        text.append(what + "\n")
    groups = [g for g in GROUPS.get(stem, GROUP_COLUMNS) if g in header]
    if not groups:
        text.append(markdown_table(header, body))
    else:
        index = [header.index(g) for g in groups]
        seen = []
        for r in body:
            key = tuple(r[i] for i in index)
            if key not in seen:
                seen.append(key)
        other = [i for i in range(len(header)) if i not in index]
        for key in seen:
            rows = [[r[i] for i in other] for r in body if tuple(r[i] for i in index) == key]
            text.append("## " + ", ".join(f"{g} {k}" for g, k in zip(groups, key)) + "\n")
            text.append(markdown_table([header[i] for i in other], rows))
    return "\n".join(text)


def text_page(page, title, command, stems, results):
    out = [HEADER.format(src=", ".join(s + ".txt" for s in stems)), f"# {title}\n",
           f"Written by `{command}`: each section is the file as that command printed it.\n"]
    for s in stems:
        path = os.path.join(results, s + ".txt")
        if not os.path.exists(path):
            continue
        with open(path) as f:
            body = f.read().rstrip("\n")
        note = f"\n\n{NOT_FROM_A_TARGET[s]}." if s in NOT_FROM_A_TARGET else ""
        out.append(f"## {s} (`bench/results/{s}.txt`){note}\n\n```\n{body}\n```\n")
    return "\n".join(out)


def compare_json_page(page, title, command, stems, results):
    out = [HEADER.format(src=", ".join(s + ".json" for s in stems)), f"# {title}\n",
           f"Written by `{command}` (the `romkit compare --report` of each scene): normalized MSE and "
           "relative error against the scene's full-order run.\n"]
    for s in stems:
        path = os.path.join(results, s + ".json")
        if not os.path.exists(path):
            continue
        with open(path) as f:
            report = json.load(f)
        out.append(f"## {s} (`bench/results/{s}.json`: {report.get('vertices')} vertices, "
                   f"{report.get('tets')} tets, {report.get('steps')} steps)\n")
        keys = ["seconds_per_step", "normalized_mse", "relative_error", "relative_online_error"]
        rows = [[m.get("name", "")] + ["" if m.get(k) is None else repr(m.get(k)) for k in keys]
                for m in report.get("methods", [])]
        out.append(markdown_table(["method"] + keys, rows))
    return "\n".join(out)


def write(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)


def main():
    results = sys.argv[1] if len(sys.argv) > 1 else "bench/results"
    docs = sys.argv[2] if len(sys.argv) > 2 else "docs/results"
    if not os.path.isdir(results):
        sys.exit(f"tables.py: {results}: no such folder (run make bench first)")
    os.makedirs(docs, exist_ok=True)
    index = []
    for name in sorted(os.listdir(results)):
        stem, ext = os.path.splitext(name)
        if ext == ".csv":
            write(os.path.join(docs, stem + ".md"), csv_page(stem, os.path.join(results, name)))
            index.append((stem, ABOUT.get(stem, (stem,))[0], name))
        elif ext == ".md":
            with open(os.path.join(results, name)) as f:
                body = f.read()
            write(os.path.join(docs, stem + ".md"), HEADER.format(src=name) + body)
            index.append((stem, ABOUT.get(stem, (stem,))[0], name))
    for page, title, command, stems in PAGES_OF_TEXT:
        if any(os.path.exists(os.path.join(results, s + ".txt")) for s in stems):
            write(os.path.join(docs, page + ".md"), text_page(page, title, command, stems, results))
            index.append((page, title, ", ".join(s + ".txt" for s in stems)))
    for page, title, command, stems in PAGES_OF_COMPARE_JSON:
        if any(os.path.exists(os.path.join(results, s + ".json")) for s in stems):
            write(os.path.join(docs, page + ".md"), compare_json_page(page, title, command, stems, results))
            index.append((page, title, ", ".join(s + ".json" for s in stems)))
    lines = [HEADER.format(src="*"), "# Results tables\n",
             "Every table here is written by `bench/tables.py` from the files the benches leave in "
             "`bench/results/` (`make bench`, `make paper-table` and `make bench-reference` call it at "
             "their end; `make results-tables` runs it alone). What the numbers mean and what they show "
             "is discussed in [../performance.md](../performance.md) and [../methods.md](../methods.md). "
             "Measured on 2 cores of an AMD EPYC (a shared cloud VM), Debian 12, gcc 12.\n",
             "| page | what | from |", "|---|---|---|"]
    for stem, title, src in index:
        lines.append(f"| [{stem}.md]({stem}.md) | {title} | `{src}` |")
    write(os.path.join(docs, "README.md"), "\n".join(lines) + "\n")
    print(f"tables.py: {len(index)} pages in {docs}/ from {results}/")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""tests/bench/quick_bench_test.py NAME BUILD_DIR     (ctest -L bench runs it for every benchmark)

Runs `scripts/bench NAME --quick` on the programs built in BUILD_DIR with an empty cache directory,
as on a fresh clone, and checks what it prints: one JSON object for benchmark NAME, run in quick
mode, whose figures are all finite and include NAME's headline figures, and whose correctness
flags hold. Exits with $TEXSIM_TEST_SKIPPED_EXIT_CODE (ctest: Skipped) when NAME needs DOLFINx and python3-dolfinx is absent: the
quick mode never installs packages from a test (scripts/bench fem-step installs it).
"""

import importlib.util
import json
import math
import os
import subprocess
import sys
import tempfile

# Per benchmark: figures that must be present, and figures that must be true.
EXPECTED = {
    "checkpoint": (["write_MBps_n1", "write_MBps_n2", "read_verify_MBps_n2"], ["exact"]),
    "fem-step": (["vertices", "rd_step_s_n2", "heat_cg_iters", "dolfinx_step_s",
                  "ratio_vs_dolfinx", "edge_cut_scotch_n2", "cg_iteration_over_matmult_n2",
                  "cg_iteration_over_matmult_icc_n2"], []),
    "similarity-set": (["voxels", "pruned_s_n2", "scan_s_n2", "scan_over_pruned_n2",
                        "exemplar_128_s_n2"], ["exact", "pruned_equals_scan"]),
    "solid-synthesis": (["features_64_s", "synth_128_s_n2", "synth_128_s_n1", "voxels_per_s_n2"],
                        []),
    "turk": (["cells", "relax_100k_s", "cell_updates_per_s_n2", "bandwidth_fraction"],
             ["solver_finite", "fused_matches_solver"]),
    "partition": (["elephant_cut_scotch_2", "elephant_cut_morton_2", "elephant_cut_ratio_3"], []),
    "raw-scan": (["fem_jacobi_cg_iterations_per_step", "fem_auto_cg_iterations_per_step",
                  "turk_substeps", "vertices"], []),
    "scale": (["rss_n8_over_n1_solid", "rss_n8_over_n1_fem", "rss_n8_over_n1_turk",
               "rss_n8_over_n1_surface", "rss_mb_n8_surface_rank0",
               "rss_mb_n8_surface_other_ranks_max", "pss_n8_over_n1_solid",
               "projected_efficiency_64_solid", "projected_efficiency_64_fem",
               "projected_efficiency_64_turk"], ["solid_work_model_matches_n8"]),
    "fluid": (["frame_s_n2", "frame_s_n1", "advect_s", "update_s", "create_s", "atlas_s",
               "write_s", "speedup_1_to_2", "patches"], []),
    "loop-basis": (["functions_level2", "p1_ms_per_step_level2", "loop_ms_per_step_level2",
                    "loop_over_p1_level2"], []),
    "surface-synthesis": (["relax_s_n2", "exact_s_n2", "tsvq_s_n2", "pruned_s_n2",
                           "speedup_1_to_2", "neighbourhood_error_exact", "neighbourhood_error_tsvq",
                           "neighbourhood_error_pruned", "tsvq_exact_fraction"], []),
}


def fail(message):
    print(f"FAIL: {message}")
    sys.exit(1)


def finite(value):
    if isinstance(value, bool):
        return True
    if isinstance(value, (int, float)):
        return math.isfinite(value)
    return isinstance(value, str) and value != ""


def main():
    name, build_dir = sys.argv[1], sys.argv[2]
    if name == "fem-step" and importlib.util.find_spec("dolfinx") is None:
        print("SKIPPED: python3-dolfinx is not installed (scripts/bench fem-step installs it)")
        return int(os.environ["TEXSIM_TEST_SKIPPED_EXIT_CODE"])
    source_dir = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    with tempfile.TemporaryDirectory(prefix=f"texsim_bench_{name}_") as cache:
        run = subprocess.run(
            [os.path.join(source_dir, "scripts", "bench"), name, "--quick",
             "--build-dir", build_dir, "--cache-dir", cache],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, check=False)
    if run.returncode != 0:
        fail(f"scripts/bench {name} --quick exited with {run.returncode}:\n{run.stderr}")
    try:
        result = json.loads(run.stdout)
    except json.JSONDecodeError as error:
        fail(f"stdout is not one JSON object ({error}):\n{run.stdout}")
    if result.get("benchmark") != name or result.get("quick") is not True:
        fail(f"benchmark {result.get('benchmark')!r}, quick {result.get('quick')!r}")
    figures = result.get("figures")
    if not isinstance(figures, dict) or not figures:
        fail("no figures")
    bad = {key: value for key, value in figures.items() if not finite(value)}
    if bad:
        fail(f"figures that are not finite: {bad}")
    present, flags = EXPECTED[name]
    missing = [key for key in present + flags if key not in figures]
    if missing:
        fail(f"figures missing: {missing}")
    false = [key for key in flags if figures[key] is not True]
    if false:
        fail(f"figures that should be true: {false}")
    print(f"PASS: {name}: {len(figures)} figures")
    return 0


if __name__ == "__main__":
    sys.exit(main())

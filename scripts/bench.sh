#!/usr/bin/env bash
# Builds ellipsekit (Release, into build/) and runs the benchmark suite:
#   out/bench/bench.json   Google Benchmark JSON (every number below comes from this one run)
#   out/bench/ratios.md    time ratios measured in that run
#   out/bench/stages.png   detect() time per stage on the generated scenes, per backend
# Usage: scripts/bench.sh [extra ellipsekit_bench flags, e.g. --benchmark_filter=...]
#        scripts/bench.sh --python [COUNT]   the Python batch runner's throughput (see below)
# ELLIPSEKIT_BENCH_MIN_TIME (seconds per benchmark, default 0.2) trades run time for noise.
# ELLIPSEKIT_BUILD_DIR picks the build tree (default build/), ELLIPSEKIT_BENCH_OUT the output
# folder (default out/bench). A quick look at the Vulkan edge stage alone, for example:
#   ELLIPSEKIT_BENCH_MIN_TIME=0.05 scripts/bench.sh --benchmark_filter='^edge_stage/'
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

scripts/setup.sh

# scripts/bench.sh --python [COUNT]: only the batch runner's throughput (python/bench/batch_throughput.py):
# images per second of `python3 -m ellipsekit.batch` with 1 and 2 local workers against
# `ellipsekit detect --warmup 0` over COUNT (default 2000) generated 640x480 scenes -> out/bench/batch.md.
build_dir="${ELLIPSEKIT_BUILD_DIR:-build}"
if [[ "${1:-}" == "--python" ]]; then
  cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$build_dir" -j2 --target ellipsekit_cli ellipsekit_python
  python=$(sed -n 's/^Python_EXECUTABLE:FILEPATH=//p' "$build_dir/CMakeCache.txt")
  exec "${python:-python3}" python/bench/batch_throughput.py --build "$build_dir" --count "${2:-2000}" --out out/bench
fi
cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DELLIPSEKIT_BUILD_BENCH=ON >/dev/null
cmake --build "$build_dir" -j2 --target ellipsekit_bench ellipsekit_plot

out="${ELLIPSEKIT_BENCH_OUT:-out/bench}"
mkdir -p "$out"
min_time="${ELLIPSEKIT_BENCH_MIN_TIME:-0.2}"
echo "bench.sh: running $build_dir/bin/ellipsekit_bench (min_time ${min_time}s per benchmark) -> $out/bench.json" >&2
"$build_dir/bin/ellipsekit_bench" --benchmark_format=json --benchmark_out_format=json \
  --benchmark_out="$out/bench.json" --benchmark_min_time="$min_time" "$@" >/dev/null

python3 - "$out" "$build_dir" <<'PY'
import json, statistics, sys
out = sys.argv[1]
data = json.load(open(f"{out}/bench.json"))
unit_ms = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}

# name (without the /real_time suffix) -> run; skipped runs kept apart with their message
runs, skipped = {}, {}
for b in data["benchmarks"]:
    if b.get("run_type", "iteration") != "iteration":
        continue
    name = b["name"].removesuffix("/real_time")
    if b.get("error_occurred"):
        skipped[name] = b.get("error_message", "")
        continue
    b["ms"] = b["real_time"] * unit_ms[b.get("time_unit", "ns")]
    runs[name] = b

def ms(name):
    r = runs.get(name)
    return r["ms"] if r else None

def ratio(a, b):
    return None if a is None or b is None or b == 0 else a / b

def fmt(x, digits=3):
    return "n/a" if x is None else f"{x:.{digits}g}"

sizes = ["640x480", "1280x720", "1920x1080"]
kernels = ["gaussian", "sobel", "canny_thresholds", "nms", "hysteresis", "edge_sign"]
ctx = data.get("context", {})
lines = ["# ellipsekit benchmark ratios", "",
         f"One run of `{sys.argv[2]}/bin/ellipsekit_bench` ({ctx.get('date', '?')}, {ctx.get('num_cpus', '?')} CPUs "
         f"at {ctx.get('mhz_per_cpu', '?')} MHz, load average {ctx.get('load_avg', '?')}). "
         "Ratios are wall-time ratios A / B: below 1 means A is faster. OpenCV single-threaded.", ""]

lines += ["## Edge stage (gray -> sign-classified edge map) vs OpenCV", "",
          "| size | SIMD ms | cv::Canny ms | SIMD / cv::Canny | blur+Canny ms | SIMD / (blur+Canny) | scalar / cv::Canny |",
          "|---|---|---|---|---|---|---|"]
for s in sizes:
    simd, canny, bc, sc = ms(f"edge_stage/simd/{s}"), ms(f"opencv/canny/{s}"), ms(f"opencv/blur_canny/{s}"), ms(f"edge_stage/scalar/{s}")
    lines.append(f"| {s} | {fmt(simd)} | {fmt(canny)} | {fmt(ratio(simd, canny))} | {fmt(bc)} | {fmt(ratio(simd, bc))} | {fmt(ratio(sc, canny))} |")
lines.append("")

# SIMD per kernel: the best Highway target that ran (the first registered = Backend::kSimd's default).
targets = []
for name in list(runs) + list(skipped):
    parts = name.split("/")
    if parts[0] == "kernel" and parts[2].startswith("simd:") and parts[2][5:] not in targets:
        targets.append(parts[2][5:])
ran_targets = [t for t in targets if any(n.split("/")[2] == f"simd:{t}" for n in runs if n.startswith("kernel/"))]
best = ran_targets[0] if ran_targets else None
lines += [f"## SIMD / scalar per kernel (Highway target {best or 'n/a'}, the default one)", "",
          "| kernel | " + " | ".join(sizes) + " |", "|---|" + "---|" * len(sizes)]
for k in kernels:
    cells = [fmt(ratio(ms(f"kernel/{k}/simd:{best}/{s}"), ms(f"kernel/{k}/scalar/{s}"))) for s in sizes]
    lines.append(f"| {k} | " + " | ".join(cells) + " |")
lines.append("")
if ran_targets:
    lines += ["### SIMD / scalar per kernel and Highway target, 1920x1080", "",
              "| kernel | " + " | ".join(ran_targets) + " |", "|---|" + "---|" * len(ran_targets)]
    for k in kernels:
        cells = [fmt(ratio(ms(f"kernel/{k}/simd:{t}/1920x1080"), ms(f"kernel/{k}/scalar/1920x1080"))) for t in ran_targets]
        lines.append(f"| {k} | " + " | ".join(cells) + " |")
    lines.append("")
    skipped_t = [t for t in targets if t not in ran_targets]
    if skipped_t:
        lines += [f"Skipped Highway targets (not supported by this CPU): {', '.join(skipped_t)}.", ""]

# Wall times come from edge_stage/vulkan/<size> (no timestamps); device times from
# edge_stage/vulkan_steps/<size>, the same frames with a timestamp around each of the three
# dispatches (which cost time of their own, so its wall time is the larger).
def device_ms(s):
    v = runs.get(f"edge_stage/vulkan_steps/{s}")
    d = v.get("device_ms") if v else None
    return d if d is not None and d >= 0 else None

lines += ["## Vulkan / SIMD edge stage (warm, transfers included)", "",
          "| size | Vulkan wall ms | Vulkan device ms (timestamps) | SIMD ms | Vulkan / SIMD (wall) | Vulkan / SIMD (device) | device |",
          "|---|---|---|---|---|---|---|"]
for s in sizes:
    v = runs.get(f"edge_stage/vulkan/{s}")
    simd = ms(f"edge_stage/simd/{s}")
    if v is None:
        why = skipped.get(f"edge_stage/vulkan/{s}", "not run")
        lines.append(f"| {s} | skipped: {why} | | {fmt(simd)} | | | |")
        continue
    dev = device_ms(s)
    lines.append(f"| {s} | {fmt(v['ms'])} | {fmt(dev)} | {fmt(simd)} | {fmt(ratio(v['ms'], simd))} | {fmt(ratio(dev, simd))} | {v.get('label', '')} |")
lines.append("")

steps = ["gaussian_sobel_thresholds", "nms_edge_sign", "hysteresis"]
lines += ["### Vulkan device time per dispatch (ms, `edge_stage/vulkan_steps`); 64x48: the fixed cost per frame", "",
          "| size | " + " | ".join(steps) + " | device | wall with timestamps | wall | cold wall (new stage + first frame) | SIMD wall |",
          "|---|" + "---|" * (len(steps) + 5)]
for s in sizes + ["64x48"]:
    v = runs.get(f"edge_stage/vulkan_steps/{s}")
    if v is None and ms(f"edge_stage/vulkan/{s}") is None:
        continue
    cells = [fmt(v.get(f"{st}_ms") if v else None) for st in steps]
    lines.append(f"| {s} | " + " | ".join(cells) + f" | {fmt(device_ms(s))} | {fmt(v['ms'] if v else None)} | {fmt(ms(f'edge_stage/vulkan/{s}'))} | "
                 f"{fmt(ms(f'edge_stage/vulkan_cold/{s}'))} | {fmt(ms(f'edge_stage/simd/{s}'))} |")
lines.append("")

lines += ["## End to end: detect() / (3x3 blur + cv::Canny) on the same image (median of per-image ratios)", "",
          "| set | images | detect(scalar) / blur+Canny | detect(SIMD) / blur+Canny | detect(Vulkan) / blur+Canny | median detect(SIMD) ms | median blur+Canny ms |",
          "|---|---|---|---|---|---|---|"]
for st in ["prasad", "photos", "scenes"]:
    images = sorted({n.split("/", 2)[2] for n in runs if n.startswith(f"opencv_blur_canny_image/{st}/")})
    cols = []
    for be in ["scalar", "simd", "vulkan"]:
        rs = [ratio(ms(f"detect/{be}/{st}/{i}"), ms(f"opencv_blur_canny_image/{st}/{i}")) for i in images]
        rs = [r for r in rs if r is not None]
        cols.append(fmt(statistics.median(rs)) if rs else "n/a")
    dsimd = [ms(f"detect/simd/{st}/{i}") for i in images if ms(f"detect/simd/{st}/{i}") is not None]
    canny = [ms(f"opencv_blur_canny_image/{st}/{i}") for i in images]
    lines.append(f"| {st} | {len(images)} | " + " | ".join(cols) +
                 f" | {fmt(statistics.median(dsimd)) if dsimd else 'n/a'} | {fmt(statistics.median(canny)) if canny else 'n/a'} |")
lines.append("")
# The issue's set: all 200 scenes of `ellipsekit scenes --count 200 --seed 7`, one iteration each.
c200 = ms("opencv_blur_canny_image/scenes200")
lines += ["## End to end over the 200 generated scenes (sum of times per iteration)", "",
          "| backend | detect / (blur + cv::Canny) | detect ms per scene | blur + cv::Canny ms per scene |", "|---|---|---|---|"]
for be in ["scalar", "simd", "vulkan"]:
    d = ms(f"detect/{be}/scenes200")
    per = lambda x: None if x is None else x / 200
    lines.append(f"| {be} | {fmt(ratio(d, c200))} | {fmt(per(d))} | {fmt(per(c200))} |")
lines.append("")
if skipped:
    lines += ["## Skipped", ""] + [f"- `{n}`: {m}" for n, m in sorted(skipped.items())] + [""]
open(f"{out}/ratios.md", "w").write("\n".join(lines))

# stages.tsv for ellipsekit_plot: mean stage time of detect() over the scenes, per backend.
stages = ["edges", "curves", "arcs", "fit", "validate"]
rows = []
for be in ["scalar", "simd", "vulkan"]:
    rr = [r for n, r in runs.items() if n.startswith(f"detect/{be}/scenes/")]
    if not rr:
        continue
    for stg in stages:
        rows.append(f"{stg}\t{be}\t{statistics.mean(r[stg + '_ms'] for r in rr):.4f}")
    rows.append(f"total\t{be}\t{statistics.mean(r['total_ms'] for r in rr):.4f}")
with open(f"{out}/stages.tsv", "w") as f:
    f.write(f"detect() time per stage, mean over {len(rr) if rows else 0} generated scenes (640x480)\tms per frame (log scale)\tlog\n")
    f.write("\n".join(rows) + "\n")
PY

wrote="$out/bench.json, $out/ratios.md"
if grep -q '^total' "$out/stages.tsv"; then  # a run filtered to no detect/*/scenes/* has nothing to plot
  "$build_dir/bin/ellipsekit_plot" "$out/stages.tsv" "$out/stages.png"
  wrote+=", $out/stages.png"
fi
echo "bench.sh: wrote $wrote" >&2
cat "$out/ratios.md"

"""Images per second of `python3 -m ellipsekit.batch` (1 and 2 local workers) against
`ellipsekit detect --warmup 0` over the same generated 640x480 scenes (decoding included in both).

    python3 python/bench/batch_throughput.py --build build --count 2000 --out out/bench [--repeats 3]

Run by `scripts/bench.sh --python`. The runs are interleaved (CLI, 1 worker, 2 workers, then again)
so that a machine shared with other work spreads its noise over all three; the medians are
reported. For the batch, two rates: the run itself (first chunk submitted to last line written,
what its summary prints) and the whole command (interpreter, cluster start and stop included).
"""
import argparse
import os
import re
import statistics
import subprocess
import sys
import time


def timed(cmd, env=None):
    t0 = time.perf_counter()
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    wall = time.perf_counter() - t0
    if r.returncode != 0:
        sys.exit(f"batch_throughput: {' '.join(cmd[:4])} ... failed ({r.returncode}):\n{r.stderr[-3000:]}")
    return wall, r.stdout


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--build", default="build")
    p.add_argument("--count", type=int, default=2000)
    p.add_argument("--seed", type=int, default=7)
    p.add_argument("--out", default="out/bench")
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--workers", default="1,2")
    args = p.parse_args()

    cli = os.path.join(args.build, "bin", "ellipsekit")
    scenes = os.path.join(args.out, f"scenes{args.count}_seed{args.seed}")
    images_dir = os.path.join(scenes, "images")
    have = len(os.listdir(images_dir)) if os.path.isdir(images_dir) else 0
    if have != args.count:
        print(f"batch_throughput: generating {args.count} scenes into {scenes}", file=sys.stderr)
        subprocess.run([cli, "scenes", "--out", scenes, "--count", str(args.count), "--seed", str(args.seed)],
                       check=True, stdout=subprocess.DEVNULL)
    images = sorted(os.path.join(images_dir, f) for f in os.listdir(images_dir))
    env = dict(os.environ, PYTHONPATH=os.path.join(os.path.abspath(args.build), "python"))
    results = os.path.join(args.out, "batch_results.jsonl")
    workers = [int(w) for w in args.workers.split(",")]

    cli_rate, run_rate, cmd_rate = [], {w: [] for w in workers}, {w: [] for w in workers}
    load = [os.getloadavg()[0]]
    for rep in range(args.repeats):
        wall, _ = timed([cli, "detect", "--warmup", "0", *images])
        cli_rate.append(len(images) / wall)
        print(f"batch_throughput: [{rep + 1}/{args.repeats}] ellipsekit detect: {cli_rate[-1]:.1f} images/s",
              file=sys.stderr)
        for w in workers:
            wall, out = timed([sys.executable, "-m", "ellipsekit.batch", images_dir, "--out", results,
                               "--workers", str(w), "--no-progress"], env=env)
            rate = float(re.search(r"^images per second: ([0-9.]+)$", out, re.M).group(1))
            run_rate[w].append(rate)
            cmd_rate[w].append(len(images) / wall)
            print(f"batch_throughput: [{rep + 1}/{args.repeats}] batch, {w} worker(s): {rate:.1f} images/s "
                  f"({cmd_rate[w][-1]:.1f} with the cluster's start)", file=sys.stderr)
        load.append(os.getloadavg()[0])

    med = statistics.median
    c = med(cli_rate)
    lines = [
        "# Batch throughput: python3 -m ellipsekit.batch vs ellipsekit detect", "",
        f"{len(images)} generated 640x480 scenes (seed {args.seed}), {args.repeats} interleaved repetitions, "
        f"medians; {os.cpu_count()} CPUs, 1-minute load average {min(load):.1f}-{max(load):.1f} during the runs.", "",
        "| run | images/s | vs `ellipsekit detect` | vs 1 worker |",
        "|---|---|---|---|",
        f"| `ellipsekit detect --warmup 0` (one process) | {c:.1f} | 1.00 | |",
    ]
    base = med(run_rate[workers[0]])
    for w in workers:
        r = med(run_rate[w])
        lines.append(f"| batch, {w} worker(s): the run | {r:.1f} | {r / c:.2f} | {r / base:.2f} |")
        lines.append(f"| batch, {w} worker(s): whole command | {med(cmd_rate[w]):.1f} | {med(cmd_rate[w]) / c:.2f} | |")
    lines += ["", "All runs: ellipsekit detect " + ", ".join(f"{x:.1f}" for x in cli_rate) + "; " +
              "; ".join(f"{w} worker(s) " + ", ".join(f"{x:.1f}" for x in run_rate[w]) for w in workers), ""]
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "batch.md"), "w") as f:
        f.write("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()

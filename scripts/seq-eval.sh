#!/bin/bash
# Scores a rendered sequence (ellipsekit scenes --conveyor|--stack|--crossing --out SEQ):
#   detection: `ellipsekit eval` over its frames, each frame's truth the ellipses of truth.jsonl
#              (written as an eval dataset to SEQ/eval/: images/ links to frames/, gt/);
#   tracking:  `ellipsekit track SEQ [--conveyor]`, per frame the confirmed track nearest the
#              true top centre: frames without one, distinct ids, position error median / p95.
# Usage: scripts/seq-eval.sh SEQ [--conveyor]   (run from the repository root after a build)
set -euo pipefail
seq=${1:?usage: scripts/seq-eval.sh SEQ [--conveyor]}
shift
bin=build/bin/ellipsekit
[ -x "$bin" ] || { echo "seq-eval: $bin not found (build first)" >&2; exit 1; }
[ -f "$seq/truth.jsonl" ] || { echo "seq-eval: $seq/truth.jsonl not found" >&2; exit 1; }
rm -rf "$seq/eval"
mkdir -p "$seq/eval/images" "$seq/eval/gt"
python3 - "$seq" <<'PY'
import json, os, sys
seq = sys.argv[1]
for i, line in enumerate(open(os.path.join(seq, "truth.jsonl"))):
    stem = "%06d" % i
    os.symlink(os.path.abspath(os.path.join(seq, "frames", stem + ".png")),
               os.path.join(seq, "eval", "images", stem + ".png"))
    with open(os.path.join(seq, "eval", "gt", stem + ".txt"), "w") as f:
        for top in json.loads(line)["tops"]:
            f.write(" ".join(repr(v) for v in top["ellipse"]) + "\n")
PY
"$bin" eval "$seq/eval" | grep -E '^(precision|recall|F-measure)'
"$bin" track "$seq" "$@" --out "$seq/eval/track.jsonl" > /dev/null
python3 - "$seq" <<'PY'
import json, math, os, statistics, sys
seq = sys.argv[1]
truth = [json.loads(l) for l in open(os.path.join(seq, "truth.jsonl"))]
tracks = [json.loads(l) for l in open(os.path.join(seq, "eval", "track.jsonl"))]
errors, without, ids = [], 0, set()
for t, k in zip(truth, tracks):
    for top in t["tops"]:
        confirmed = [x for x in k["tracks"] if x["state"] == "confirmed"]
        if not confirmed:
            without += 1
            continue
        nearest = min(confirmed, key=lambda x: math.dist(x["position"], top["centre"]))
        ids.add(nearest["id"])
        errors.append(1000 * math.dist(nearest["position"], top["centre"]))
print("tops without a confirmed track: %d of %d" % (without, sum(len(t["tops"]) for t in truth)))
print("track ids: %d" % len(ids))
if errors:
    errors.sort()
    print("position error: median %.2f mm, p95 %.2f mm" % (statistics.median(errors), errors[int(0.95 * (len(errors) - 1))]))
PY

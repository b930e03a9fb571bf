#!/usr/bin/env bash
# The fixture set through every method and scheme, hashed: `bash .ci/fixture-hashes.sh SUBDIV OUT`
# runs `SUBDIV batch` (the release binary under test) over fixtures/ and prints one line per
# output file and per record, `sha256  path`, records with their timings and file fingerprints
# removed. Two binaries that print the same lines wrote the same bytes and the same reports.
set -euo pipefail
bin="$1"; out="$(mkdir -p "$2" && cd "$2" && pwd)"
cd "$(dirname "$0")/.."
rm -rf "$out"; mkdir -p "$out"
run() { # name, then the batch arguments
    local name="$1"; shift
    "$bin" batch "$@" 'fixtures/**/*' --out-dir "$out/$name" --jobs 2 > "$out/$name.jsonl" 2> "$out/$name.stderr" || true
}
for method in nasri zheng-cai cheng fan-cheng-lai deng-wang deng-ma fair; do
    run "interpolate-$method" interpolate --method "$method" --levels 1
done
run interpolate-fair-loop interpolate --method fair --scheme loop --levels 1
run interpolate-cheng-edge-only interpolate --method cheng --boundary edge-only --levels 1 --format ply
for scheme in doo-sabin catmull-clark loop deng-ma; do
    run "subdivide-$scheme" subdivide --scheme "$scheme" --levels 2
done
run subdivide-catmull-clark-limit subdivide --scheme catmull-clark --levels 1 --limit --normals
run subdivide-loop-triangulate subdivide --scheme loop --levels 1 --triangulate --beta loop
run info info
python3 - "$out" <<'PY'
import hashlib, json, pathlib, sys
out = pathlib.Path(sys.argv[1])
prefix = str(out.resolve()) + "/"
def strip(v):
    if isinstance(v, dict):
        return {k: strip(x) for k, x in v.items() if k not in ("seconds", "timing_ms", "fingerprint", "skipped")}
    if isinstance(v, list):
        return [strip(x) for x in v]
    if isinstance(v, str):
        return v.replace(prefix, "OUT/")  # output paths, as the records name them
    return v
for path in sorted(out.rglob("*")):
    if path.is_dir() or path.suffix == ".stderr":
        continue
    rel = path.relative_to(out)
    if path.name.endswith(".record.json"):
        continue  # the same records are in the .jsonl, in input order
    if path.suffix == ".jsonl":
        for line in path.read_text().splitlines():
            rec = strip(json.loads(line))
            digest = hashlib.sha256(json.dumps(rec, sort_keys=True).encode()).hexdigest()
            print(f"{digest}  {rel}#{rec.get('name')}")
    else:
        print(f"{hashlib.sha256(path.read_bytes()).hexdigest()}  {rel}")
PY

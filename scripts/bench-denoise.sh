#!/usr/bin/env bash
# The denoising goal of issue 46 (BENCHMARKS.md, "Denoising"): the Cornell box at
# 512x512 path-traced at 16 samples per pixel, noisy and denoised (OIDN's high and
# fast networks), each rendered three times for the median of the AOV pass's and
# the filter's seconds against the render's (--stats-json), and their RMSE against a
# 4096-sample render (made once, an hour on 2 cores; kept in the output folder),
# with `nffrt diff --metric rmse` on the linear values (PFM) and on the pictures as
# shown (PNG, gamma 2.2; the reference's PNG made from its PFM by pfm-to-png.py,
# as nffrt would write it).
#
#   scripts/bench-denoise.sh [OUT_DIR]       (default target/bench-denoise)
#
# Needs the release binary and Open Image Denoise (pip install pyoidn, or
# NFFRT_OIDN), and numpy for pfm-to-png.py ($PYTHON, default python3).
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-target/bench-denoise}"
mkdir -p "$out"
nffrt="$PWD/target/release/nffrt"
python="${PYTHON:-python3}"
scene=(examples/cornell.p3f --width 512 --height 512)

if [ ! -f "$out/ref.pfm" ]; then
    echo "== the 4096-sample reference (long)"
    "$nffrt" render "${scene[@]}" --spp 4096 -q -o "$out/ref.pfm"
fi
"$python" scripts/pfm-to-png.py "$out/ref.pfm" "$out/ref.png" gamma2.2

for run in 1 2 3; do
    "$nffrt" render "${scene[@]}" --spp 16 -q -o "$out/noisy.pfm" --stats-json "$out/noisy-$run.json"
    "$nffrt" render "${scene[@]}" --spp 16 --denoise -q -o "$out/high.pfm" --stats-json "$out/high-$run.json"
    "$nffrt" render "${scene[@]}" --spp 16 --denoise=fast -q -o "$out/fast.pfm" --stats-json "$out/fast-$run.json"
done
for kind in noisy high fast; do
    flags=()
    [ "$kind" = high ] && flags=(--denoise)
    [ "$kind" = fast ] && flags=(--denoise=fast)
    "$nffrt" render "${scene[@]}" --spp 16 "${flags[@]}" -q -o "$out/$kind.png"
done

echo "== RMSE against the 4096-sample render"
for kind in noisy high fast; do
    "$nffrt" diff "$out/$kind.pfm" "$out/ref.pfm" --metric rmse
    "$nffrt" diff "$out/$kind.png" "$out/ref.png" --metric rmse
done
echo "== seconds: medians of 3 (render, AOV pass, filter)"
for kind in noisy high fast; do
    "$python" - "$out" "$kind" <<'PY'
import json, statistics, sys
out, kind = sys.argv[1], sys.argv[2]
runs = [json.load(open(f"{out}/{kind}-{r}.json")) for r in (1, 2, 3)]
med = lambda key: statistics.median(r.get(key, 0.0) for r in runs)
render, aov, filt = med("render_s"), med("aov_s"), med("denoise_s")
print(f"{kind:6} render {render:.3f}  aov {aov:.3f}  filter {filt:.3f}  ({(aov + filt) / render:.0%} of the render)")
PY
done

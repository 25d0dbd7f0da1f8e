#!/usr/bin/env bash
# nffrt's path tracer against Mitsuba 3 on examples/cornell.p3f and glass-mirror.p3f:
# channel means, 8x8 block z-scores against both sides' sampling error, and a
# side-by-side PNG per scene in target/mitsuba-compare/ (scripts/compare-mitsuba.py).
#
#   scripts/compare-mitsuba.sh                         2048 spp per side, 256x256
#   scripts/compare-mitsuba.sh --spp 256 --size 128    a quick look
#   scripts/compare-mitsuba.sh --variant scalar_rgb    without LLVM
# Environment: see scripts/mitsuba-env.sh (MITSUBA_PY, NFFRT, DRJIT_LIBLLVM_PATH).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/mitsuba-env.sh
variant=()
[ -n "${DRJIT_LIBLLVM_PATH:-}" ] || variant=(--variant scalar_rgb)
exec "$MITSUBA_PY" scripts/compare-mitsuba.py --nffrt "$NFFRT" "${variant[@]}" "$@"

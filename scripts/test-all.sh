#!/usr/bin/env bash
# Every test, Rust and Python: the README's test command (.ci/run calls it too).
#
#   1. cargo test --profile test-release (the library, the command line, the docs'
#      examples; release speed without fat LTO, see Cargo.toml);
#   2. the Python module built from pyproject.toml (`pip install .`, a wheel made by
#      maturin) into a virtual environment with numpy, dask[distributed], pytest and
#      flip-evaluator (NVIDIA's FLIP, the peer of `nffrt diff`, python/tests/test_diff.py):
#      $NFFRT_VENV, by default target/py-venv, made on first use (delete it, or
#      point NFFRT_VENV at a new folder, for a fresh one);
#   3. pytest python/tests against that module and the binary of step 1;
#   4. Open Image Denoise for the denoising tests, Rust and Python alike: the
#      library pip's pyoidn puts in that environment, when it is there (.ci/run
#      installs it; `$venv/bin/pip install pyoidn` does it here), through
#      NFFRT_OIDN unless that is set already; without it those tests skip, saying so;
#   5. a summary of the checks skipped, grouped by reason: every test that skips
#      one (most for want of ../shared) appends `SKIPPED: <test>: <reason>` to
#      target/skipped-tests.log (tests/common/skip.rs, python/tests/conftest.py).
#
# Extra arguments go to pytest (e.g. `scripts/test-all.sh -k dask`).
# NFFRT_SHARED=/nowhere runs the tests as a fresh clone without ../shared would;
# NFFRT_REQUIRE_SHARED=1 (set by .ci/run) makes every ../shared skip a failure.
set -euo pipefail
cd "$(dirname "$0")/.."

mkdir -p target
export NFFRT_SKIP_LOG="$PWD/target/skipped-tests.log"
: >"$NFFRT_SKIP_LOG"

# The skipped checks by reason, most frequent first; printed however the run ends.
summary() {
    local n
    n=$(wc -l <"$NFFRT_SKIP_LOG")
    echo "== skipped: $n"
    if [ "$n" -gt 0 ]; then
        sed -E 's/^SKIPPED: [^ ]+: //' "$NFFRT_SKIP_LOG" | sort | uniq -c | sort -rn
        echo "   (each test: $NFFRT_SKIP_LOG)"
    fi
}
trap summary EXIT

venv="${NFFRT_VENV:-target/py-venv}"
# Open Image Denoise from the tests' environment, if pip's pyoidn is in it.
if [ -z "${NFFRT_OIDN:-}" ]; then
    for lib in "$venv"/lib/python3*/site-packages/pyoidn/oidn/lib; do
        if [ -d "$lib" ]; then
            case "$lib" in /*) ;; *) lib="$PWD/$lib" ;; esac
            export NFFRT_OIDN="$lib"
        fi
    done
fi
echo "== Open Image Denoise: ${NFFRT_OIDN:-not installed (the denoising tests skip; $venv/bin/pip install pyoidn)}"

echo "== Rust: cargo test --profile test-release"
cargo test --profile test-release
cargo build --profile test-release --bin nffrt

echo "== Python: build and install the module into $venv"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
    "$venv/bin/pip" install -q --upgrade pip
fi
"$venv/bin/pip" install -q "maturin>=1.9.4,<2" numpy "dask[distributed]" pytest flip-evaluator
# The wheel pip builds with maturin from pyproject.toml (the same command a user
# runs), reinstalled every time so the tests never see a stale module.
"$venv/bin/pip" install -q --force-reinstall --no-deps .

# The tests compare the module (release profile, fat LTO) with this binary
# (test-release): floating point is the same under both, and the tests check it.
# -rs: each skipped test with its reason.
echo "== Python: pytest python/tests"
NFFRT_BIN="$PWD/target/test-release/nffrt" "$venv/bin/python" -m pytest -q -rs python/tests "$@"

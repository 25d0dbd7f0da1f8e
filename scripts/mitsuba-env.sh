# Sourced by compare-mitsuba.sh and bench-mitsuba.sh: a Python with Mitsuba 3 (a venv
# in target/mitsuba-venv, made on first use), Dr.Jit's LLVM for the llvm_* variants,
# and the nffrt binary to measure.
#
#   MITSUBA_PY=/path/to/python   a Python that already has mitsuba, numpy and pillow
#   NFFRT=/path/to/nffrt         the binary (default target/release/nffrt, built if absent)
#   DRJIT_LIBLLVM_PATH=...       libLLVM for llvm_ad_rgb (default: Debian's libLLVM-19
#                                if installed: apt-get install -y libllvm19)
venv=target/mitsuba-venv
if [ -z "${MITSUBA_PY:-}" ]; then
    if [ ! -x "$venv/bin/python" ]; then
        python3 -m venv "$venv"
        "$venv/bin/pip" install -q mitsuba numpy pillow
    fi
    MITSUBA_PY=$venv/bin/python
fi
if [ -z "${DRJIT_LIBLLVM_PATH:-}" ] && [ -e /usr/lib/x86_64-linux-gnu/libLLVM-19.so ]; then
    export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so
fi
NFFRT=${NFFRT:-target/release/nffrt}
[ -x "$NFFRT" ] || cargo build --release -q

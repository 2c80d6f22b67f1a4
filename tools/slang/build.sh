#!/usr/bin/env bash
# Builds slang_check against the Slang compiler shipped in the PyPI wheel
# `slangpy` (installed with pip if missing).
#
# usage: tools/slang/build.sh [OUT_DIR]      (default: tools/slang/build)
# Prints the absolute path of the built binary on its last stdout line.
#
# Env: PYTHON (default python3), CXX (default g++), SLANGPY_SPEC.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
out_dir="${1:-$here/build}"
python="${PYTHON:-python3}"
cxx="${CXX:-g++}"
# Pinned: the version the tool was written and tested against.
slangpy_spec="${SLANGPY_SPEC:-slangpy==0.43.1}"

slangpy_dir() {
    # find_spec locates the package without importing it (the compiler library is
    # all that is needed, not slangpy's Python dependencies).
    "$python" -c 'import importlib.util, os; print(os.path.dirname(importlib.util.find_spec("slangpy").origin))' 2>/dev/null
}

if ! sdk="$(slangpy_dir)" || [ -z "$sdk" ]; then
    echo "slang/build.sh: installing $slangpy_spec with pip" >&2
    "$python" -m pip install --quiet --no-deps "$slangpy_spec" >&2
    sdk="$(slangpy_dir)"
fi

# The wheel ships only the versioned library (libslang-compiler.so.0.<ver>),
# whose SONAME is that same name; link it by full path and add an rpath so
# the binary finds it (and the glslang / glsl-module plugins beside it).
lib="$(ls "$sdk"/libslang-compiler.so.* 2>/dev/null | head -n 1 || true)"
if [ -z "$lib" ] || [ ! -f "$sdk/include/slang.h" ]; then
    echo "slang/build.sh: no libslang-compiler.so.* / include/slang.h in $sdk" >&2
    exit 1
fi

mkdir -p "$out_dir"
out_dir="$(cd "$out_dir" && pwd)"
"$cxx" -std=c++17 -O1 -Wall -Wextra \
    -I"$sdk/include" \
    "$here/slang_check.cpp" \
    -o "$out_dir/slang_check" \
    "$lib" -Wl,-rpath,"$sdk"
echo "$out_dir/slang_check"

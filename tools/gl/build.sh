#!/usr/bin/env bash
# Builds gl_link (EGL surfaceless + OpenGL 4.5 core, through glvnd).
#
# usage: tools/gl/build.sh [OUT_DIR]      (default: tools/gl/build)
# Prints the absolute path of the built binary on its last stdout line.
#
# Debian packages: libegl-dev libopengl-dev libgl-dev (headers + link libs)
# and libegl-mesa0 libgl1-mesa-dri (Mesa's EGL and its llvmpipe driver).
# Missing ones are installed with apt-get when running as root.
# Env: CC (default gcc).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
out_dir="${1:-$here/build}"
cc="${CC:-gcc}"
packages=(libegl-dev libopengl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri)

missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ]; then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
        echo "gl/build.sh: installing ${missing[*]}" >&2
        apt-get install -y --no-install-recommends "${missing[@]}" >&2 ||
            { apt-get update >&2 && apt-get install -y --no-install-recommends "${missing[@]}" >&2; }
    else
        echo "gl/build.sh: missing Debian packages: ${missing[*]}" >&2
        exit 1
    fi
fi

mkdir -p "$out_dir"
out_dir="$(cd "$out_dir" && pwd)"
"$cc" -std=c11 -O1 -Wall -Wextra "$here/gl_link.c" -o "$out_dir/gl_link" -lEGL -lOpenGL
echo "$out_dir/gl_link"

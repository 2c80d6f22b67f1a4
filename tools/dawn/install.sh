#!/usr/bin/env bash
# Installs dawn_check's only dependency, the npm package `webgpu` (Dawn's
# node bindings, prebuilt dawn.node inside the package), pinned by
# package-lock.json, into tools/dawn/node_modules.
#
# usage: tools/dawn/install.sh
# Needs node >= 18 and npm.  `--ignore-scripts`: the package's only install
# script strips a macOS quarantine attribute and does nothing on Linux.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")"
npm ci --ignore-scripts --no-audit --no-fund >&2
echo "$(pwd)/dawn_check.mjs"

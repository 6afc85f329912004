#!/usr/bin/env bash
# Vendors three.js (the WebGL library of `crestline view`) from the npm registry:
# its self-contained ES module build and its licence, into crates/crestline/src/view/,
# where the viewer embeds them in every HTML file it writes. Needs npm.
#
#     tools/vendor_three.sh [VERSION]
#
# 0.170.0 is the last release whose build/three.module.min.js imports nothing (later
# ones import ./three.core.js).
set -euo pipefail
version="${1:-0.170.0}"
here="$(cd "$(dirname "$0")/.." && pwd)"
target="$here/crates/crestline/src/view"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
(cd "$work" && npm pack --silent "three@$version" >/dev/null && tar xzf "three-$version.tgz")
if grep -q '</script' "$work/package/build/three.module.min.js"; then
    echo "three@$version contains '</script' and cannot be embedded in a script element" >&2
    exit 1
fi
cp "$work/package/build/three.module.min.js" "$target/three.module.min.js"
cp "$work/package/LICENSE" "$target/three-LICENSE"
echo "three@$version -> $target"
